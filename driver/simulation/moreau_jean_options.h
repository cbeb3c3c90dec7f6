#pragma once

#include <dynamics/moreau_jean.h>
#include <softpack/parameters.h>

namespace softpack::simulation
{

/// The time stepper's options from the generated parameter structs: the
/// one place where schema names meet dynamics::MoreauJeanOptions (to be
/// removed once MoreauJeanOptions holds the generated structs itself).
/// @param[in] p The run's parameters (time, contact, damping)
/// @param[in] velocity_scale Velocity scale of the Newton test (m/s)
dynamics::MoreauJeanOptions moreau_jean_options(const parameters::Parameters& p,
                                                double velocity_scale);

} // namespace softpack::simulation
