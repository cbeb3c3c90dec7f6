// 3D contact detection cost: icospheres (R = 1 cm) on a jittered cubic
// lattice whose neighbours overlap by 0.1 mm, so every sphere has
// contacts. Prints one JSON line per run and the fitted exponents of
// time ~ N^p (1) against the number of spheres at a fixed mesh and (2)
// against the triangles per sphere at a fixed lattice: both near 1 for a
// linear broad phase (node against all triangles of the other body would
// give 2 in (2)).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <detection/detection_3d.h>
#include <random>
#include <surface_fixtures.h>
#include <vector>

using namespace softpack;

namespace
{
struct Lattice
{
  std::vector<dynamics::BoundarySurface> surfaces;
  std::vector<double> x;
};

Lattice lattice(int side, int level)
{
  const test::Mesh m = test::icosphere(level);
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> jitter(-5e-5, 5e-5);
  const double R = 0.01, pitch = 2 * R - 1e-4;
  Lattice l;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j)
      for (int k = 0; k < side; ++k)
      {
        const std::array<double, 3> c = {i * pitch + jitter(gen),
                                         j * pitch + jitter(gen),
                                         k * pitch + jitter(gen)};
        std::vector<std::int32_t> nodes;
        for (const auto& p : m.points)
        {
          nodes.push_back(static_cast<std::int32_t>(l.x.size() / 3));
          for (int d = 0; d < 3; ++d)
            l.x.push_back(c[d] + R * p[d]);
        }
        l.surfaces.emplace_back(nodes, m.triangles);
      }
  return l;
}

/// Best of 3 runs (seconds), printed with the sizes
double time_detection(int side, int level)
{
  const Lattice l = lattice(side, level);
  dynamics::DetectionOptions options;
  options.alert_distance = 1e-4;
  options.max_penetration = 2e-4;
  const std::vector<dynamics::PlaneWall> walls = {{{0, 0, -0.0101}, {0, 0, 1}}};
  double best = 1e300;
  std::size_t contacts = 0;
  for (int r = 0; r < 3; ++r)
  {
    const auto t0 = std::chrono::steady_clock::now();
    contacts =
        dynamics::detect_contacts_3d(l.surfaces, l.x, walls, options).size();
    best = std::min(best, std::chrono::duration<double>(
                              std::chrono::steady_clock::now() - t0)
                              .count());
  }
  std::printf("{\"bench\": \"detection_3d\", \"spheres\": %d, "
              "\"triangles_per_sphere\": %zu, \"contacts\": %zu, "
              "\"seconds\": %.6g}\n",
              side * side * side, l.surfaces[0].triangles().size(), contacts,
              best);
  return best;
}

/// Least-squares slope of log t against log n
double exponent(const std::vector<double>& n, const std::vector<double>& t)
{
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double m = static_cast<double>(n.size());
  for (std::size_t i = 0; i < n.size(); ++i)
  {
    const double x = std::log(n[i]), y = std::log(t[i]);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  return (m * sxy - sx * sy) / (m * sxx - sx * sx);
}
} // namespace

int main()
{
  std::vector<double> n, t;
  for (int side : {4, 6, 8, 10})
  {
    n.push_back(side * side * side);
    t.push_back(time_detection(side, 2));
  }
  std::printf("{\"bench\": \"detection_3d_scaling_spheres\", \"exponent\": "
              "%.3f}\n",
              exponent(n, t));
  n.clear(), t.clear();
  for (int level : {2, 3, 4, 5})
  {
    n.push_back(20 * std::pow(4, level));
    t.push_back(time_detection(4, level));
  }
  std::printf("{\"bench\": \"detection_3d_scaling_mesh\", \"exponent\": "
              "%.3f}\n",
              exponent(n, t));
}
