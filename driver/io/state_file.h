#pragma once

#include <bodies/BodySet.h>
#include <cstdint>
#include <dynamics/moreau_jean.h>
#include <filesystem>
#include <io/raw_output.h>

namespace softpack::io
{

/// What a state belongs to: hashes (FNV-1a, 64 bits) of the mesh and
/// packing (the nodes' reference coordinates and each cell's body) and of
/// the walls' initial lines (points and normals). A state continues only
/// the run it came from: another seed, a shifted mesh or other walls are
/// refused on load instead of failing later as an inverted element.
struct StateIdentity
{
  std::uint64_t mesh = 0;
  std::uint64_t walls = 0;
  bool operator==(const StateIdentity&) const = default;
};

/// The identity of a run's bodies and its walls as driver.json gives them
/// (their initial lines, not the current ones).
StateIdentity state_identity(const bodies::BodySet& bodies,
                             const std::vector<dynamics::Wall>& walls);

/// The identity of a 3D run: its bodies and its plane walls' initial
/// points and normals (simulation::box_walls_3d: the box with its lid)
StateIdentity state_identity(const bodies::BodySet& bodies,
                             const std::vector<dynamics::Wall3D>& walls);

/// A state file's content.
struct StateFile
{
  dynamics::SchemeState state;
  StateIdentity identity;
  /// The run's convergence and overlap counts up to the state's step, so
  /// that a run continued from it reports totals over the whole run
  RunChecks checks;
};

/// A run's state on disk (docs/driver_io.md, raw/state.bin): a small binary
/// file, written atomically, that lets a run (or a benchmark) start from the
/// middle of a compaction. The layout is the driver's own: no other stage
/// parses it (`softpack-simulate --state-info FILE` prints its step and
/// time).
///
/// Layout (native little-endian): the 16 bytes "softpack-state-6", the
/// identity (2 uint64), int64 counts (DOFs, walls, reactions, wall
/// velocities: 0 or the wall count), time (double), steps (int64), u, v,
/// the wall points (2 doubles each), the reactions (3 int32 keys and 2
/// doubles each), the 10 doubles of the energy balance, the wall
/// velocities, the run checks (4 int64, a double, an int64), the kept
/// iteration matrix (its age, -1 for none, the last step's Newton
/// iterations and the count of the displacement it was assembled at, 0 or
/// the DOFs, as int64, then that displacement), the adaptive time step
/// (the current step, a double; the window's calm steps and Newton
/// iterations and the retried steps, int64; the energy residual and the
/// energy supplied at the window's start, 2 doubles), the cohesion account
/// (a double), the periodic cell (layout 7), the bonds (layout 8), the
/// viscous account (a double), each cell's internal variables and those of
/// the kept tangent (each an int64 count, 0 for a law without, then the
/// doubles; layout 9), for a 3D state its section, and last the FNV-1a 64
/// hash of every byte before it. Layouts 8, 7, 6, 5 (without the window's
/// start and the cohesion) and 3 (without the adaptive step) are still
/// read.
///
/// One layout for both dimensions: a 2D state ends after the internal
/// variables (its bytes those of a 2D state before 3D states were written);
/// a 3D state has no 2D walls or reactions (their counts 0) and adds its
/// section there: the dimension 3, the counts (int64) of its plane walls,
/// of their velocities (0 or the walls) and of its reactions, each wall's
/// point and velocity (3 doubles each), and each reaction's key (3 int32)
/// and world impulse (3 doubles: ImpulseHistory::Entry3D).
void write_state(const std::filesystem::path& path,
                 const dynamics::SchemeState& state,
                 const StateIdentity& identity = {},
                 const RunChecks& checks = {});

/// Read a state file, checking its layout and checksum, and its identity
/// against `expected` when given.
/// @throws std::runtime_error naming the file if it is not a state file of
/// this layout, is truncated, its checksum does not match, or it belongs
/// to another mesh and packing or other walls
StateFile read_state_file(const std::filesystem::path& path,
                          const StateIdentity* expected = nullptr);

/// The state of read_state_file, without its identity.
dynamics::SchemeState read_state(const std::filesystem::path& path);

/// Read a state file for the run whose identity is `expected`.
/// @throws std::runtime_error naming the file and what differs (its mesh
/// and packing, or its walls) when it belongs to another run
dynamics::SchemeState read_state(const std::filesystem::path& path,
                                 const StateIdentity& expected);

} // namespace softpack::io
