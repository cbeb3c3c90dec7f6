#pragma once

#include <io/driver_config.h>
#include <mpi.h>
#include <string>

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
/// stdout.
/// @param[in] comm The communicator of the run's mesh and files (one rank
/// for now; bodies are not distributed yet)
RunSummary run_simulation(MPI_Comm comm, const io::DriverConfig& config,
                          bool quiet = false);

} // namespace softpack::simulation
