#include "material_parameters.h"
#include <stdexcept>

namespace softpack::bodies
{

std::map<std::string, double>
plane_strain_parameters(double shear_modulus, std::optional<double> lame_lambda)
{
  const double mu = shear_modulus;
  if (!(mu > 0))
    throw std::invalid_argument("shear_modulus must be positive");
  const double lambda = lame_lambda.value_or(2 * mu);
  // In 2D the bulk modulus is lambda + mu; it must stay positive.
  if (!(lambda > -mu))
    throw std::invalid_argument("lame_lambda must exceed -shear_modulus "
                                "(positive 2D bulk modulus)");
  return {{"shear_modulus", mu}, {"lame_lambda", lambda}};
}

double poisson_ratio(double shear_modulus, double lame_lambda)
{
  return lame_lambda / (2 * (lame_lambda + shear_modulus));
}

} // namespace softpack::bodies
