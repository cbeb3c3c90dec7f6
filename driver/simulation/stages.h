#pragma once

#include <bodies/BodySet.h>
#include <bodies/body_forces.h>
#include <dynamics/moreau_jean.h>
#include <filesystem>
#include <io/driver_config.h>
#include <optional>
#include <string>
#include <vector>

/// Loading programs: a run as a sequence of stages (schema [stages],
/// docs/loading.md), each changing the walls' drives (or a periodic cell's,
/// docs/periodic_cell.md) between two time steps and ending at its own
/// stop criterion.
namespace softpack::simulation
{

/// Where the current stage started: its criteria are measured from there.
struct StageStart
{
  /// Index of the stage in the program
  int index = 0;
  /// Time step and time at which it started
  long step = 0;
  double time = 0;
  /// The energy accounts' wall_work, external_work (gravity) and
  /// cell_work at its start (after the drive change)
  double wall_work = 0, external_work = 0, cell_work = 0;
  /// Distance between the strain wall and the wall facing it (0: none)
  double length = 0;
  /// +1 when Phi (pressure) started below the stage's target, -1 above
  int phi_side = 1, pressure_side = 1;
  /// The criterion that ended each earlier stage (StageCheck::met)
  std::vector<std::string> ended_by;
};

/// What a stage check found after a step.
struct StageCheck
{
  /// The criterion met ("packing_fraction", "strain", "pressure",
  /// "equilibrium", or "max_time" for a stage with no other), or ""
  std::string met;
  /// The stage's max_time was reached before its other criteria
  bool timed_out = false;
};

/// The two ratios of the equilibrium criterion at the last step.
struct Balance
{
  /// K / |W_stage|: kinetic energy of the bodies and servo walls (and
  /// cell) over the work supplied since the stage's start, by the walls,
  /// gravity and the cell (inf when that work is 0 and K > 0)
  double kinetic = 0;
  /// The larger of max_p |f_p| / <|f_c|> (the largest resultant force,
  /// contacts and weight, on a particle over the mean magnitude of the nonzero
  /// pair contact forces, each pair's nodal forces summed; 0 without contact
  /// forces) and, for each servo wall, |F_imposed - F_received| / |F_imposed|
  /// (its imposed force against the normal contact force it received)
  double force = 0;
};

/// The box's wall pressure P = (sxx + syy) / 2, sxx = (F_left / l_left +
/// F_right / l_right) / 2 and syy likewise with bottom and top, F the
/// normal force each wall received (along -normal, so > 0 in compression)
/// and l its current length.
/// @param[in] walls The walls (with the four box walls)
/// @param[in] forces The force each wall received (MoreauJean::wall_forces)
double box_pressure(const std::vector<dynamics::Wall>& walls,
                    const std::vector<std::array<double, 2>>& forces);
/// The same for a 3D run's box (its vertical walls, a wall's area its
/// length times the box's height from base to lid; the base and lid do not
/// enter P)
double box_pressure(const std::vector<dynamics::Wall3D>& walls,
                    const std::vector<std::array<double, 3>>& forces);

/// The wall facing wall w (its normal opposite), or -1.
int facing_wall(const std::vector<dynamics::Wall>& walls, int w);

/// Distance between wall w and the wall facing it, along w's normal.
double facing_distance(const std::vector<dynamics::Wall>& walls, int w);
double facing_distance(const std::vector<dynamics::Wall3D>& walls, int w);

/// max_p |f_p| / <|f_c|> from the last step's contacts and impulses
/// (Balance::force); f_p includes the particle's weight under `gravity`
/// (schema [gravity]), so that a particle at rest on others is balanced.
double unbalanced_force_ratio(const dynamics::MoreauJean& scheme,
                              const bodies::BodySet& bodies,
                              const bodies::Acceleration& gravity);

/// The stages of a run and the current one.
///
/// A stage's drives are applied between two steps: a wall that becomes a
/// servo wall starts at rest, a servo wall that becomes velocity-driven
/// leaves the accounts' kinetic energy, so its m V^2 / 2 is taken from
/// wall_work (the loading program took it back) and the balance closes.
class StageProgram
{
public:
  explicit StageProgram(const io::DriverConfig& config);

  bool empty() const { return _stages.empty(); }
  int size() const { return static_cast<int>(_stages.size()); }
  const parameters::Stage& stage() const { return _stages[_start.index]; }
  const StageStart& start() const { return _start; }
  bool last() const { return _start.index + 1 == size(); }

  /// true when a stage has bond = true: bonds form at the starts of such
  /// stages only, not at the run's first step (docs/contact_laws.md)
  bool forms_bonds() const;

  /// Begin stage k after step `step`: its drives on the scheme's walls, its
  /// friction and, with bond = true, bonds to form at its first step; its
  /// start recorded; `ended_by`: the criterion that ended the stage before
  /// it (none for the first)
  void begin(int k, dynamics::MoreauJean& scheme, std::optional<double> phi,
             const std::string& ended_by = "");

  /// Set the walls' drives of stages 0..start.index and that stage's
  /// friction (before the scheme's
  /// restore from a state) and continue that stage from `start`.
  void resume(const StageStart& start, dynamics::MoreauJean& scheme);

  /// The current stage's criteria after a step; equilibrium only when
  /// `output_step` (it needs the energies).
  StageCheck check(const dynamics::MoreauJean& scheme,
                   const bodies::BodySet& bodies, std::optional<double> phi,
                   bool output_step) const;

  /// The equilibrium ratios now.
  Balance balance(const dynamics::MoreauJean& scheme,
                  const bodies::BodySet& bodies) const;

  /// A line saying which criterion the stage missed and where it stood.
  std::string missed(const dynamics::MoreauJean& scheme,
                     const bodies::BodySet& bodies,
                     std::optional<double> phi) const;

private:
  /// Set stage k's drives on the scheme's walls (of its dimension); the
  /// kinetic energy of servo walls turned velocity-driven
  static double set_drives(const parameters::Stage& stage,
                           dynamics::MoreauJean& scheme);
  /// Distance between the wall `name` and the wall facing it, now
  static double wall_distance(const dynamics::MoreauJean& scheme,
                              const std::string& name);
  /// box_pressure of the scheme's walls and last forces
  static double pressure(const dynamics::MoreauJean& scheme);
  double strain(const dynamics::MoreauJean& scheme) const;

  std::vector<parameters::Stage> _stages;
  /// A periodic cell's drive from [cell] and each stage's (empty: walls)
  dynamics::CellDrive _cell_drive;
  std::vector<dynamics::CellDrive> _stage_cells;
  /// [gravity] acceleration: the particles' weight enters their balance
  bodies::Acceleration _gravity;
  StageStart _start;
};

/// The stage record of a state file S.bin: S.stage.json next to it.
std::filesystem::path stage_record_path(const std::filesystem::path& state);

/// Write the record of the current stage (atomically), for a state written
/// at `step`.
void write_stage_record(const std::filesystem::path& path, long step,
                        const StageStart& start, const std::string& name);

/// Read the stage record of a state at `step`.
/// @throws std::runtime_error naming the file when it is absent, of
/// another step or malformed: a run with stages continues only from a
/// state whose stage is known
StageStart read_stage_record(const std::filesystem::path& path, long step,
                             int stages);

} // namespace softpack::simulation
