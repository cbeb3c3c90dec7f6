#include "material_parameters.h"
#include <stdexcept>

namespace softpack::bodies
{

std::map<std::string, double>
plane_strain_parameters(double mu, std::optional<double> lmbda)
{
  if (!(mu > 0))
    throw std::invalid_argument("shear modulus mu must be positive");
  const double l = lmbda.value_or(2 * mu);
  // In 2D the bulk modulus is lmbda + mu; it must stay positive.
  if (!(l > -mu))
    throw std::invalid_argument("lmbda must exceed -mu (positive 2D bulk "
                                "modulus)");
  return {{"mu", mu}, {"lmbda", l}};
}

double poisson_ratio(double mu, double lmbda)
{
  return lmbda / (2 * (lmbda + mu));
}

} // namespace softpack::bodies
