#pragma once

#include <span>
#include <string>
#include <string_view>
#include <ufcx.h>
#include <vector>

/// Materials compiled from forms/materials/*.py, looked up by name.
namespace softpack::forms
{

/// The compiled forms of one hyperelastic material (plane strain, P1).
struct MaterialForms
{
  /// File stem of the UFL file, e.g. "neo_hookean"
  const char* name;
  /// Total strain energy, \f$\int \Psi\,dx\f$ (rank 0)
  ufcx_form* energy;
  /// Internal force, \f$\partial E/\partial u\f$ (rank 1)
  ufcx_form* residual;
  /// Tangent stiffness, \f$\partial^2 E/\partial u^2\f$ (rank 2)
  ufcx_form* tangent;
  /// Cell integrals of the Cauchy stress, \f$\int P F^T dX\f$ (= \f$\int
  /// \sigma\,da\f$), tested against a DG0 4-vector: components xx, yy, xy,
  /// yx (rank 1; derived from `energy` by forms/cauchy_integral.py)
  ufcx_form* cauchy_integral;
  /// The displacement space ("v", "u", "du") of this material's forms
  ufcx_function_space* (*function_space)(const char*);
};

/// All registered materials (generated table; order of file names).
std::span<const MaterialForms> material_table();

/// Names of all registered materials.
std::vector<std::string> material_names();

/// Find a material by name.
/// @throws std::invalid_argument naming the allowed materials
const MaterialForms& find_material(std::string_view name);

/// Names of the constants (material parameters) a material's residual uses,
/// in the order the compiled form expects them.
std::vector<std::string> material_parameters(const MaterialForms& m);

} // namespace softpack::forms
