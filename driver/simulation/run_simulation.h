#pragma once

#include <bodies/BodySet.h>
#include <io/driver_config.h>
#include <mpi.h>
#include <string>
#include <vector>

/// The whole run: config -> bodies -> time loop -> raw files and fields.
namespace softpack::simulation
{

/// How a run ended.
struct RunSummary
{
  long steps = 0;
  double seconds = 0;
  /// "packing_fraction", "max_time" or "steps"
  std::string reason;
};

/// Run the time loop described by a driver config until a stop criterion
/// holds, writing raw/setup.json before the first step and the outputs
/// docs/driver_io.md describes, with a progress line per output step on
/// stdout. A 3D scene (scene.model.dimension = 3) runs the same loop on
/// its box of six planes (box_3d.h), once check_3d_run has refused what
/// 3D lacks.
/// @param[in] comm The communicator of the run's mesh and files
/// @param[in] initial_only Write the initial state (raw/setup.json, the
/// first output row, the state and the fields at the start) and stop
/// before the first step (reason "initial_only")
RunSummary run_simulation(MPI_Comm comm, const io::DriverConfig& config,
                          bool quiet = false, bool initial_only = false);

/// The bodies of driver.json's mesh and materials, of the scene's
/// dimension (a collective: rank 0 alone reads the mesh and sends its
/// arrays to the others, parallel::broadcast_geometry); errors in a
/// material name driver.json and the key (material.parameters.KEY,
/// materials[0].parameters.KEY).
bodies::BodySet make_bodies(MPI_Comm comm, const io::DriverConfig& config);

/// The box's area (x_right - x_left) (y_top - y_bottom) from the four box
/// walls' current positions (3D: the area of its base).
double box_area(const std::vector<dynamics::Wall>& walls);

} // namespace softpack::simulation
