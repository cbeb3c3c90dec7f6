#pragma once

#include "run_simulation.h"

/// A 3D scene's way through the driver until the 3D time step exists.
namespace softpack::simulation
{

/// What a 3D run asked to step is told (and its exit status is nonzero).
inline constexpr const char* no_3d_stepping = "3D time stepping: not yet built";

/// A 3D scene (scene.model.dimension = 3): read its tetrahedral bodies
/// into a BodySet of dimension 3 (their materials' 3D forms), check them,
/// write raw/setup.json (per body its volume, node and tetrahedron
/// counts) and, with output.fields, the fields at t = 0 (fields.xdmf and
/// fields.h5 of tetrahedra: displacement, Psi, particle), and print the
/// volume fraction Phi in the box. Then, unless `initial_only`, refuse to
/// advance it (no_3d_stepping): the Moreau-Jean step, the compliance and
/// the walls are 2D so far (docs/bodies_3d.md).
/// @param[in] comm One rank only for now
/// @return 0 steps, reason "initial_only"
/// @throws std::runtime_error naming driver.json: more than one rank, a
/// mesh not of tetrahedra, a law without 3D forms; no_3d_stepping when
/// not initial_only (after the initial state is written)
RunSummary run_initial_3d(MPI_Comm comm, const io::DriverConfig& config,
                          bool quiet, bool initial_only);

} // namespace softpack::simulation
