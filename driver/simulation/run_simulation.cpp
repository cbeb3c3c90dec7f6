#include "run_simulation.h"

#include <bodies/BodySet.h>
#include <bodies/body_mesh.h>
#include <chrono>
#include <cstdio>
#include <io/field_output.h>
#include <io/raw_output.h>
#include <io/state_file.h>
#include <material_registry.h>
#include <numeric>

namespace softpack::simulation
{
namespace
{
/// Box area from the four walls' current positions.
double box_area(const std::vector<dynamics::Wall>& walls, const io::Box& box)
{
  auto gap = [&](const std::string& a, const std::string& b)
  {
    const dynamics::Wall& wa = walls[io::wall_index(walls, a)];
    const dynamics::Wall& wb = walls[io::wall_index(walls, b)];
    return (wb.point[0] - wa.point[0]) * wa.normal[0] +
           (wb.point[1] - wa.point[1]) * wa.normal[1];
  };
  return gap(box.left, box.right) * gap(box.bottom, box.top);
}

double packing_fraction(const bodies::BodySet& bodies,
                        const std::vector<dynamics::Wall>& walls,
                        const io::Box& box)
{
  const std::vector<double> area = bodies.body_current_area();
  return std::accumulate(area.begin(), area.end(), 0.0) / box_area(walls, box);
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
} // namespace

RunSummary run_simulation(const io::DriverConfig& config, bool quiet)
{
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  auto elapsed = [&]
  { return std::chrono::duration<double>(clock::now() - start).count(); };

  bodies::BodySet bodies(bodies::read_body_mesh(config.mesh),
                         forms::find_material(config.material),
                         config.material_parameters, config.density);
  dynamics::MoreauJeanOptions options = config.stepping;
  options.failed_problem_directory =
      config.output_directory / "raw" / "failed_contact_problems";
  dynamics::MoreauJean scheme(bodies, config.walls, options);
  if (config.initial_state)
    scheme.restore(io::read_state(*config.initial_state));
  io::RawOutput raw(config.output_directory, config.walls);
  std::unique_ptr<io::FieldOutput> fields;
  if (config.fields_every_outputs > 0)
    fields = std::make_unique<io::FieldOutput>(config.output_directory, bodies);

  auto phi = [&]() -> std::optional<double>
  {
    if (!config.box)
      return std::nullopt;
    return packing_fraction(bodies, scheme.walls(), *config.box);
  };
  const std::optional<double> phi0 = phi();
  auto progress = [&](std::optional<double> p)
  {
    double f = scheme.time() / config.stop_max_time;
    if (p && config.stop_packing_fraction)
      f = std::max(f, (*p - *phi0) / (*config.stop_packing_fraction - *phi0));
    return std::clamp(f, 0.0, 1.0);
  };

  RunSummary summary;
  dynamics::StepTimings spent;
  dynamics::ContactForceAverage average;
  long outputs = 0;
  auto output =
      [&](long step, const dynamics::StepReport& r, std::optional<double> p)
  {
    raw.write(step, scheme, r, p, elapsed(), bodies, spent, average);
    average.reset();
    if (config.write_state)
      io::write_state(config.output_directory / "raw" / "state.bin",
                      scheme.state());
    if (fields && outputs % config.fields_every_outputs == 0)
      fields->write(bodies, scheme.time());
    ++outputs;
    if (!quiet)
      print_progress(progress(p), step, scheme, p, r, elapsed());
  };

  const long first = scheme.steps();
  output(first, dynamics::StepReport{}, phi0);
  for (long step = first + 1;; ++step)
  {
    const dynamics::StepReport r = scheme.step();
    average.add_step(scheme);
    spent.detection += r.seconds.detection;
    spent.assembly += r.seconds.assembly;
    spent.factorization += r.seconds.factorization;
    spent.delassus += r.seconds.delassus;
    spent.nlgs += r.seconds.nlgs;
    spent.solves += r.seconds.solves;
    const std::optional<double> p = phi();
    const bool full = p && config.stop_packing_fraction &&
                      *p >= *config.stop_packing_fraction;
    const bool late = scheme.time() >= config.stop_max_time * (1 - 1e-12);
    if (full || late || step % config.output_every_steps == 0)
      output(step, r, p);
    if (full || late)
    {
      summary = {step, elapsed(), full ? "packing_fraction" : "max_time"};
      break;
    }
  }
  raw.finish(summary.steps, summary.seconds, summary.reason, spent,
             scheme.factorizations());
  return summary;
}

} // namespace softpack::simulation
