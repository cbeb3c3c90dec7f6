#pragma once

#include <map>
#include <optional>
#include <string>

namespace softpack::bodies
{

/// The paper's plane-strain effective Lamé parameters (Sec. III.B): matching
/// the small-strain energy of the incompressible 3D cylinder gives
/// \f$\tilde\mu = \mu\f$, \f$\tilde\lambda = 2\mu\f$ (\f$\tilde\nu = 1/3\f$).
/// The keys are the constants of forms/materials/neo_hookean.py, and the
/// default of lame_lambda is the one that file declares (2 mu), through
/// forms/material_defaults.h: no copy here.
/// @param[in] shear_modulus Shear modulus mu (Pa)
/// @param[in] lame_lambda Override of the effective first Lamé parameter (Pa)
/// @return {"shear_modulus": mu, "lame_lambda": lame_lambda or its default}
/// @throws std::invalid_argument if mu <= 0 or lambda <= -mu (unstable)
std::map<std::string, double>
plane_strain_parameters(double shear_modulus,
                        std::optional<double> lame_lambda = std::nullopt);

/// Poisson's ratio \f$\nu = \lambda / (2(\lambda + \mu))\f$
double poisson_ratio(double shear_modulus, double lame_lambda);

} // namespace softpack::bodies
