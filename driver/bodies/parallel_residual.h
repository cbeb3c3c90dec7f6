#pragma once

#include "BodySet.h"
#include <dolfinx/fem/Form.h>
#include <dolfinx/fem/Function.h>
#include <span>
#include <vector>

namespace softpack::bodies
{

/// Assembly of a vector form (the internal force) body by body on all
/// cores.
///
/// dolfinx's assemble_vector runs on one core and packs every coefficient
/// into a separate array first; this loop calls the same FFCx kernel cell
/// by cell, reads the displacement straight from its array, and gives
/// whole bodies to the threads (bodies share no node, so no two threads
/// write the same entry). It handles the forms the materials produce: one
/// cell integral over all cells, the displacement as the only coefficient,
/// an element without DOF transformations (Lagrange). For anything else
/// supported() is false and the caller uses dolfinx's assembler.
class ParallelResidual
{
public:
  /// @param[in] L The linear form (its test space must be u's space)
  /// @param[in] u The only coefficient of L
  /// @param[in] bodies Cells of each body
  ParallelResidual(const dolfinx::fem::Form<double>& L,
                   std::shared_ptr<const dolfinx::fem::Function<double>> u,
                   const std::vector<Body>& bodies);

  /// Whether L is of the kind this loop handles
  bool supported() const { return _supported; }

  /// b += L (b holds every DOF of the mesh)
  /// @param[in] bodies The same cells per body as at construction
  void assemble(std::span<double> b, const std::vector<Body>& bodies) const;

private:
  const dolfinx::fem::Form<double>& _L;
  std::shared_ptr<const dolfinx::fem::Function<double>> _u;
  bool _supported = false;
};

} // namespace softpack::bodies
