#pragma once

#include <dynamics/moreau_jean.h>

namespace softpack::test
{

/// Time-stepping options for small checks against exact properties: theta
/// = 1/2 (no numerical dissipation), full Newton to a tight tolerance,
/// plain Gauss–Seidel to 1e-8 with every Delassus block kept, no damping,
/// detection distances for centimetre disks, and fixed steps. Tests change what
/// they check from there; the production settings are the schema's defaults.
/// @param[in] time_step h (s)
/// @param[in] velocity_scale Velocity scale of the Newton test (m/s)
inline dynamics::MoreauJeanOptions exact_options(double time_step,
                                                 double velocity_scale)
{
  dynamics::MoreauJeanOptions o;
  o.time.time_step = time_step;
  o.time.max_step_factor = 1; // checks at a known step
  o.time.theta = 0.5;
  o.time.newton_tolerance = 1e-6;
  o.time.full_newton = true;
  o.time.tangent_reuse_steps = 1;
  o.contact.friction = 0.3;
  o.contact.alert_distance = 1e-4;
  o.contact.max_penetration = 1e-3;
  o.contact.nlgs_tolerance = 1e-8;
  o.contact.nlgs_max_sweeps = 10000;
  o.contact.nlgs_relaxation = 1.0;
  o.contact.delassus_drop_tolerance = 0;
  o.damping.alpha = 0;
  o.damping.beta = 0;
  o.velocity_scale = velocity_scale;
  return o;
}

} // namespace softpack::test
