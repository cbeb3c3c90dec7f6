// softpack-simulate DRIVER_JSON: run one simulation described by a resolved
// driver.json (written by `./softpack run`, see docs/contract.md and
// docs/driver_io.md).
#include "threads.h"
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <dolfinx/common/log.h>
#include <exception>
#include <io/driver_config.h>
#include <io/state_file.h>
#include <mpi.h>
#include <simulation/run_simulation.h>
#include <stdexcept>

namespace
{
/// A failure on one rank of several: its message, then every rank stops
/// (the others may wait in a collective forever otherwise); rank 0 never
/// reaches raw/done.json, so the run does not look complete.
[[noreturn]] void abort_all(const char* what)
{
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  std::fprintf(stderr, "softpack-simulate: rank %d of %d: %s\n", rank, size,
               what);
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, 1);
  std::exit(1); // MPI_Abort does not return
}

int world_size()
{
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}
/// `--state-info FILE`: {"step": ..., "time": ..., "dofs": ..., "walls":
/// ..., "dimension": ...} on stdout.
int print_state_info(const std::string& path)
{
  try
  {
    const softpack::dynamics::SchemeState s = softpack::io::read_state(path);
    std::printf("{\"step\": %ld, \"time\": %.17g, \"dofs\": %zu, "
                "\"walls\": %zu, \"dimension\": %d}\n",
                s.steps, s.time, s.u.size(),
                s.dim == 3 ? s.wall_points_3d.size() : s.wall_points.size(),
                s.dim);
    return 0;
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "softpack-simulate: %s\n", e.what());
    return 1;
  }
}
} // namespace

int main(int argc, char** argv)
{
  // Before anything else: OpenMP reads its wait policy when loaded.
  softpack::apps::ensure_passive_waiting(argv);
  CLI::App app{"Nonsmooth contact dynamics of soft disks (softpack)"};
  std::string config_path;
  bool quiet = false;
  std::string state_path;
  auto* config_option = app.add_option("config", config_path, "driver.json");
  auto* info_option = app.add_option(
      "--state-info", state_path,
      "print the step and time of a state file (raw/state.bin) as JSON and "
      "exit: the layout is the driver's own, nobody else parses it");
  config_option->excludes(info_option);
  info_option->excludes(config_option);
  app.add_flag("--quiet", quiet, "no progress lines");
  bool initial_only = false;
  app.add_flag("--initial-only", initial_only,
               "read and check driver.json and the bodies, write the initial "
               "state (raw/setup.json, the first output row and state, the "
               "fields at the start) and stop before the first step");
  int threads = 0;
  app.add_option("--threads", threads,
                 "OpenMP threads (default 0: one per core this process may "
                 "use)");
  CLI11_PARSE(app, argc, argv);
  if (!state_path.empty())
    return print_state_info(state_path);
  if (config_path.empty())
  {
    std::fprintf(stderr, "softpack-simulate: driver.json is required\n");
    return 2;
  }

  MPI_Init(&argc, &argv);
  // dolfinx logs at INFO level unless initialised (with no arguments: WARNING)
  char* no_args[] = {argv[0]};
  dolfinx::init_logging(1, no_args);
  int status = 0;
  try
  {
    softpack::apps::set_thread_count(threads);
    const softpack::io::DriverConfig config =
        softpack::io::read_driver_config(config_path);
    const auto summary = softpack::simulation::run_simulation(
        MPI_COMM_WORLD, config, quiet, initial_only);
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (rank == 0)
      std::printf("done: %ld steps in %.1f s (%s)\n", summary.steps,
                  summary.seconds, summary.reason.c_str());
  }
  catch (const std::exception& e)
  {
    if (world_size() > 1)
      abort_all(e.what());
    std::fprintf(stderr, "softpack-simulate: %s\n", e.what());
    status = 1;
  }
  MPI_Finalize();
  return status;
}
