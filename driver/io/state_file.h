#pragma once

#include <dynamics/moreau_jean.h>
#include <filesystem>

namespace softpack::io
{

/// A run's state on disk (docs/driver_io.md, raw/state.bin): a small binary
/// file, written atomically, that lets a run (or a benchmark) start from the
/// middle of a compaction. The layout is the driver's own: no other stage
/// parses it (its time and step are in the raw/steps.csv written with it).
///
/// Layout (native little-endian): the 16 bytes "softpack-state-1", then
/// int64 counts (DOFs, walls, reactions), time (double), steps (int64), u,
/// v, the wall points (2 doubles each), the reactions (3 int32 keys and 2
/// doubles each), and the 10 doubles of the energy balance.
void write_state(const std::filesystem::path& path,
                 const dynamics::SchemeState& state);

/// @throws std::runtime_error naming the file if it is not a state file or
/// is truncated
dynamics::SchemeState read_state(const std::filesystem::path& path);

} // namespace softpack::io
