#include "run_simulation.h"

#include <algorithm>
#include <bodies/BodySet.h>
#include <bodies/body_forces.h>
#include <bodies/body_geometry.h>
#include <bodies/stress_average.h>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <io/field_output.h>
#include <io/output_gather.h>
#include <io/raw_output.h>
#include <io/setup_file.h>
#include <io/state_file.h>
#include <material_registry.h>
#include <numeric>
#include <parallel/geometry_broadcast.h>
#include <simulation/box_3d.h>
#include <simulation/overlap_check.h>
#include <simulation/rank_report.h>
#include <simulation/run_support.h>
#include <simulation/stages.h>
#include <sys/resource.h>

namespace softpack::simulation
{
double box_area(const std::vector<dynamics::Wall>& walls)
{
  auto gap = [&](const std::string& a, const std::string& b)
  {
    const dynamics::Wall& wa = walls[io::wall_index(walls, a)];
    const dynamics::Wall& wb = walls[io::wall_index(walls, b)];
    return (wb.point[0] - wa.point[0]) * wa.normal[0] +
           (wb.point[1] - wa.point[1]) * wa.normal[1];
  };
  const std::vector<std::string>& names = io::box_wall_names; // l, r, b, t
  return gap(names[0], names[1]) * gap(names[2], names[3]);
}

bodies::BodySet make_bodies(MPI_Comm comm, const io::DriverConfig& config)
{
  try // a law without forms of the dimension, a bad material parameter
  {
    bodies::BodyGeometry geometry;
    if (rank_of(comm) == 0)
      geometry = bodies::read_body_geometry(
          config.mesh, bodies::displacement_space(
                           config.body_materials.materials, config.dimension));
    parallel::broadcast_geometry(comm, geometry);
    io::check_body_count(config, geometry.num_bodies());
    // A distributed run's ranks assemble the masses they keep only
    // (parallel::Distribution, BodySet::set_local)
    int ranks = 1;
    MPI_Comm_size(comm, &ranks);
    return bodies::BodySet(std::move(geometry), config.body_materials.materials,
                           config.body_materials.body_material, ranks == 1);
  }
  catch (const std::invalid_argument& e)
  {
    throw std::runtime_error(config.file.string() + ": " + e.what());
  }
}

namespace
{
/// The time stepper of the bodies' dimension over the processes: 2D with
/// driver.json's walls, 3D with the box's six planes (box_3d.h)
dynamics::MoreauJean make_scheme(MPI_Comm comm, bodies::BodySet& bodies,
                                 const io::DriverConfig& config)
{
  const parameters::Parameters& p = config.parameters;
  dynamics::MoreauJeanOptions options{p.time,          p.contact,
                                      p.damping,       config.velocity_scale,
                                      config.friction, p.parallel};
  if (bodies.dim() == 3)
    try // what the 3D step refuses (rigid bodies, cohesion, ...)
    {
      return dynamics::MoreauJean(bodies, std::move(options),
                                  box_walls_3d(config),
                                  parallel::Distribution(comm, bodies));
    }
    catch (const std::invalid_argument& e)
    {
      throw std::runtime_error(config.file.string() + ": " + e.what());
    }
  return dynamics::MoreauJean(bodies, config.walls, std::move(options),
                              parallel::Distribution(comm, bodies));
}

/// The walls' names as steps.csv's columns give them
std::vector<std::string> wall_names(const io::DriverConfig& config)
{
  std::vector<std::string> names;
  for (const dynamics::Wall& w : config.walls)
    names.push_back(w.name);
  if (config.dimension == 3)
    names.insert(names.end(), box_planes_3d.begin(), box_planes_3d.end());
  return names;
}

/// One run: its objects, and the bookkeeping between output steps.
class Run
{
public:
  /// Rank 0 reads the mesh and sends its arrays to every rank; a rank then
  /// keeps and computes its own bodies and every boundary
  /// (parallel::Distribution); rank 0 alone writes.
  Run(MPI_Comm comm, const io::DriverConfig& config, bool quiet,
      bool initial_only)
      : _config(config), _p(config.parameters), _initial_only(initial_only),
        _raw_dir(config.directory / "raw"), _root(rank_of(comm) == 0),
        _quiet(quiet || !_root), _bodies(make_bodies(comm, config)),
        // The state's identity and fields.h5's mesh from every node, before
        // a rank keeps its own bodies' interiors only
        _identity(_bodies.dim() == 3
                      ? io::state_identity(_bodies, box_walls_3d(config))
                      : io::state_identity(_bodies, config.walls)),
        _fields(_root && _p.output.fields
                    ? std::make_unique<io::FieldOutput>(
                          config.directory, _bodies,
                          config.initial_state.has_value())
                    : nullptr),
        _scheme(make_scheme(comm, _bodies, config)),
        _raw(_root ? std::make_unique<io::RawOutput>(
                         config.directory, wall_names(config), _bodies.dim(),
                         config.cell.has_value())
                   : nullptr),
        _program(config)
  {
    if (const bodies::Acceleration g = gravity(config);
        g != bodies::Acceleration{0, 0, 0})
      _scheme.set_external_force(_bodies.to_global(bodies::weight(_bodies, g)));
    if (config.cell)
      _scheme.set_cell(*config.cell);
    if (config.initial_state)
    {
      io::StateFile f = io::read_state_file(*config.initial_state, &_identity);
      if (!_program.empty()) // the stage's drives before the walls' state
        _program.resume(
            read_stage_record(stage_record_path(*config.initial_state),
                              f.state.steps, _program.size()),
            _scheme);
      _scheme.restore(f.state);
      if (_fields) // a resume continues its fields (none: a new run's)
        _fields->continue_after(f.state.time);
      _checks = f.checks; // totals over the whole run in done.json
    }
    else if (!_program.empty())
    {
      if (_program.forms_bonds()) // bonds at the starts of such stages only
        _scheme.form_bonds(false);
      _program.begin(0, _scheme, phi());
    }
    _first = _scheme.steps();
    _time0 = _scheme.time();
    _phi0 = phi();
    _phi_base0 = phi_base();
    if (!_root)
      return;
    io::write_setup(_raw_dir, io::setup_json(config, _bodies));
  }

  /// Step until a stop criterion holds; the step that meets it is an
  /// output step.
  RunSummary run()
  {
    output(_first, dynamics::StepReport{}, _phi0,
           _program.empty() ? 0 : _program.start().index);
    if (_initial_only)
      return finish(_first, "initial_only");
    fail_if_asked();
    for (long step = _first + 1;; ++step)
    {
      const dynamics::StepReport r = _scheme.step();
      check_convergence(step, r);
      add_forces();
      add_timings(_spent, r.seconds);
      const std::optional<double> now = phi();
      const bool output_step = step % _p.output.every_steps == 0;
      if (!_program.empty())
      {
        const std::optional<RunSummary> end = stage_step(step, r, now);
        if (end)
          return *end;
        continue;
      }
      // (the base's faces summed only when a criterion reads them)
      const std::string reason = stop_reason(
          _config, _scheme, _first, step, now,
          _p.stop.base_area_fraction > 0 ? phi_base() : std::nullopt);
      if (!reason.empty() || output_step)
        output(step, r, now, 0, !reason.empty());
      if (!reason.empty())
        return finish(step, reason);
    }
  }

private:
  /// The failure test of a distributed run (tests/python/test_mpi.py):
  /// SOFTPACK_TEST_FAIL_RANK=R makes rank R throw after the first output,
  /// when the others are about to wait in the first step's collectives.
  void fail_if_asked() const
  {
    const char* rank = std::getenv("SOFTPACK_TEST_FAIL_RANK");
    if (rank && std::atoi(rank) == _scheme.distribution().comm().rank())
      throw std::runtime_error("SOFTPACK_TEST_FAIL_RANK=" + std::string(rank) +
                               ": this rank fails on purpose (a test)");
  }

  RunSummary finish(long step, const std::string& reason,
                    const nlohmann::json& extra = nullptr)
  {
    const RunSummary summary{step, elapsed(), reason};
    nlohmann::json done = extra.is_object() ? extra : nlohmann::json::object();
    done["mpi_ranks"] = _scheme.distribution().comm().size();
    done["factor_patterns"] = _scheme.factor_patterns();
    if (_bodies.dim() == 3)
      done["dimension"] = 3;
    if (_scheme.distribution().distributed())
      done["mpi"] =
          rank_report(_scheme.distribution(), _scheme.contact_traffic());
    if (_raw)
      _raw->finish(summary.steps, summary.seconds, summary.reason, _spent,
                   _scheme.factorizations(), _checks, done);
    return summary;
  }

  /// After a step of a run with stages: the current stage's criteria, then
  /// the run's ([stop] max_time, steps). A stage whose criterion is met
  /// ends with an output step (labelled with it) and the next one begins
  /// before that step's state is written; a stage that reaches its
  /// max_time first ends the run, incomplete. The run's end, or nothing.
  std::optional<RunSummary> stage_step(long step, const dynamics::StepReport& r,
                                       std::optional<double> now)
  {
    const bool output_step = step % _p.output.every_steps == 0;
    if (output_step) // the equilibrium test reads the energies
      _scheme.prepare_output();
    const StageCheck check = _program.check(_scheme, _bodies, now, output_step);
    const int label = _program.start().index;
    const std::string name = _program.stage().name;
    nlohmann::json extra = {{"stage", label},
                            {"stage_name", name},
                            {"stages", _program.size()},
                            {"ended_by", _program.start().ended_by},
                            {"complete", true}};
    if (check.timed_out || !check.met.empty())
      _scheme.prepare_output(); // the energies of the next stage's start
    if (check.timed_out)
    {
      const std::string why = _program.missed(_scheme, _bodies, now);
      if (_root)
        std::fprintf(stderr, "softpack-simulate: %s: the run ends incomplete\n",
                     why.c_str());
      output(step, r, now, label, true);
      extra["complete"] = false;
      return finish(step, why, extra);
    }
    if (!check.met.empty())
    {
      if (!_quiet)
        std::printf("stage %d \"%s\" ended by %s at t=%.5f s\n", label,
                    name.c_str(), check.met.c_str(), _scheme.time());
      if (_program.last())
      {
        output(step, r, now, label, true);
        extra["ended_by"].push_back(check.met);
        return finish(step, "stages", extra);
      }
      _program.begin(label + 1, _scheme, now, check.met);
      output(step, r, now, label);
      return std::nullopt;
    }
    const std::string reason = stop_reason(_config, _scheme, _first, step, now);
    if (!reason.empty() || output_step)
      output(step, r, now, label, !reason.empty());
    if (reason.empty())
      return std::nullopt;
    // [stop] steps (or max_time) ended the run inside a stage.
    extra["complete"] = false;
    return finish(step, reason, extra);
  }

  /// Count the step if a solve did not converge, warn (rate-limited) and
  /// keep the first unsolved contact problems.
  void check_convergence(long step, const dynamics::StepReport& r)
  {
    io::ConvergenceCounts& total = _checks.total;
    const io::ConvergenceCounts before = total;
    _interval.add(r);
    total.add(r);
    _checks.newton_iterations += r.newton_iterations;
    _checks.nlgs_sweeps += r.nlgs_iterations;
    if (_root &&
        total.newton_unconverged_steps > before.newton_unconverged_steps &&
        warn_now(total.newton_unconverged_steps))
      std::fprintf(stderr,
                   "softpack-simulate: warning: step %ld: Newton did not "
                   "converge in %d iterations (%ld such steps so far)\n",
                   step, r.newton_iterations, total.newton_unconverged_steps);
    if (_root && total.nlgs_unconverged_steps > before.nlgs_unconverged_steps &&
        warn_now(total.nlgs_unconverged_steps))
      std::fprintf(stderr,
                   "softpack-simulate: warning: step %ld: a contact solve "
                   "did not converge (error %.2e; %ld such steps so far)\n",
                   step, r.nlgs_error, total.nlgs_unconverged_steps);
    if (!r.keeps_unsolved_problem())
      return;
    if (_checks.problems_written < max_problem_dumps)
    {
      if (_root)
        write_unsolved_problem(_raw_dir, step, r);
      ++_checks.problems_written;
    }
    else
      ++_checks.problems_not_written;
  }

  /// The overlap measured from the deformed boundaries (overlap_check.h),
  /// warned about when deeper than the contact detection's alert distance.
  double check_overlap(long step)
  {
    const double depth =
        _bodies.dim() == 3
            ? max_overlap_depth_3d(_bodies, _scheme.walls_3d(),
                                   dynamics::detection_options(_p.contact))
            : max_overlap_depth(deformed_boundaries(_bodies), _scheme.walls(),
                                _scheme.cell() ? &*_scheme.cell() : nullptr);
    _checks.max_overlap_depth = std::max(_checks.max_overlap_depth, depth);
    // A continued run's first row is the state's step, counted already.
    const bool counted = _config.initial_state && step == _first;
    if (depth > _p.contact.alert_distance && !counted)
    {
      ++_checks.overlap_steps;
      if (_root && warn_now(_checks.overlap_steps))
        std::fprintf(stderr,
                     "softpack-simulate: warning: step %ld: bodies overlap "
                     "by %.3g m, more than contact.alert_distance = %.3g m "
                     "(%ld such output steps so far)\n",
                     step, depth, _p.contact.alert_distance,
                     _checks.overlap_steps);
    }
    return depth;
  }

  /// Accumulate the step's contact and wall forces for the next output
  void add_forces()
  {
    if (_bodies.dim() == 3)
      _wall_average_3d.add_step(_scheme);
    else
      _average.add_step(_scheme.contacts(), _scheme.impulses(),
                        _scheme.walls().size(), _scheme.time_step());
  }

  double elapsed() const
  {
    return std::chrono::duration<double>(clock::now() - _start).count();
  }

  /// (not const: MoreauJean::walls_3d is writable only)
  std::optional<double> phi()
  {
    if (const auto& cell = _scheme.cell())
      return packing_fraction(_bodies, cell->area());
    if (!_config.box)
      return std::nullopt;
    if (_bodies.dim() == 3)
      return packing_fraction(_bodies, box_volume(_scheme.walls_3d()));
    return packing_fraction(_bodies, box_area(_scheme.walls()));
  }

  /// A 3D run's base area fraction (box_3d.h); none in 2D
  std::optional<double> phi_base()
  {
    if (_bodies.dim() != 3 || !_config.box)
      return std::nullopt;
    return base_area_fraction(_bodies, _scheme.walls_3d());
  }

  /// Fraction done of what this process runs (a run continued from a state:
  /// of the rest, every criterion from the state on, as the ETA counts the
  /// seconds): the furthest of the stop criteria (not const: phi_base reads
  /// MoreauJean::walls_3d)
  double progress(long step, std::optional<double> phi_now)
  {
    const parameters::Stop& stop = _p.stop;
    double f = stop.max_time > _time0
                   ? (_scheme.time() - _time0) / (stop.max_time - _time0)
                   : 1.0;
    if (phi_now && stop.packing_fraction > 0)
      f = std::max(f, (*phi_now - *_phi0) / (stop.packing_fraction - *_phi0));
    if (_phi_base0 && stop.base_area_fraction > 0)
      f = std::max(f, (*phi_base() - *_phi_base0) /
                          (stop.base_area_fraction - *_phi_base0));
    if (stop.steps > 0)
      f = std::max(f, double(step - _first) / stop.steps);
    return std::clamp(f, 0.0, 1.0);
  }

  /// An output row (its stage column `stage`), the state and its stage
  /// record, the fields (at every output.fields_every-th output, and at
  /// the `last` one, so that the fields end with the run's final state).
  void output(long step, const dynamics::StepReport& r,
              std::optional<double> now, int stage = 0, bool last = false)
  {
    // Rank 0 writes what every body's interior gives: the owners compute
    // their bodies' energies and stresses, rank 0 gets global copies of
    // the vectors (fields, the state).
    _scheme.prepare_output();
    io::OutputGather gathered(_scheme, _bodies);
    const std::vector<double> cauchy = body_cauchy(_scheme, _bodies);
    const double depth = check_overlap(step);
    if (_raw)
    {
      _raw->set_stage(stage);
      _raw->set_phi_base(phi_base());
      _raw->write(step, _scheme, r, now, elapsed(), _bodies,
                  wall_rows(_scheme, _average, _wall_average_3d), cauchy,
                  _spent, _average, _interval, depth);
    }
    _average.reset();
    _wall_average_3d.reset();
    _interval = {};
    if (_p.output.fields && (last || _outputs % _p.output.fields_every == 0))
    {
      // Each cell's energy from its body's owner, onto rank 0 (before the
      // state, which takes rank 0's copy of the displacement)
      std::vector<double> psi = _bodies.cell_strain_energy();
      _scheme.distribution().comm().sum_to_root(psi);
      if (_fields)
        _fields->write(gathered.displacement(), psi, _scheme.time());
    }
    if (_root && _p.output.state)
    {
      io::write_state(_raw_dir / "state.bin", gathered.take_state(), _identity,
                      _checks);
      if (!_program.empty())
        write_stage_record(stage_record_path(_raw_dir / "state.bin"), step,
                           _program.start(), _program.stage().name);
    }
    ++_outputs;
    if (!_quiet)
      print_progress(progress(step, now), step, _scheme, now, r, elapsed());
  }

  using clock = std::chrono::steady_clock;
  const io::DriverConfig& _config;
  const parameters::Parameters& _p;
  const bool _initial_only;
  const std::filesystem::path _raw_dir;
  const bool _root;
  const bool _quiet;
  const clock::time_point _start = clock::now();
  bodies::BodySet _bodies;
  const io::StateIdentity _identity;
  /// Rank 0's (the other ranks write nothing), when fields are written
  std::unique_ptr<io::FieldOutput> _fields;
  dynamics::MoreauJean _scheme;
  /// Rank 0's: the other ranks write nothing
  std::unique_ptr<io::RawOutput> _raw;
  StageProgram _program;
  dynamics::StepTimings _spent;
  dynamics::ContactForceAverage _average;
  /// A 3D run's wall forces since the last output (_average's in 2D)
  WallForceAverage3D _wall_average_3d;
  io::ConvergenceCounts _interval;
  io::RunChecks _checks;
  long _outputs = 0;
  long _first = 0;
  double _time0 = 0; ///< the time of step _first
  std::optional<double> _phi0;
  std::optional<double> _phi_base0;
};
} // namespace

RunSummary run_simulation(MPI_Comm comm, const io::DriverConfig& config,
                          bool quiet, bool initial_only)
{
  if (config.dimension == 3)
    check_3d_run(comm, config);
  gravity(config); // its refusal before anything is written
  return Run(comm, config, quiet, initial_only).run();
}

} // namespace softpack::simulation
