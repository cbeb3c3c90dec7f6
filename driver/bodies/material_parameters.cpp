#include "material_parameters.h"
#include <material_defaults.h>
#include <stdexcept>

namespace softpack::bodies
{

std::map<std::string, double>
plane_strain_parameters(double shear_modulus, std::optional<double> lame_lambda)
{
  const double mu = shear_modulus;
  if (!(mu > 0))
    throw std::invalid_argument("shear_modulus must be positive");
  forms::ParameterValues given = {{"shear_modulus", mu}};
  if (lame_lambda)
    given["lame_lambda"] = *lame_lambda;
  // lame_lambda's default is the one forms/materials/neo_hookean.py declares
  std::map<std::string, double> p = forms::with_defaults("neo_hookean", given);
  // In 2D the bulk modulus is lambda + mu; it must stay positive.
  if (!(p.at("lame_lambda") > -mu))
    throw std::invalid_argument("lame_lambda must exceed -shear_modulus "
                                "(positive 2D bulk modulus)");
  return p;
}

double poisson_ratio(double shear_modulus, double lame_lambda)
{
  return lame_lambda / (2 * (lame_lambda + shear_modulus));
}

} // namespace softpack::bodies
