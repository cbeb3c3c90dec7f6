#pragma once

#include <map>
#include <optional>
#include <string>

namespace softpack::bodies
{

/// The paper's plane-strain effective Lamé parameters (Sec. III.B): matching
/// the small-strain energy of the incompressible 3D cylinder gives
/// \f$\tilde\mu = \mu\f$, \f$\tilde\lambda = 2\mu\f$ (\f$\tilde\nu = 1/3\f$).
/// @param[in] mu Shear modulus (Pa)
/// @param[in] lmbda Override of the effective first Lamé parameter (Pa)
/// @return {"mu": mu, "lmbda": lmbda or 2 mu}
/// @throws std::invalid_argument if mu <= 0 or lmbda <= -mu (unstable)
std::map<std::string, double>
plane_strain_parameters(double mu, std::optional<double> lmbda = std::nullopt);

/// Poisson's ratio \f$\nu = \lambda / (2(\lambda + \mu))\f$
double poisson_ratio(double mu, double lmbda);

} // namespace softpack::bodies
