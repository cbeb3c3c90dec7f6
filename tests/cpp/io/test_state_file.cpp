// The state file's one layout for both dimensions (driver/io/state_file.h):
// a 3D state's section (its plane walls and its warm start in world
// components) read back exactly; a 2D state ending where it always did
// (no section, the same bytes); a 3D section cut short or of another
// dimension refused.
#include <cstring>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <io/state_file.h>
#include <iterator>
#include <temp_dir.h>

using namespace softpack;

namespace
{
/// A small state of each dimension: every field the file holds nonzero
dynamics::SchemeState a_state(int dim)
{
  dynamics::SchemeState s;
  s.time = 0.125;
  s.steps = 42;
  const std::size_t n = dim == 3 ? 9 : 6;
  for (std::size_t i = 0; i < n; ++i)
  {
    s.u.push_back(1e-3 * (i + 1));
    s.v.push_back(-0.25 * (i + 1));
  }
  s.energy.wall_work = 0.5;
  s.matrix_age = 3;
  s.last_iterations = 4;
  s.u_tangent.assign(n, 1e-4);
  s.step_size.h = 7.2e-5;
  s.dim = dim;
  if (dim == 2)
  {
    s.wall_points = {{0.0, 0.1}, {0.2, 0.3}};
    s.wall_velocities = {{0.0, 0.0}, {-0.5, 0.0}};
    s.reactions = {{{0, 5, -2}, {1e-4, -2e-5}}};
    return s;
  }
  s.wall_points_3d = {{0.11, 0.0, 0.0}, {0.0, 0.0, 0.02}};
  s.wall_velocities_3d = {{-0.5, 0.0, 0.0}, {0.0, 0.0, 0.0}};
  s.reactions_3d = {{{0, 5, 1}, {1e-4, -2e-5, 3e-6}},
                    {{1, 2, -5}, {-1e-6, 0.0, 7e-5}}};
  return s;
}

std::string bytes_of(const std::filesystem::path& path)
{
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A payload with its FNV-1a 64 checksum, as write_state ends a file
std::string with_checksum(std::string payload)
{
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const char c : payload)
    h = (h ^ static_cast<unsigned char>(c)) * 0x100000001b3ULL;
  payload.append(reinterpret_cast<const char*>(&h), sizeof(h));
  return payload;
}

/// What read_state says of these bytes ("" if it reads them)
std::string refusal(const std::filesystem::path& path, const std::string& b)
{
  std::ofstream(path, std::ios::binary) << b;
  try
  {
    io::read_state(path);
  }
  catch (const std::runtime_error& e)
  {
    return e.what();
  }
  return "";
}
} // namespace

TEST(StateFile3D, TheWallsAndWarmStartOfA3DStateReadBackExactly)
{
  const test::TempDir dir;
  const std::filesystem::path path = dir.path() / "state.bin";
  const dynamics::SchemeState s = a_state(3);
  const io::StateIdentity id{11, 22};
  io::write_state(path, s, id);
  const io::StateFile f = io::read_state_file(path, &id);
  EXPECT_EQ(f.state.dim, 3);
  EXPECT_EQ(f.state.steps, 42);
  EXPECT_EQ(f.state.u, s.u);
  EXPECT_EQ(f.state.u_tangent, s.u_tangent);
  EXPECT_TRUE(f.state.wall_points.empty());
  EXPECT_TRUE(f.state.reactions.empty());
  EXPECT_EQ(f.state.wall_points_3d, s.wall_points_3d);
  EXPECT_EQ(f.state.wall_velocities_3d, s.wall_velocities_3d);
  EXPECT_EQ(f.state.reactions_3d, s.reactions_3d);
}

TEST(StateFile3D, A2DStateEndsWhereThe3DSectionBegins)
{
  const test::TempDir dir;
  const std::filesystem::path two = dir.path() / "two.bin",
                              three = dir.path() / "three.bin";
  const dynamics::SchemeState s2 = a_state(2);
  io::write_state(two, s2);
  const io::StateFile f = io::read_state_file(two);
  EXPECT_EQ(f.state.dim, 2);
  EXPECT_EQ(f.state.wall_points, s2.wall_points);
  EXPECT_EQ(f.state.wall_velocities, s2.wall_velocities);
  EXPECT_EQ(f.state.reactions, s2.reactions);
  EXPECT_TRUE(f.state.wall_points_3d.empty());
  EXPECT_TRUE(f.state.reactions_3d.empty());
  // The same state marked 3D: the 2D bytes, then the section (the
  // dimension and three counts, all 0 here) before the checksum
  dynamics::SchemeState s3 = s2;
  s3.dim = 3;
  s3.wall_points.clear();
  s3.wall_velocities.clear();
  s3.reactions.clear();
  dynamics::SchemeState plain = s3;
  plain.dim = 2;
  io::write_state(two, plain);
  io::write_state(three, s3);
  const std::string b2 = bytes_of(two), b3 = bytes_of(three);
  ASSERT_EQ(b3.size(), b2.size() + 4 * sizeof(std::int64_t));
  EXPECT_EQ(b3.substr(0, b2.size() - 8), b2.substr(0, b2.size() - 8));
  std::int64_t dim;
  std::memcpy(&dim, b3.data() + b2.size() - 8, sizeof(dim));
  EXPECT_EQ(dim, 3);
  EXPECT_EQ(io::read_state(three).dim, 3);
}

TEST(StateFile3D, ACutOrForeignSectionIsRefused)
{
  const test::TempDir dir;
  const std::filesystem::path path = dir.path() / "state.bin";
  io::write_state(path, a_state(3));
  const std::string bytes = bytes_of(path);
  const std::string payload = bytes.substr(0, bytes.size() - 8);
  // The section: dimension, 3 counts, 2 walls' points and velocities, 2
  // reactions (3 int32 and 3 doubles each)
  const std::size_t section = 4 * 8 + 2 * 2 * 3 * 8 + 2 * (12 + 24);
  std::string foreign = payload;
  foreign[payload.size() - section] = 4; // a dimension 4
  EXPECT_NE(refusal(path, with_checksum(foreign)).find("bad sizes"),
            std::string::npos);
  // Cut inside the last reaction, the checksum made again
  EXPECT_NE(refusal(path, with_checksum(payload.substr(0, payload.size() - 40)))
                .find("truncated"),
            std::string::npos);
  // A section with walls and a 2D wall in the header: not a state
  // write_state makes
  dynamics::SchemeState mixed = a_state(3);
  mixed.wall_points = {{0.0, 0.0}};
  io::write_state(path, mixed);
  EXPECT_NE(refusal(path, bytes_of(path)).find("bad sizes"), std::string::npos);
  EXPECT_EQ(refusal(path, bytes), "");
}
