#pragma once

#include <bodies/BodySet.h>
#include <dynamics/contact_history.h>
#include <dynamics/moreau_jean.h>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

namespace softpack::io
{

/// Writer of a run's raw output (docs/driver_io.md, "Raw output"): the
/// per-step series, per-particle values and per-contact forces, flushed at
/// each output so that a crash loses nothing already computed, and
/// `raw/done.json` written last to mark the run complete.
class RawOutput
{
public:
  /// Create `directory/raw/` (removing a previous done.json) and the files'
  /// headers.
  RawOutput(const std::filesystem::path& directory,
            const std::vector<dynamics::Wall>& walls);

  /// Append one output step.
  /// @param[in] step Step number
  /// @param[in] scheme The time stepper (state, contacts, energies)
  /// @param[in] report The step's report
  /// @param[in] phi Packing fraction, if there is a box
  /// @param[in] seconds Wall time since the start
  /// @param[in] bodies The bodies (areas and energies)
  /// @param[in] spent Wall time per part of the step, summed since the start
  /// @param[in] forces Contact and wall forces averaged since the previous
  /// output step (the forces written)
  void write(long step, const dynamics::MoreauJean& scheme,
             const dynamics::StepReport& report, std::optional<double> phi,
             double seconds, const bodies::BodySet& bodies,
             const dynamics::StepTimings& spent,
             const dynamics::ContactForceAverage& forces);

  /// Mark the run complete.
  void finish(long steps, double seconds, const std::string& reason,
              const dynamics::StepTimings& spent, int factorizations);

private:
  void write_particles(long step, const bodies::BodySet& bodies);
  void write_contacts(long step, const dynamics::ContactForceAverage& forces);

  std::filesystem::path _raw;
  std::ofstream _steps, _particles;
};

} // namespace softpack::io
