#pragma once

#include <io/driver_config.h>
#include <string>

/// The whole run: config -> bodies -> time loop -> raw files and fields.
namespace softpack::simulation
{

/// How a run ended.
struct RunSummary
{
  long steps = 0;
  double seconds = 0;
  /// "packing_fraction" or "max_time"
  std::string reason;
};

/// Run the time loop described by a driver config until a stop criterion
/// holds, writing outputs as docs/driver_io.md describes and a progress
/// line per output step on stdout.
RunSummary run_simulation(const io::DriverConfig& config, bool quiet = false);

} // namespace softpack::simulation
