#include "run_support.h"

#include <contact/fclib_io.h>
#include <cstdio>
#include <numeric>
#include <stdexcept>

namespace softpack::simulation
{

bodies::Acceleration gravity(const io::DriverConfig& config)
{
  const std::vector<double>& g = config.parameters.gravity.acceleration;
  if (config.dimension == 2 && g.size() == 3)
    throw std::runtime_error(
        config.file.string() +
        ": gravity.acceleration has 3 components in a "
        "2D run (scene.model.dimension = 2): gravity acts in the plane, "
        "[gx, gy]");
  return {g[0], g[1], g.size() == 3 ? g[2] : 0.0};
}

double packing_fraction(const bodies::BodySet& bodies, double space)
{
  const std::vector<double> area = bodies.body_current_area();
  return std::accumulate(area.begin(), area.end(), 0.0) / space;
}

void print_progress(double fraction, long step, const dynamics::MoreauJean& s,
                    std::optional<double> phi, const dynamics::StepReport& r,
                    double seconds)
{
  const double eta = fraction > 1e-6 ? seconds * (1 - fraction) / fraction : 0;
  std::printf("[%5.1f%%] step %ld t=%.5f s", 100 * fraction, step, s.time());
  if (phi)
    std::printf(" Phi=%.4f", *phi);
  std::printf(" contacts %d newton %d nlgs %d (err %.1e) elapsed %.0f s "
              "ETA %.0f s\n",
              r.active_contacts, r.newton_iterations, r.nlgs_iterations,
              r.nlgs_error, seconds, eta);
  std::fflush(stdout);
}

void add_timings(dynamics::StepTimings& sum, const dynamics::StepTimings& t)
{
  sum.detection += t.detection;
  sum.assembly += t.assembly;
  sum.factorization += t.factorization;
  sum.delassus += t.delassus;
  sum.nlgs += t.nlgs;
  sum.solves += t.solves;
}

bool warn_now(long count)
{
  return count == 1 || count % 100 == 0;
}

void write_unsolved_problem(const std::filesystem::path& raw, long step,
                            const dynamics::StepReport& r)
{
  const std::filesystem::path dir = raw / "failed_contact_problems";
  std::filesystem::create_directories(dir);
  char name[40];
  std::snprintf(name, sizeof(name), "step_%08ld.hdf5", step);
  const std::string description =
      "softpack step " + std::to_string(step) + ": NLGS did not converge";
  if (r.unsolved_problem_3d)
    contact::dump_problem(*r.unsolved_problem_3d, dir / name, description,
                          r.unsolved_start);
  else
    contact::dump_problem(*r.unsolved_problem, dir / name, description,
                          r.unsolved_start);
}

int rank_of(MPI_Comm comm)
{
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return rank;
}

std::string stop_reason(const io::DriverConfig& config,
                        const dynamics::MoreauJean& scheme, long first,
                        long step, std::optional<double> phi,
                        std::optional<double> phi_base)
{
  const parameters::Stop& stop = config.parameters.stop;
  if (phi && stop.packing_fraction > 0 && *phi >= stop.packing_fraction)
    return "packing_fraction";
  if (phi_base && stop.base_area_fraction > 0 &&
      *phi_base >= stop.base_area_fraction)
    return "base_area_fraction";
  if (scheme.time() >= stop.max_time * (1 - 1e-12))
    return "max_time";
  if (stop.steps > 0 && step - first >= stop.steps)
    return "steps";
  return "";
}

std::vector<double> body_cauchy(const dynamics::MoreauJean& scheme,
                                const bodies::BodySet& bodies)
{
  if (bodies.dim() == 3)
  {
    static_assert(sizeof(bodies::CauchyIntegral3D) == 9 * sizeof(double));
    std::vector<bodies::CauchyIntegral3D> c =
        bodies::cauchy_integrals_3d(bodies);
    scheme.distribution().scatterer().share_by_body(
        std::span<double>(c.front().data(), 9 * c.size()), 9);
    return std::vector<double>(c.front().data(),
                               c.front().data() + 9 * c.size());
  }
  static_assert(sizeof(bodies::CauchyIntegral) == 4 * sizeof(double));
  std::vector<bodies::CauchyIntegral> cauchy = bodies::cauchy_integrals(bodies);
  scheme.distribution().scatterer().share_by_body(
      std::span<double>(cauchy.front().data(), 4 * cauchy.size()), 4);
  return std::vector<double>(cauchy.front().data(),
                             cauchy.front().data() + 4 * cauchy.size());
}

std::vector<io::WallRow> wall_rows(dynamics::MoreauJean& scheme,
                                   const dynamics::ContactForceAverage& average,
                                   const WallForceAverage3D& average_3d)
{
  std::vector<io::WallRow> rows;
  if (scheme.walls().empty() && !scheme.walls_3d().empty())
  {
    const std::vector<dynamics::Wall3D>& walls = scheme.walls_3d();
    const auto forces = average_3d.forces(walls.size());
    for (std::size_t w = 0; w < walls.size(); ++w)
      rows.push_back({walls[w].point, forces[w]});
    return rows;
  }
  std::vector<std::array<double, 2>> forces = average.wall_forces();
  forces.resize(scheme.walls().size(), {0, 0});
  for (std::size_t w = 0; w < forces.size(); ++w)
  {
    const dynamics::Wall& wall = scheme.walls()[w];
    rows.push_back(
        {{wall.point[0], wall.point[1], 0}, {forces[w][0], forces[w][1], 0}});
  }
  return rows;
}

} // namespace softpack::simulation
