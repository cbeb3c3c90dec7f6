// softpack-simulate DRIVER_JSON: run one simulation described by a resolved
// driver.json (written by `./softpack run`, see docs/contract.md and
// docs/driver_io.md).
#include "threads.h"
#include <CLI/CLI.hpp>
#include <cstdio>
#include <dolfinx/common/log.h>
#include <exception>
#include <io/driver_config.h>
#include <io/state_file.h>
#include <mpi.h>
#include <simulation/run_simulation.h>
#include <stdexcept>

namespace
{
/// The run's communicator. Bodies are not distributed yet (a later issue):
/// until they are, a run on several ranks would only repeat the same work.
MPI_Comm run_communicator()
{
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size > 1)
    throw std::runtime_error(
        "runs on " + std::to_string(size) +
        " MPI ranks are not supported yet (bodies are not distributed): "
        "run on one rank, OpenMP uses the cores");
  return MPI_COMM_WORLD;
}
/// `--state-info FILE`: {"step": ..., "time": ..., "dofs": ...} on stdout.
int print_state_info(const std::string& path)
{
  try
  {
    const softpack::dynamics::SchemeState s = softpack::io::read_state(path);
    std::printf("{\"step\": %ld, \"time\": %.17g, \"dofs\": %zu, "
                "\"walls\": %zu}\n",
                s.steps, s.time, s.u.size(), s.wall_points.size());
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
    const MPI_Comm comm = run_communicator();
    const softpack::io::DriverConfig config =
        softpack::io::read_driver_config(config_path);
    const auto summary =
        softpack::simulation::run_simulation(comm, config, quiet);
    std::printf("done: %ld steps in %.1f s (%s)\n", summary.steps,
                summary.seconds, summary.reason.c_str());
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "softpack-simulate: %s\n", e.what());
    status = 1;
  }
  MPI_Finalize();
  return status;
}
