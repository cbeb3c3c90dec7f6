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
/// cell integral per form (one form per material, together over all
/// cells), the displacement as the only coefficient, an element without
/// DOF transformations (Lagrange). For anything else
/// supported() is false and the caller uses dolfinx's assembler.
class ParallelResidual
{
public:
  /// @param[in] L The linear forms, one per material in use (each with its
  /// test space u's space); together they cover every cell once
  /// @param[in] body_form Index in L of the form of each body
  /// @param[in] u The only coefficient of every L
  /// @param[in] bodies Cells of each body
  ParallelResidual(std::vector<const dolfinx::fem::Form<double>*> L,
                   std::vector<int> body_form,
                   std::shared_ptr<const dolfinx::fem::Function<double>> u,
                   const std::vector<Body>& bodies);

  /// Whether L is of the kind this loop handles
  bool supported() const { return _supported; }

  /// b += L (b holds every DOF of the mesh)
  /// @param[in] bodies The same cells per body as at construction
  /// @param[in] owned Assemble only the bodies flagged 1 (empty: all)
  void assemble(std::span<double> b, const std::vector<Body>& bodies,
                std::span<const char> owned = {}) const;

private:
  std::vector<const dolfinx::fem::Form<double>*> _L;
  std::vector<int> _body_form;
  std::shared_ptr<const dolfinx::fem::Function<double>> _u;
  bool _supported = false;
};

} // namespace softpack::bodies
