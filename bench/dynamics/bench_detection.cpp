// Contact detection cost against the number of bodies: disks on a jittered
// lattice (neighbours 0.2 mm apart, so every disk has contacts), the same
// mesh per disk; prints one JSON line per size and the fitted exponent of
// time ~ N^p. Each size is also timed as a periodic cell of the lattice's
// period (no walls; the edge rows touch their images), to give the images'
// extra cost (issue 38: under 10 %).
#include <algorithm>
#include <bodies/material_parameters.h>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <detection/detection.h>
#include <dolfinx/common/log.h>
#include <material_registry.h>
#include <mesh_fixtures.h>
#include <mpi.h>
#include <random>
#include <vector>
#include <walls/periodic_cell.h>

using namespace softpack;

namespace
{
struct Lattice
{
  bodies::BodySet bodies;
  std::vector<double> x;
  double period;
};

Lattice lattice(int side, int rings)
{
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> jitter(-5e-5, 5e-5);
  const double R = 0.01, pitch = 2 * R + 2e-4;
  std::vector<test::Triangulation> parts;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j)
      parts.push_back(test::disk(i * pitch + jitter(gen),
                                 j * pitch + jitter(gen), R, rings));
  bodies::BodySet bodies(test::bodies_mesh(parts),
                         forms::find_material("neo_hookean"),
                         bodies::plane_strain_parameters(0.15e6), 1180);
  std::vector<double> x(bodies.reference_coordinates().begin(),
                        bodies.reference_coordinates().end());
  return {std::move(bodies), std::move(x), side * pitch};
}

/// The median of 5 detections, walled (periodic = false) or in a cell of
/// the lattice's period; prints its JSON line.
double time_detection(const Lattice& l, int side, int rings, bool periodic)
{
  const double R = 0.01, L = l.period;
  const std::vector<dynamics::Wall> walls =
      periodic ? std::vector<dynamics::Wall>{}
               : dynamics::box_walls(-R - 1e-4, L - R + 1e-4, -R - 1e-4,
                                     L - R + 1e-4, 0);
  const dynamics::PeriodicCell cell =
      dynamics::PeriodicCell::moving({L, 0}, {0, L}, {0, 0}, {0, 0});
  dynamics::DetectionOptions options;
  options.alert_distance = 5e-4;
  std::vector<double> seconds;
  std::size_t contacts = 0;
  for (int repeat = 0; repeat < 5; ++repeat)
  {
    const auto t0 = std::chrono::steady_clock::now();
    contacts = dynamics::detect_contacts(l.bodies, l.x, walls, options,
                                         periodic ? &cell : nullptr)
                   .size();
    seconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
            .count());
  }
  std::sort(seconds.begin(), seconds.end());
  std::printf(
      "{\"bench\": \"%s\", \"bodies\": %d, \"boundary_nodes_per_body\": "
      "%d, \"contacts\": %zu, \"seconds\": %.6g}\n",
      periodic ? "detection_periodic" : "detection", side * side, 6 * rings,
      contacts, seconds[2]);
  std::fflush(stdout);
  return seconds[2];
}
} // namespace

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  char* no_args[] = {argv[0]};
  dolfinx::init_logging(1, no_args);
  const int rings = 10; // 60 boundary nodes, as a 20 mm disk at 1.065 mm
  std::vector<double> logn, logt;
  for (int side : {10, 20, 40})
  {
    const Lattice l = lattice(side, rings);
    const double t = time_detection(l, side, rings, false);
    time_detection(l, side, rings, true);
    logn.push_back(std::log(side * side));
    logt.push_back(std::log(t));
  }
  // Least-squares slope of log t against log N.
  const double n = logn.size();
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < logn.size(); ++i)
  {
    sx += logn[i];
    sy += logt[i];
    sxx += logn[i] * logn[i];
    sxy += logn[i] * logt[i];
  }
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  std::printf(
      "{\"bench\": \"detection_scaling\", \"bodies\": [100, 400, 1600], "
      "\"exponent\": %.3f}\n",
      slope);
  MPI_Finalize();
  return 0;
}
