// Nothing silent (issue 16): unconverged steps are counted per output row
// and in done.json with the failure dumps bounded; an overlap the contact
// detection missed is measured from the deformed boundaries; a state file
// from another run, or corrupted, is refused by name.
#include "driver_json.h"
#include "mesh_fixtures.h"
#include <cmath>
#include <fstream>
#include <gtest/gtest.h>
#include <io/driver_config.h>
#include <io/state_file.h>
#include <numeric>
#include <simulation/overlap_check.h>
#include <simulation/run_simulation.h>
#include <sstream>

using namespace softpack;
using nlohmann::json;

namespace
{
json read_json(const std::filesystem::path& path)
{
  std::ifstream in(path);
  return json::parse(in);
}

/// The values of a column of a CSV file, one per row.
std::vector<double> column(const std::filesystem::path& path,
                           const std::string& name)
{
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::stringstream header(line);
  int index = 0;
  for (std::string cell; std::getline(header, cell, ','); ++index)
    if (cell == name)
      break;
  std::vector<double> values;
  while (std::getline(in, line))
  {
    std::stringstream row(line);
    std::string cell;
    for (int i = 0; i <= index; ++i)
      std::getline(row, cell, ',');
    values.push_back(std::stod(cell));
  }
  return values;
}

double column_sum(const std::filesystem::path& path, const std::string& name)
{
  const std::vector<double> v = column(path, name);
  return std::accumulate(v.begin(), v.end(), 0.0);
}

double column_max(const std::filesystem::path& path, const std::string& name)
{
  const std::vector<double> v = column(path, name);
  return std::accumulate(v.begin(), v.end(), 0.0,
                         [](double a, double b) { return std::max(a, b); });
}

simulation::RunSummary run(const json& doc, const std::filesystem::path& dir)
{
  test::write_json(doc, dir / "driver.json");
  return simulation::run_simulation(
      MPI_COMM_WORLD, softpack::io::read_driver_config(dir / "driver.json"),
      true);
}

std::string error_of(const json& doc, const std::filesystem::path& dir)
{
  try
  {
    run(doc, dir);
  }
  catch (const std::runtime_error& e)
  {
    return e.what();
  }
  return "";
}

/// Two disks of radius 0.01 whose centres are `distance` apart.
std::filesystem::path two_disks(const std::filesystem::path& dir,
                                double distance, double shift = 0)
{
  const auto mesh =
      test::bodies_mesh({test::disk(0.02 + shift, 0.02, 0.01, 2),
                         test::disk(0.02 + shift + distance, 0.02, 0.01, 2)});
  test::write_body_mesh(mesh, dir / "mesh.xdmf");
  return dir / "mesh.xdmf";
}
} // namespace

TEST(RunChecks, UnconvergedStepsAreCountedAndDumpsBounded)
{
  const std::filesystem::path dir = test::fresh_directory("checks-unconv");
  // A block on the bottom wall squeezed by the top wall: one sweep and one
  // Newton iteration cannot converge to these tolerances.
  const auto mesh =
      test::bodies_mesh({test::rectangle(0.02, 0.0, 0.012, 0.008, 3, 2)});
  test::write_body_mesh(mesh, dir / "mesh.xdmf");
  json doc = test::driver_json(dir, dir / "mesh.xdmf", 1, 0.08, 0.008, 0.0);
  doc["walls"][3]["velocity"] = {0.0, -0.1};
  doc["stop"]["steps"] = 25;
  doc["output"]["every_steps"] = 10;
  doc["output"]["fields"] = false;
  doc["contact"]["nlgs_max_sweeps"] = 1;
  doc["contact"]["nlgs_tolerance"] = 1e-15;
  // The sweep this scenario was made with: in the alternate order one of
  // the 25 one-sweep steps happens to find every contact open (r = 0,
  // error 0) and converges.
  doc["contact"]["nlgs_order"] = "contact";
  doc["contact"]["nlgs_relaxation"] = 1.8;
  doc["time"]["newton_max_iterations"] = 1;
  doc["time"]["newton_tolerance"] = 1e-12;
  run(doc, dir);
  const json done = read_json(dir / "raw" / "done.json");
  EXPECT_FALSE(done.at("converged").get<bool>());
  // Every step is seen, not only the output rows (3 of 25 steps).
  EXPECT_EQ(done.at("newton_unconverged_steps"), 25);
  EXPECT_EQ(done.at("nlgs_unconverged_steps"), 25);
  const std::filesystem::path steps = dir / "raw" / "steps.csv";
  EXPECT_EQ(column_sum(steps, "newton_unconverged_steps"), 25);
  EXPECT_EQ(column_sum(steps, "nlgs_unconverged_steps"), 25);
  // At most 20 dumps; the others are counted.
  long files = 0;
  for (const auto& f : std::filesystem::directory_iterator(
           dir / "raw" / "failed_contact_problems"))
    files += f.path().extension() == ".hdf5";
  EXPECT_EQ(files, 20);
  EXPECT_EQ(done.at("failed_contact_problems_written"), 20);
  EXPECT_EQ(done.at("failed_contact_problems_not_written"), 5);
  // The run's work: one Newton iteration of one sweep per step
  EXPECT_EQ(done.at("newton_iterations"), 25);
  EXPECT_EQ(done.at("nlgs_sweeps"), 25);

  // Continued from its state for 5 steps: the totals cover the whole run,
  // and the dumps stay bounded.
  const std::filesystem::path next = test::fresh_directory("checks-next");
  doc["directory"] = next.string();
  doc["initial_state"] = (dir / "raw" / "state.bin").string();
  doc["stop"]["steps"] = 5;
  run(doc, next);
  const json more = read_json(next / "raw" / "done.json");
  EXPECT_EQ(more.at("newton_unconverged_steps"), 30);
  EXPECT_EQ(more.at("failed_contact_problems_written"), 20);
  EXPECT_EQ(more.at("failed_contact_problems_not_written"), 10);
  // ... counted for this run's steps only
  EXPECT_EQ(more.at("newton_iterations"), 5);
  EXPECT_EQ(more.at("nlgs_sweeps"), 5);
  EXPECT_FALSE(
      std::filesystem::exists(next / "raw" / "failed_contact_problems"));
  if (!HasFailure())
  {
    std::filesystem::remove_all(dir);
    std::filesystem::remove_all(next);
  }
}

TEST(RunChecks, ConvergedRunIsMarkedConverged)
{
  const std::filesystem::path dir = test::fresh_directory("checks-conv");
  json doc = test::driver_json(dir, two_disks(dir, 0.03), 2, 0.06, 0.04, 0.01);
  doc["stop"]["steps"] = 4;
  doc["output"]["fields"] = false;
  run(doc, dir);
  const json done = read_json(dir / "raw" / "done.json");
  EXPECT_TRUE(done.at("converged").get<bool>());
  EXPECT_EQ(done.at("newton_unconverged_steps"), 0);
  // No overlap beyond rounding (a contact solved to 1e-6 leaves ~1e-13 m,
  // against disks of radius 1e-2 m)
  EXPECT_LT(done.at("max_overlap_depth").get<double>(), 1e-9);
  EXPECT_FALSE(
      std::filesystem::exists(dir / "raw" / "failed_contact_problems"));
  if (!HasFailure())
    std::filesystem::remove_all(dir);
}

// Two disks overlapping by 1 mm that the detection ignores
// (max_penetration 1e-9): the detection reports no penetration, the
// boundaries show the overlap.
TEST(RunChecks, OverlapMissedByTheDetectionIsMeasured)
{
  const std::filesystem::path dir = test::fresh_directory("checks-overlap");
  json doc = test::driver_json(dir, two_disks(dir, 0.019), 2, 0.06, 0.04, 0.0);
  doc["stop"]["steps"] = 1;
  doc["output"]["every_steps"] = 1;
  doc["output"]["fields"] = false;
  doc["contact"]["max_penetration"] = 1e-9;
  run(doc, dir);
  const std::filesystem::path steps = dir / "raw" / "steps.csv";
  EXPECT_LT(column_max(steps, "max_penetration"), 1e-9);
  // The tip of one 12-gon ring inside the other: 1 mm minus the gap
  // between the other's chord and its circle, which is at most
  // R (1 - cos(pi / 12)) = 0.34 mm.
  const double depth = read_json(dir / "raw" / "done.json")
                           .at("max_overlap_depth")
                           .get<double>();
  EXPECT_GT(depth, 0.6e-3);
  EXPECT_LE(depth, 1.0e-3 + 1e-12);
  EXPECT_GE(read_json(dir / "raw" / "done.json").at("overlap_steps"), 1);
  if (!HasFailure())
    std::filesystem::remove_all(dir);
}

TEST(OverlapCheck, DepthOfNonConvexAndWalls)
{
  using simulation::Segment;
  // An L (non-convex, counter-clockwise) and a unit square whose corner
  // (1.2, 1.2) sits in the L's notch: outside the L, though inside its
  // convex hull.
  const std::vector<std::array<double, 2>> L = {{0, 0}, {2, 0}, {2, 1},
                                                {1, 1}, {1, 2}, {0, 2}};
  auto ring = [](const std::vector<std::array<double, 2>>& p)
  {
    std::vector<Segment> s;
    for (std::size_t i = 0; i < p.size(); ++i)
    {
      const auto& a = p[i];
      const auto& b = p[(i + 1) % p.size()];
      s.push_back({a[0], a[1], b[0], b[1]});
    }
    return s;
  };
  auto square = [&](double x, double y) {
    return ring({{x, y}, {x + 1, y}, {x + 1, y + 1}, {x, y + 1}});
  };
  EXPECT_EQ(simulation::max_overlap_depth({ring(L), square(1.2, 1.2)}, {}),
            0.0);
  // Moved down-left by 0.3: its corner (0.9, 0.9) is in the L, nearest to
  // the L's reflex corner (1, 1), at 0.1 sqrt(2) (the L's corner is 0.1
  // deep in the square).
  EXPECT_NEAR(simulation::max_overlap_depth({ring(L), square(0.9, 0.9)}, {}),
              0.1 * std::sqrt(2.0), 1e-14);
  // A wall y >= 0.25 (normal +y): the L's bottom is 0.25 behind it.
  dynamics::Wall wall;
  wall.point = {0, 0.25};
  wall.normal = {0, 1};
  EXPECT_NEAR(simulation::max_overlap_depth({ring(L)}, {wall}), 0.25, 1e-15);
  // In a periodic cell 5 x 5 the square at (4.9, 0.5) has an image at
  // (-0.1, 0.5), over the L: its corner (0.9, 0.5) is 0.5 inside the L (from
  // the L's bottom); unseen without the cell
  const auto cell =
      dynamics::PeriodicCell::moving({5, 0}, {0, 5}, {0, 0}, {0, 0});
  EXPECT_EQ(simulation::max_overlap_depth({ring(L), square(4.9, 0.5)}, {}),
            0.0);
  EXPECT_NEAR(
      simulation::max_overlap_depth({ring(L), square(4.9, 0.5)}, {}, &cell),
      0.5, 1e-14);
}

TEST(StateFile, RefusesCorruptedFilesAndStatesOfOtherRuns)
{
  const std::filesystem::path first = test::fresh_directory("state-first");
  json doc =
      test::driver_json(first, two_disks(first, 0.03), 2, 0.06, 0.04, 0.01);
  doc["stop"]["steps"] = 2;
  doc["output"]["fields"] = false;
  run(doc, first);
  const std::filesystem::path state = first / "raw" / "state.bin";
  ASSERT_EQ(softpack::io::read_state(state).steps, 2);

  // Another mesh: every x shifted by 5 cm.
  const std::filesystem::path next = test::fresh_directory("state-next");
  json other = doc;
  other["directory"] = next.string();
  other["initial_state"] = state.string();
  other["scene"]["bodies"]["mesh"] = two_disks(next, 0.03, 0.05).string();
  std::string e = error_of(other, next);
  EXPECT_NE(e.find("another mesh or packing"), std::string::npos) << e;
  // Other walls (the box 1 cm longer).
  other = doc;
  other["directory"] = next.string();
  other["initial_state"] = state.string();
  other["walls"][1]["point"] = {0.07, 0.0};
  e = error_of(other, next);
  EXPECT_NE(e.find("other walls"), std::string::npos) << e;
  // The same run continues.
  other["walls"] = doc["walls"];
  EXPECT_EQ(error_of(other, next), "");

  // One flipped byte in the middle.
  std::string bytes;
  {
    std::ifstream in(state, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  bytes[bytes.size() / 2] ^= 0x10;
  std::ofstream(state, std::ios::binary | std::ios::trunc) << bytes;
  e = error_of(other, next);
  EXPECT_NE(e.find("checksum mismatch"), std::string::npos) << e;
  EXPECT_NE(e.find("state.bin"), std::string::npos) << e;
  // The old layout is refused by name.
  bytes.replace(0, 16, "softpack-state-1");
  std::ofstream(state, std::ios::binary | std::ios::trunc) << bytes;
  EXPECT_NE(error_of(other, next).find("softpack-state-1"), std::string::npos);
  // So is the layout without the kept iteration matrix.
  bytes.replace(0, 16, "softpack-state-2");
  std::ofstream(state, std::ios::binary | std::ios::trunc) << bytes;
  EXPECT_NE(error_of(other, next).find("softpack-state-2"), std::string::npos);
  if (!HasFailure())
  {
    std::filesystem::remove_all(first);
    std::filesystem::remove_all(next);
  }
}

namespace
{
/// The state file at `path` rewritten as an older layout: `strip` bytes
/// of its payload's end dropped, its magic and its checksum (FNV-1a 64 over
/// the payload) replaced
void rewrite_as(const std::filesystem::path& path, const char* magic,
                std::size_t strip)
{
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  bytes.resize(bytes.size() - sizeof(std::uint64_t) - strip);
  bytes.replace(0, 16, magic);
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const char c : bytes)
    h = (h ^ static_cast<unsigned char>(c)) * 0x100000001b3ULL;
  bytes.append(reinterpret_cast<const char*>(&h), sizeof(h));
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}
} // namespace

TEST(StateFile, KeepsCellBondsWindowStartAndCohesionAndReadsLayouts7To5)
{
  const std::filesystem::path dir = test::fresh_directory("state-layout8");
  dynamics::SchemeState s;
  s.time = 0.5;
  s.steps = 7;
  s.u = s.v = {1.0, 2.0};
  s.energy.friction = 0.25;
  s.energy.cohesion = -1.5e-3;
  s.energy.cell_work = 3.5e-2;
  s.energy.rewrap = -2e-9;
  s.cell = {0.1, 0.0, 0.01, 0.2};
  s.energy.bond = 2.5e-4;
  s.bonds = {{{0, 3, 1}, 1e-5}, {{2, 8, -2}, -3e-7}};
  s.bonds_formed = true;
  s.step_size.h = 2e-4;
  s.step_size.window_start = {1e-7, 0.75};
  const std::filesystem::path path = dir / "state.bin";
  softpack::io::write_state(path, s);
  const dynamics::SchemeState back = softpack::io::read_state(path);
  EXPECT_EQ(back.energy.cohesion, -1.5e-3);
  EXPECT_EQ(back.energy.bond, 2.5e-4);
  EXPECT_EQ(back.bonds, s.bonds);
  EXPECT_TRUE(back.bonds_formed);
  EXPECT_EQ(back.energy.friction, 0.25);
  EXPECT_EQ(back.energy.cell_work, 3.5e-2);
  EXPECT_EQ(back.energy.rewrap, -2e-9);
  EXPECT_EQ(back.cell, s.cell);
  EXPECT_EQ(back.step_size.window_start.residual, 1e-7);
  EXPECT_EQ(back.step_size.window_start.supplied, 0.75);

  // Layout 7: without the bonds (formed flag, count: two int64; no entry
  // here) and the bond account (nor layout 9's internal variables: their
  // account and two counts, no values here)
  s.bonds.clear();
  softpack::io::write_state(path, s);
  const std::size_t bonds = 2 * sizeof(std::int64_t) + sizeof(double) +
                            sizeof(double) + 2 * sizeof(std::int64_t);
  rewrite_as(path, "softpack-state-7", bonds);
  const dynamics::SchemeState seven = softpack::io::read_state(path);
  EXPECT_EQ(seven.energy.bond, 0.0);
  EXPECT_TRUE(seven.bonds.empty());
  EXPECT_FALSE(seven.bonds_formed);
  EXPECT_EQ(seven.energy.cell_work, 3.5e-2);
  EXPECT_EQ(seven.cell, s.cell);

  // Layout 6: also without the cell's accounts, its size and its 4 numbers
  s.cell.clear();
  softpack::io::write_state(path, s);
  const std::size_t cell = 3 * sizeof(double);
  rewrite_as(path, "softpack-state-6", bonds + cell);
  const dynamics::SchemeState six = softpack::io::read_state(path);
  EXPECT_EQ(six.energy.cohesion, -1.5e-3);
  EXPECT_EQ(six.energy.cell_work, 0.0);
  EXPECT_TRUE(six.cell.empty());
  EXPECT_EQ(six.step_size.window_start.supplied, 0.75);

  // Layout 5: also without the trailing window start and cohesion (three
  // doubles)
  softpack::io::write_state(path, s);
  rewrite_as(path, "softpack-state-5", bonds + cell + 3 * sizeof(double));
  const dynamics::SchemeState old = softpack::io::read_state(path);
  EXPECT_EQ(old.energy.cohesion, 0.0);
  EXPECT_EQ(old.energy.friction, 0.25);
  EXPECT_EQ(old.steps, 7);
  EXPECT_EQ(old.step_size.h, 2e-4);
  EXPECT_TRUE(std::isnan(old.step_size.window_start.residual));
  EXPECT_TRUE(std::isnan(old.step_size.window_start.supplied));
  if (!HasFailure())
    std::filesystem::remove_all(dir);
}

TEST(StateFile, KeepsInternalVariablesAndReadsLayout8WithoutThem)
{
  const std::filesystem::path dir = test::fresh_directory("state-layout9");
  dynamics::SchemeState s;
  s.u = s.v = {1.0, 2.0};
  s.energy.bond = 2.5e-4;
  s.energy.viscous = 0.125;
  s.internal = {1.0, 0.1, 0.9, 1.05, 1.0, 0.0, 1.0, 1.0};
  s.internal_tangent = {1.0, 0.0, 1.0, 1.0, 0.99, 0.02, 1.01, 1.0};
  s.matrix_age = 2;
  s.u_tangent = {0.5, 0.25};
  const std::filesystem::path path = dir / "state.bin";
  softpack::io::write_state(path, s);
  const dynamics::SchemeState back = softpack::io::read_state(path);
  EXPECT_EQ(back.energy.viscous, 0.125);
  EXPECT_EQ(back.internal, s.internal);
  EXPECT_EQ(back.internal_tangent, s.internal_tangent);
  EXPECT_EQ(back.energy.bond, 2.5e-4);

  // Layout 8: without them (the account and two counts; no values)
  s.internal.clear();
  s.internal_tangent.clear();
  softpack::io::write_state(path, s);
  rewrite_as(path, "softpack-state-8",
             sizeof(double) + 2 * sizeof(std::int64_t));
  const dynamics::SchemeState eight = softpack::io::read_state(path);
  EXPECT_EQ(eight.energy.viscous, 0.0);
  EXPECT_TRUE(eight.internal.empty());
  EXPECT_EQ(eight.energy.bond, 2.5e-4);
  EXPECT_EQ(eight.u_tangent, s.u_tangent);
  if (!HasFailure())
    std::filesystem::remove_all(dir);
}
