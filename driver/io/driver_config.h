#pragma once

#include <array>
#include <dynamics/moreau_jean.h>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

/// Reading the resolved run description (docs/driver_io.md).
namespace softpack::io
{

/// Names of the four walls bounding the packing (for Phi).
struct Box
{
  std::string left, right, bottom, top;
};

/// Everything `softpack-simulate` needs, read from driver.json.
struct DriverConfig
{
  std::filesystem::path mesh;
  std::string material;
  std::map<std::string, double> material_parameters;
  double density = 0;
  std::vector<dynamics::Wall> walls;
  std::optional<Box> box;
  dynamics::MoreauJeanOptions stepping;
  std::optional<double> stop_packing_fraction;
  double stop_max_time = 0;
  std::filesystem::path output_directory;
  int output_every_steps = 100;
  /// Write fields every this many output steps (0: never)
  int fields_every_outputs = 1;
  /// Write raw/state.bin at every output step
  bool write_state = false;
  /// Start from this state file (io/state_file.h) instead of rest
  std::optional<std::filesystem::path> initial_state;
};

/// Parse and check a driver.json file.
/// @throws std::runtime_error naming the file and the key at fault
DriverConfig read_driver_config(const std::filesystem::path& path);

/// Index of the wall with this name.
/// @throws std::runtime_error if absent
int wall_index(const std::vector<dynamics::Wall>& walls,
               const std::string& name);

} // namespace softpack::io
