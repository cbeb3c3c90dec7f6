#include "initial_3d.h"

#include <bodies/BodySet.h>
#include <chrono>
#include <cstdio>
#include <io/field_output.h>
#include <io/setup_file.h>
#include <numeric>
#include <stdexcept>

namespace softpack::simulation
{

RunSummary run_initial_3d(MPI_Comm comm, const io::DriverConfig& config,
                          bool quiet, bool initial_only)
{
  const auto start = std::chrono::steady_clock::now();
  const std::string file = config.file.string();
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  if (ranks != 1)
    throw std::runtime_error(file +
                             ": scene.model.dimension = 3: one MPI "
                             "rank only for now (" +
                             std::to_string(ranks) + " given)");
  if (config.cell)
    throw std::runtime_error(file + ": cell.enabled with "
                                    "scene.model.dimension = 3: a periodic "
                                    "cell is 2D only for now");
  const bodies::BodySet bodies = make_bodies(comm, config);
  const std::vector<double> volumes = bodies.body_current_area();
  const double volume = std::accumulate(volumes.begin(), volumes.end(), 0.0);
  io::write_setup(config.directory / "raw", io::setup_json(config, bodies));
  if (config.parameters.output.fields)
  {
    io::FieldOutput fields(config.directory, bodies);
    const std::vector<double> u(bodies.num_global_dofs(), 0.0);
    fields.write(u, bodies.cell_strain_energy(), 0.0);
  }
  if (!quiet)
  {
    std::printf("3D scene: %d bodies, %zu nodes, %zu tetrahedra, volume "
                "%.9g m^3",
                bodies.num_bodies(), bodies.num_global_dofs() / 3,
                bodies.cell_body().size(), volume);
    if (config.box)
      std::printf(", Phi = %.6f (volume fraction of the box)",
                  volume / (box_area(config.walls) * config.box_height));
    std::printf("\n");
    std::fflush(stdout);
  }
  if (!initial_only)
    throw std::runtime_error(
        std::string(no_3d_stepping) + ": " + file +
        " is a 3D scene (scene.model.dimension = 3); its bodies were read "
        "and checked and its initial state written (raw/setup.json, "
        "fields.xdmf at t = 0); --initial-only stops there with status 0");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  return {0, seconds, "initial_only"};
}

} // namespace softpack::simulation
