#pragma once

#include "BodySet.h"
#include <array>
#include <map>
#include <material_registry.h>
#include <string>
#include <vector>

/// The integral of each body's own Cauchy stress, for the assembly's mean
/// stress (issue 12 item 3): sigma_FE = (1/A_box) sum over bodies of
/// \f$\int_{b} \sigma\,da\f$.
namespace softpack::bodies
{

/// \f$\int \sigma\,da = \int P F^T dX\f$ over one deformed body (plane
/// strain, per unit length along z: N), components xx, yy, xy, yx, tension
/// positive.
using CauchyIntegral = std::array<double, 4>;

/// Each local body's Cauchy integral from the internal force
/// (BodySet::local_bodies; the others' are zero: a distributed run's share
/// reads its own bodies' interiors only).
///
/// For P1 elements the current position x = X + u is in the displacement
/// space, so for A = e_i (x) e_j the nodal sum
/// \f$\sum_n f^{int}_{n,i} x_{n,j} = \int P : \nabla(A x)\,dX
/// = \int P : (A F)\,dX = (\int P F^T dX)_{ij}\f$ exactly (the same
/// quadrature as the residual). One internal-force evaluation: valid for
/// every law, whatever law each body has. A body that moves rigidly (a
/// rigid material) has no internal force and gets zero: its share of the
/// assembly's stress is then only in the wall and Love-Weber estimates.
std::vector<CauchyIntegral> cauchy_integrals(const BodySet& bodies);

/// \f$\int \sigma\,dv = \int P F^T dX\f$ over one deformed 3D body (N m),
/// components xx, yy, xy, yx (cauchy_integrals' four), then zz, xz, zx,
/// yz, zy, tension positive.
using CauchyIntegral3D = std::array<double, 9>;

/// cauchy_integrals for 3D bodies (the same nodal sum over three
/// components).
/// @throws std::invalid_argument if the bodies are not 3D
std::vector<CauchyIntegral3D> cauchy_integrals_3d(const BodySet& bodies);

/// Each body's Cauchy integral from its law's compiled `cauchy_integral`
/// form (forms/cauchy_integral.py: P F^T from the derivative of the law's
/// energy), evaluated cell by cell and summed by body. An independent
/// route to cauchy_integrals(), used to check it.
class CauchyIntegralForm
{
public:
  /// @param[in] bodies The bodies (mesh, displacement, cells of each body)
  /// @param[in] law The compiled material of every body
  /// @param[in] parameters A value for each constant of the law's form
  /// @throws std::invalid_argument if a constant is missing, or the form
  /// is not one cell integral over P1 triangles
  CauchyIntegralForm(const BodySet& bodies, const forms::MaterialForms& law,
                     const std::map<std::string, double>& parameters);

  /// The integral of each body, at the bodies' current displacement
  std::vector<CauchyIntegral> evaluate() const;

private:
  const BodySet& _bodies;
  ufcx_tabulate_tensor_float64* _kernel;
  std::vector<double> _constants;
};

} // namespace softpack::bodies
