#pragma once

#include <bodies/BodySet.h>
#include <bodies/stress_average.h>
#include <detection/contact_history.h>
#include <dynamics/moreau_jean.h>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>

namespace softpack::io
{

/// Steps of an output interval (or of the whole run) whose solves did not
/// converge: they are counted, never silent (issue 16, item 4).
struct ConvergenceCounts
{
  /// Steps whose Newton iterations stopped at time.newton_max_iterations
  long newton_unconverged_steps = 0;
  /// Steps with at least one contact solve that stopped unconverged
  long nlgs_unconverged_steps = 0;
  /// Steps solved only after a retry at a smaller step size (StepSize):
  /// solved, so not unconverged, but counted
  long retried_steps = 0;

  void add(const dynamics::StepReport& r)
  {
    retried_steps += r.retries > 0 ? 1 : 0;
    newton_unconverged_steps += r.newton_converged ? 0 : 1;
    nlgs_unconverged_steps +=
        (r.nlgs_converged && r.unsolved_contact_solves == 0) ? 0 : 1;
  }
  bool converged() const
  {
    return newton_unconverged_steps == 0 && nlgs_unconverged_steps == 0;
  }
};

/// What raw/done.json reports beyond the stop: the run's convergence and
/// the independent overlap check.
struct RunChecks
{
  ConvergenceCounts total;
  /// Unsolved contact problems dumped, and how many were not (bounded)
  long problems_written = 0, problems_not_written = 0;
  /// Largest overlap depth seen at an output step (overlap_check.h), m
  double max_overlap_depth = 0;
  /// Output steps whose overlap depth exceeded the tolerance
  long overlap_steps = 0;
  /// The work of this run's steps (not carried through a continuation):
  /// Newton iterations and NLGS sweeps, summed
  long newton_iterations = 0, nlgs_sweeps = 0;
};

/// One wall's columns of raw/steps.csv: its current point and the force it
/// received, averaged since the previous output (2 components in 2D, 3 in
/// 3D; the third is unused in 2D).
struct WallRow
{
  std::array<double, 3> point = {0, 0, 0}, force = {0, 0, 0};
};

/// Writer of a run's raw output (docs/driver_io.md, "Raw output"): the
/// per-step series, per-particle values and per-contact forces, flushed at
/// each output so that a crash loses nothing already computed, and
/// `raw/done.json` written last to mark the run complete. The bodies'
/// dimension sets the columns of points, forces and stresses (2 or 3
/// components; docs/driver_io.md, "3D runs").
class RawOutput
{
public:
  /// Create `directory/raw/` (removing a previous done.json) and the files'
  /// headers; with a periodic cell, steps.csv has its edge vectors
  /// (cell_a1x, cell_a1y, cell_a2x, cell_a2y) and each contact its image
  /// (image1, image2).
  /// @param[in] walls The walls' names, in the order of write's rows
  /// @param[in] dim The bodies' dimension, 2 or 3
  RawOutput(const std::filesystem::path& directory,
            const std::vector<std::string>& walls, int dim, bool cell = false);

  /// Append one output step.
  /// @param[in] step Step number
  /// @param[in] scheme The time stepper (state, contacts, energies)
  /// @param[in] report The step's report
  /// @param[in] phi Packing fraction, if there is a box
  /// @param[in] seconds Wall time since the start
  /// @param[in] bodies The bodies (areas; their strain energies are the
  /// scheme's, MoreauJean::body_strain_energy)
  /// @param[in] walls Each wall's point and force, in the constructor's
  /// order
  /// @param[in] cauchy Each body's Cauchy integral (bodies/stress_average.h:
  /// 4 components per body in 2D, 9 in 3D), every body's (on a
  /// distributed run, from its owner)
  /// @param[in] spent Wall time per part of the step, summed since the start
  /// @param[in] forces Contact forces averaged since the previous output
  /// step (the 2D contacts written; a 3D run writes its last step's)
  /// @param[in] interval Unconverged steps since the previous output step
  /// @param[in] overlap_depth Largest overlap depth now (overlap_check.h)
  void write(long step, const dynamics::MoreauJean& scheme,
             const dynamics::StepReport& report, std::optional<double> phi,
             double seconds, const bodies::BodySet& bodies,
             const std::vector<WallRow>& walls, std::span<const double> cauchy,
             const dynamics::StepTimings& spent,
             const dynamics::ContactForceAverage& forces,
             const ConvergenceCounts& interval, double overlap_depth);

  /// The loading stage the next rows belong to (the `stage` column; 0
  /// without stages).
  void set_stage(int stage) { _stage = stage; }
  /// The base area fraction of the next rows (3D runs' phi_base column,
  /// simulation::base_area_fraction; empty when none)
  void set_phi_base(std::optional<double> phi_base) { _phi_base = phi_base; }

  /// Mark the run complete; `extra` (an object) adds its keys to done.json
  /// (a run with stages: its last stage and whether it ended complete).
  void finish(long steps, double seconds, const std::string& reason,
              const dynamics::StepTimings& spent, int factorizations,
              const RunChecks& checks, const nlohmann::json& extra = nullptr);

private:
  void write_particles(long step, const bodies::BodySet& bodies,
                       std::span<const double> strain_energy,
                       std::span<const double> cauchy);
  void write_particles_3d(long step, const bodies::BodySet& bodies,
                          std::span<const double> strain_energy,
                          std::span<const double> cauchy);
  void write_contacts(long step, const dynamics::ContactForceAverage& forces);
  /// The last step's 3D contacts and their forces (impulse / h)
  void write_contacts_3d(long step, const dynamics::MoreauJean& scheme);
  /// Components per Cauchy integral: 4 in 2D, 9 in 3D
  int cauchy_size() const { return _dim == 2 ? 4 : 9; }

  std::filesystem::path _raw;
  /// A periodic cell's run (its columns written)
  bool _cell = false;
  /// The bodies' dimension
  int _dim = 2;
  std::ofstream _steps, _particles;
  int _stage = 0;
  std::optional<double> _phi_base;
};

} // namespace softpack::io
