#include "moreau_jean_options.h"

namespace softpack::simulation
{

dynamics::MoreauJeanOptions moreau_jean_options(const parameters::Parameters& p,
                                                double velocity_scale)
{
  dynamics::MoreauJeanOptions o;
  o.time_step = p.time.time_step;
  o.theta = p.time.theta;
  o.lumped_mass = p.time.mass == "lumped";
  o.newton_tolerance = p.time.newton_tolerance;
  o.max_newton_iterations = p.time.newton_max_iterations;
  o.full_newton = p.time.full_newton;
  o.tangent_reuse_steps = p.time.tangent_reuse_steps;
  o.refactor_above_iterations = p.time.refactor_above_iterations;
  o.velocity_scale = velocity_scale;
  o.alpha = p.damping.alpha;
  o.beta = p.damping.beta;
  o.friction = p.contact.friction;
  o.detection.alert_distance = p.contact.alert_distance;
  o.detection.max_penetration = p.contact.max_penetration;
  o.delassus_drop_tolerance = p.contact.delassus_drop_tolerance;
  o.nlgs.tolerance = p.contact.nlgs_tolerance;
  o.nlgs.max_sweeps = p.contact.nlgs_max_sweeps;
  o.nlgs.relaxation = p.contact.nlgs_relaxation;
  return o;
}

} // namespace softpack::simulation
