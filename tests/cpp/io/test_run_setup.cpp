// A tiny run through the driver: raw/setup.json describes the run (every
// body's reference area is its boundary polygon's), stop.steps ends it, and
// a run from its state continues for stop.steps more.
#include "driver_json.h"
#include "mesh_fixtures.h"
#include <cmath>
#include <contact/fclib_io.h>
#include <gtest/gtest.h>
#include <io/driver_config.h>
#include <io/state_file.h>
#include <numbers>
#include <simulation/run_simulation.h>
#include <sstream>

using namespace softpack;
using nlohmann::json;

namespace
{
constexpr double R = 0.01;
constexpr int rings = 2;

json read_json(const std::filesystem::path& path)
{
  std::ifstream in(path);
  return json::parse(in);
}

/// The header and last row of a CSV file.
std::pair<std::vector<std::string>, std::vector<std::string>>
header_and_last_row(const std::filesystem::path& path)
{
  std::ifstream in(path);
  std::string line, last;
  std::getline(in, line);
  auto split = [](const std::string& s)
  {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string cell; std::getline(ss, cell, ',');)
      out.push_back(cell);
    return out;
  };
  const std::vector<std::string> header = split(line);
  while (std::getline(in, line))
    if (!line.empty())
      last = line;
  return {header, split(last)};
}

std::string column(
    const std::pair<std::vector<std::string>, std::vector<std::string>>& table,
    const std::string& name)
{
  const auto& [header, row] = table;
  const auto it = std::find(header.begin(), header.end(), name);
  return it == header.end() ? "" : row.at(it - header.begin());
}

/// Two disks and a rectangle in a 0.08 x 0.04 box, written as a mesh file.
std::filesystem::path tiny_mesh(const std::filesystem::path& dir)
{
  const auto mesh = test::bodies_mesh(
      {test::disk(0.015, 0.015, R, rings), test::disk(0.040, 0.015, R, rings),
       test::rectangle(0.055, 0.005, 0.012, 0.008, 3, 2)});
  test::write_body_mesh(mesh, dir / "mesh.xdmf");
  return dir / "mesh.xdmf";
}
} // namespace

TEST(RunSetup, SetupDescribesTheRunAndStepsStopIt)
{
  const std::filesystem::path dir = test::fresh_directory("run-setup");
  json doc = test::driver_json(dir, tiny_mesh(dir), 3, 0.08, 0.04, 0.01);
  doc["stop"]["steps"] = 3;
  doc["output"]["every_steps"] = 2;
  test::write_json(doc, dir / "driver.json");
  const softpack::io::DriverConfig config =
      softpack::io::read_driver_config(dir / "driver.json");
  const auto summary =
      simulation::run_simulation(MPI_COMM_WORLD, config, /*quiet=*/true);
  EXPECT_EQ(summary.steps, 3);
  EXPECT_EQ(summary.reason, "steps");

  const json setup = read_json(dir / "raw" / "setup.json");
  EXPECT_EQ(setup.at("schema_version"), 2);
  EXPECT_EQ(setup.at("scene"), doc.at("scene"));
  EXPECT_EQ(setup.at("material"), doc.at("material"));
  EXPECT_EQ(setup.at("walls"), doc.at("walls"));
  EXPECT_EQ(setup.at("stages"), json::array());
  EXPECT_TRUE(setup.at("initial_state").is_null());
  for (const char* s :
       {"stop", "contact", "time", "damping", "output", "parallel"})
    EXPECT_EQ(setup.at("parameters").at(s), doc.at(s)) << s;
  EXPECT_EQ(setup.at("units").at("force"), "N/m");

  const json& bodies = setup.at("bodies");
  EXPECT_EQ(bodies.at("count"), 3);
  EXPECT_EQ(bodies.at("species"), (std::vector<int>{0, 0, 0}));
  // Ring n of the disk fixture has 6n nodes on the circle: the boundary
  // polygon is a regular 6n-gon of circumradius R.
  const int N = 6 * rings;
  const double polygon = 0.5 * N * R * R * std::sin(2 * std::numbers::pi / N);
  const auto& area = bodies.at("reference_area");
  EXPECT_NEAR(area[0].get<double>(), polygon, 1e-15);
  EXPECT_NEAR(area[1].get<double>(), polygon, 1e-15);
  EXPECT_NEAR(area[2].get<double>(), 0.012 * 0.008, 1e-15);
  EXPECT_EQ(bodies.at("nodes"), (std::vector<int>{19, 19, 12}));
  EXPECT_EQ(bodies.at("triangles"), (std::vector<int>{24, 24, 12}));

  const json done = read_json(dir / "raw" / "done.json");
  EXPECT_EQ(done.at("reason"), "steps");
  EXPECT_EQ(done.at("steps"), 3);
  // Walls are named as in the scene: the moving one is "right".
  const auto steps = header_and_last_row(dir / "raw" / "steps.csv");
  EXPECT_EQ(column(steps, "step"), "3");
  EXPECT_NEAR(std::stod(column(steps, "right_x")), 0.08 - 3 * 7.2e-5 * 0.01,
              1e-15);
  EXPECT_NE(column(steps, "right_fx"), "");
  // The state's time is in the steps.csv of the run that wrote it.
  const dynamics::SchemeState state =
      softpack::io::read_state(dir / "raw" / "state.bin");
  EXPECT_EQ(state.steps, 3);
  EXPECT_EQ(std::stod(column(steps, "time")), state.time);
  EXPECT_TRUE(std::filesystem::exists(dir / "fields.xdmf"));
  if (!HasFailure())
    std::filesystem::remove_all(dir);
}

TEST(RunSetup, StepsCountFromTheInitialState)
{
  const std::filesystem::path first = test::fresh_directory("run-first");
  json doc = test::driver_json(first, tiny_mesh(first), 3, 0.08, 0.04, 0.01);
  doc["stop"]["steps"] = 2;
  doc["output"]["fields"] = false;
  test::write_json(doc, first / "driver.json");
  simulation::run_simulation(
      MPI_COMM_WORLD, softpack::io::read_driver_config(first / "driver.json"),
      true);

  const std::filesystem::path next = test::fresh_directory("run-next");
  doc["directory"] = next.string();
  doc["initial_state"] = (first / "raw" / "state.bin").string();
  doc["stop"]["steps"] = 3;
  test::write_json(doc, next / "driver.json");
  const auto summary = simulation::run_simulation(
      MPI_COMM_WORLD, softpack::io::read_driver_config(next / "driver.json"),
      true);
  EXPECT_EQ(summary.steps, 5);
  EXPECT_EQ(summary.reason, "steps");
  EXPECT_EQ(read_json(next / "raw" / "setup.json").at("initial_state"),
            doc.at("initial_state"));
  EXPECT_FALSE(std::filesystem::exists(next / "fields.xdmf"));
  if (!HasFailure())
  {
    std::filesystem::remove_all(first);
    std::filesystem::remove_all(next);
  }
}

// A run with stages describes its loading program: each stage's name, wall
// drives and stop keys, as driver.json gave them.
TEST(RunSetup, SetupRecordsTheStages)
{
  const std::filesystem::path dir = test::fresh_directory("run-stages");
  json doc = test::driver_json(dir, tiny_mesh(dir), 3, 0.08, 0.04, 0.01);
  doc["stop"]["packing_fraction"] = 0.0;
  doc["stop"]["steps"] = 1;
  doc["output"]["fields"] = false;
  const json stop = {{"packing_fraction", 0.0}, {"strain", 0.05},
                     {"strain_wall", "right"},  {"pressure", 0.0},
                     {"equilibrium", 0.0},      {"max_time", 0.5}};
  json press = {{"name", "press"},
                {"bond", false},
                {"walls",
                 {{"right",
                   {{"control", "velocity"},
                    {"velocity", {-0.02, 0.0}},
                    {"pressure", 0.0},
                    {"force", 0.0}}}}},
                {"contact", {{"friction", 0.3}}},
                {"cell", test::stage_cell()},
                {"stop", stop}};
  json hold = press;
  hold["name"] = "hold";
  hold["walls"]["right"]["control"] = "force";
  hold["walls"]["right"]["velocity"] = {0.0, 0.0};
  hold["walls"]["right"]["force"] = 10.0;
  hold["stop"]["strain"] = 0.0;
  hold["stop"]["strain_wall"] = "";
  hold["stop"]["equilibrium"] = 1e-3;
  hold["contact"]["friction"] = 0.0;
  doc["stages"] = json::array({press, hold});
  test::write_json(doc, dir / "driver.json");
  simulation::run_simulation(
      MPI_COMM_WORLD, softpack::io::read_driver_config(dir / "driver.json"),
      true);
  const json stages = read_json(dir / "raw" / "setup.json").at("stages");
  ASSERT_EQ(stages.size(), 2u);
  EXPECT_EQ(stages[0].at("name"), "press");
  EXPECT_EQ(stages[0].at("walls").at("right").at("velocity"),
            json({-0.02, 0.0}));
  EXPECT_EQ(stages[0].at("stop").at("strain_wall"), "right");
  EXPECT_EQ(stages[1].at("walls").at("right").at("control"), "force");
  EXPECT_EQ(stages[1].at("contact").at("friction"), 0.0);
  EXPECT_EQ(stages[1].at("stop").at("equilibrium"), 1e-3);
  EXPECT_EQ(stages, doc.at("stages"));
  if (!HasFailure())
    std::filesystem::remove_all(dir);
}

TEST(RunSetup, MaterialErrorsNameTheFileAndTheKey)
{
  const std::filesystem::path dir = test::fresh_directory("run-material");
  json doc = test::driver_json(dir, tiny_mesh(dir), 3, 0.08, 0.04, 0.01);
  auto error_of = [&](const json& d)
  {
    test::write_json(d, dir / "driver.json");
    try
    {
      simulation::run_simulation(
          MPI_COMM_WORLD, softpack::io::read_driver_config(dir / "driver.json"),
          true);
    }
    catch (const std::runtime_error& e)
    {
      return std::string(e.what());
    }
    return std::string();
  };
  json bad = doc;
  bad["material"]["parameters"] = {{"mu", 1.5e5}, {"lame_lambda", 3e5}};
  std::string e = error_of(bad);
  EXPECT_NE(e.find("driver.json: material.parameters."), std::string::npos)
      << e;
  EXPECT_NE(e.find("shear_modulus, lame_lambda"), std::string::npos) << e;
  bad = doc;
  bad["material"]["law"] = "rubber";
  e = error_of(bad);
  EXPECT_NE(e.find("material.law"), std::string::npos) << e;
  EXPECT_NE(e.find("neo_hookean"), std::string::npos) << e;
  bad = doc;
  bad["scene"]["bodies"]["species"] = {0, 0};
  bad["scene"]["species"][0]["count"] = 2;
  e = error_of(bad);
  EXPECT_NE(e.find("scene.bodies.species"), std::string::npos) << e;
  if (!HasFailure())
    std::filesystem::remove_all(dir);
}

// A contact problem the NLGS leaves unsolved is written by the run loop as
// raw/failed_contact_problems/step_NNNNNNNN.hdf5 and reads back as an FCLIB
// problem with the contacts of that step.
TEST(RunSetup, UnsolvedContactProblemsAreWrittenForReplay)
{
  const std::filesystem::path dir = test::fresh_directory("run-unsolved");
  // A block pressed 10 um into the bottom wall: four coupled contacts that
  // one Gauss-Seidel sweep cannot solve to 1e-15.
  const auto mesh =
      test::bodies_mesh({test::rectangle(0.02, -1e-5, 0.012, 0.008, 3, 2)});
  test::write_body_mesh(mesh, dir / "mesh.xdmf");
  json doc = test::driver_json(dir, dir / "mesh.xdmf", 1, 0.08, 0.04, 0.01);
  doc["stop"]["steps"] = 2;
  doc["contact"]["nlgs_max_sweeps"] = 1;
  doc["contact"]["nlgs_tolerance"] = 1e-15;
  doc["output"]["fields"] = false;
  test::write_json(doc, dir / "driver.json");
  simulation::run_simulation(
      MPI_COMM_WORLD, softpack::io::read_driver_config(dir / "driver.json"),
      true);
  const std::filesystem::path file =
      dir / "raw" / "failed_contact_problems" / "step_00000001.hdf5";
  ASSERT_TRUE(std::filesystem::exists(file));
  const contact::FclibLocalFile problem = contact::read_fclib_local_file(file);
  EXPECT_EQ(problem.problem.num_contacts(), 4u);
  EXPECT_TRUE(problem.guess_r);
  if (!HasFailure())
    std::filesystem::remove_all(dir);
}
