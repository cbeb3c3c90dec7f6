#include "run_simulation.h"

#include <bodies/BodySet.h>
#include <bodies/body_mesh.h>
#include <chrono>
#include <contact/fclib_io.h>
#include <cstdio>
#include <io/field_output.h>
#include <io/raw_output.h>
#include <io/setup_file.h>
#include <io/state_file.h>
#include <material_registry.h>
#include <numeric>

namespace softpack::simulation
{
namespace
{
/// Box area from the four box walls' current positions.
double box_area(const std::vector<dynamics::Wall>& walls)
{
  auto gap = [&](const std::string& a, const std::string& b)
  {
    const dynamics::Wall& wa = walls[io::wall_index(walls, a)];
    const dynamics::Wall& wb = walls[io::wall_index(walls, b)];
    return (wb.point[0] - wa.point[0]) * wa.normal[0] +
           (wb.point[1] - wa.point[1]) * wa.normal[1];
  };
  return gap("left", "right") * gap("bottom", "top");
}

double packing_fraction(const bodies::BodySet& bodies,
                        const std::vector<dynamics::Wall>& walls)
{
  const std::vector<double> area = bodies.body_current_area();
  return std::accumulate(area.begin(), area.end(), 0.0) / box_area(walls);
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

/// raw/failed_contact_problems/step_NNNNNNNN.hdf5 (FCLIB layout, replay
/// with ./softpack fclib) when the step left a contact problem unsolved.
void write_unsolved_problem(const std::filesystem::path& raw, long step,
                            const dynamics::StepReport& r)
{
  if (!r.unsolved_problem)
    return;
  const std::filesystem::path dir = raw / "failed_contact_problems";
  std::filesystem::create_directories(dir);
  char name[40];
  std::snprintf(name, sizeof(name), "step_%08ld.hdf5", step);
  contact::dump_problem(*r.unsolved_problem, dir / name,
                        "softpack step " + std::to_string(step) +
                            ": NLGS did not converge",
                        r.unsolved_start);
}

/// The bodies of driver.json's mesh and material; errors in the material
/// name driver.json and the key (material.law, material.parameters.KEY).
bodies::BodySet make_bodies(MPI_Comm comm, const io::DriverConfig& config)
{
  const parameters::Material& m = config.parameters.material;
  bodies::BodyMesh mesh = bodies::read_body_mesh(comm, config.mesh);
  io::check_body_count(config, mesh.num_bodies);
  const forms::MaterialForms* law = nullptr;
  try
  {
    law = &forms::find_material(m.law);
  }
  catch (const std::invalid_argument& e)
  {
    throw std::runtime_error(config.file.string() +
                             ": material.law: " + e.what());
  }
  try
  {
    return bodies::BodySet(std::move(mesh), *law, m.parameters, m.density);
  }
  catch (const std::invalid_argument& e)
  {
    throw std::runtime_error(config.file.string() + ": " + e.what());
  }
}

/// The stop criterion met after `step` (counted from `first`), or "".
std::string stop_reason(const io::DriverConfig& config,
                        const dynamics::MoreauJean& scheme, long first,
                        long step, std::optional<double> phi)
{
  const parameters::Stop& stop = config.parameters.stop;
  if (phi && stop.packing_fraction > 0 && *phi >= stop.packing_fraction)
    return "packing_fraction";
  if (scheme.time() >= stop.max_time * (1 - 1e-12))
    return "max_time";
  if (stop.steps > 0 && step - first >= stop.steps)
    return "steps";
  return "";
}
} // namespace

RunSummary run_simulation(MPI_Comm comm, const io::DriverConfig& config,
                          bool quiet)
{
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  auto elapsed = [&]
  { return std::chrono::duration<double>(clock::now() - start).count(); };
  const parameters::Parameters& p = config.parameters;
  const std::filesystem::path raw_dir = config.directory / "raw";

  bodies::BodySet bodies = make_bodies(comm, config);
  dynamics::MoreauJean scheme(
      bodies, config.walls,
      {p.time, p.contact, p.damping, config.velocity_scale});
  if (config.initial_state)
    scheme.restore(io::read_state(*config.initial_state));
  io::RawOutput raw(config.directory, config.walls);
  io::write_setup(raw_dir, io::setup_json(config, bodies));
  std::unique_ptr<io::FieldOutput> fields;
  if (p.output.fields)
    fields = std::make_unique<io::FieldOutput>(comm, config.directory, bodies);

  auto phi = [&]() -> std::optional<double>
  {
    if (!config.box)
      return std::nullopt;
    return packing_fraction(bodies, scheme.walls());
  };
  const std::optional<double> phi0 = phi();
  const long first = scheme.steps();
  auto progress = [&](long step, std::optional<double> phi_now)
  {
    double f = scheme.time() / p.stop.max_time;
    if (phi_now && p.stop.packing_fraction > 0)
      f = std::max(f, (*phi_now - *phi0) / (p.stop.packing_fraction - *phi0));
    if (p.stop.steps > 0)
      f = std::max(f, double(step - first) / p.stop.steps);
    return std::clamp(f, 0.0, 1.0);
  };

  dynamics::StepTimings spent;
  dynamics::ContactForceAverage average;
  long outputs = 0;
  auto output =
      [&](long step, const dynamics::StepReport& r, std::optional<double> now)
  {
    raw.write(step, scheme, r, now, elapsed(), bodies, spent, average);
    average.reset();
    if (p.output.state)
      io::write_state(raw_dir / "state.bin", scheme.state());
    if (fields && outputs % p.output.fields_every == 0)
      fields->write(bodies, scheme.time());
    ++outputs;
    if (!quiet)
      print_progress(progress(step, now), step, scheme, now, r, elapsed());
  };

  output(first, dynamics::StepReport{}, phi0);
  RunSummary summary;
  for (long step = first + 1;; ++step)
  {
    const dynamics::StepReport r = scheme.step();
    write_unsolved_problem(raw_dir, step, r);
    average.add_step(scheme);
    add_timings(spent, r.seconds);
    const std::optional<double> now = phi();
    const std::string reason = stop_reason(config, scheme, first, step, now);
    if (!reason.empty() || step % p.output.every_steps == 0)
      output(step, r, now);
    if (!reason.empty())
    {
      summary = {step, elapsed(), reason};
      break;
    }
  }
  raw.finish(summary.steps, summary.seconds, summary.reason, spent,
             scheme.factorizations());
  return summary;
}

} // namespace softpack::simulation
