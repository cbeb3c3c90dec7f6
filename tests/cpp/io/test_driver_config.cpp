// driver.json (docs/contract.md section 4): every key required, unknown keys
// refused at every level the driver owns, the sections read back unchanged.
#include "read_driver_json.h"
#include <gtest/gtest.h>
#include <io/driver_config.h>
#include <stdexcept>

using namespace softpack;
using nlohmann::json;

namespace
{
json paper()
{
  return test::driver_json("/runs/paper", "/runs/mesh.xdmf", 3);
}

io::DriverConfig read(const json& doc)
{
  return test::read_driver_json(doc, "driver-config");
}

/// The message of the error reading `doc`, "" if it is accepted.
std::string error_of(const json& doc)
{
  return test::driver_json_error(doc, "driver-config");
}

void expect_refused(const json& doc, const std::string& key)
{
  const std::string e = error_of(doc);
  EXPECT_NE(e.find(key), std::string::npos) << "expected " << key << ": " << e;
  EXPECT_NE(e.find("driver.json"), std::string::npos) << e;
}
} // namespace

TEST(DriverConfig, RoundTrip)
{
  const json doc = paper();
  const io::DriverConfig c = read(doc);
  const json sections = parameters::to_json(c.parameters);
  for (const char* s :
       {"stop", "contact", "time", "damping", "output", "parallel", "material"})
    EXPECT_EQ(sections.at(s), doc.at(s)) << s;
  EXPECT_EQ(c.scene, doc.at("scene"));
  EXPECT_EQ(c.directory, "/runs/paper");
  EXPECT_EQ(c.mesh, "/runs/mesh.xdmf");
  EXPECT_EQ(c.body_species, (std::vector<int>{0, 0, 0}));
  EXPECT_FALSE(c.initial_state);
  EXPECT_TRUE(c.box);
  ASSERT_EQ(c.walls.size(), 4u);
  EXPECT_EQ(c.walls[1].name, "right");
  EXPECT_EQ(c.walls[1].point, (std::array<double, 2>{0.286, 0}));
  // The paper's Newton scale was the piston speed.
  EXPECT_EQ(c.velocity_scale, 0.1);
}

TEST(DriverConfig, WallsKeepTheirOrderAndNormalsAreNormalised)
{
  json doc = paper();
  doc["walls"].push_back({{"name", "slope"},
                          {"point", {0.1, 0.0}},
                          {"normal", {3.0, 4.0}},
                          {"velocity", {0.0, 0.25}},
                          {"control", "velocity"},
                          {"pressure", 0.0},
                          {"force", 0.0},
                          {"mass", 1.0}});
  const io::DriverConfig c = read(doc);
  ASSERT_EQ(c.walls.size(), 5u);
  EXPECT_EQ(c.walls[4].name, "slope");
  EXPECT_DOUBLE_EQ(c.walls[4].normal[0], 0.6);
  EXPECT_DOUBLE_EQ(c.walls[4].normal[1], 0.8);
  EXPECT_EQ(c.velocity_scale, 0.25); // the fastest wall
  doc = paper();
  doc["walls"][1]["velocity"] = {0.0, 0.0};
  EXPECT_EQ(read(doc).velocity_scale, 1e-3); // every wall fixed
  doc["walls"][1]["normal"] = {0.0, 0.0};
  expect_refused(doc, "walls[1].normal");
}

TEST(DriverConfig, MissingKeysAreRefused)
{
  for (const char* key :
       {"schema_version", "directory", "initial_state", "scene", "material",
        "walls", "stop", "contact", "time", "damping", "output", "parallel"})
  {
    json doc = paper();
    doc.erase(key);
    expect_refused(doc, key);
  }
  json doc = paper();
  doc["scene"].erase("packing");
  expect_refused(doc, "scene.packing");
  doc = paper();
  doc["scene"]["bodies"].erase("species");
  expect_refused(doc, "scene.bodies.species");
  doc = paper();
  doc["walls"][2].erase("velocity");
  expect_refused(doc, "walls[2].velocity");
  doc = paper();
  doc["material"].erase("parameters");
  expect_refused(doc, "material.parameters");
  doc = paper();
  doc["time"].erase("theta");
  expect_refused(doc, "time.theta");
}

TEST(DriverConfig, UnknownKeysAreRefused)
{
  json doc = paper();
  doc["velocity_scale"] = 0.1;
  expect_refused(doc, "velocity_scale");
  doc = paper();
  doc["scene"]["gravity"] = 9.81;
  expect_refused(doc, "scene.gravity");
  doc = paper();
  doc["walls"][0]["friction"] = 0.1;
  expect_refused(doc, "walls[0].friction");
  doc = paper();
  doc["material"]["name"] = "neo_hookean";
  expect_refused(doc, "material.name");
  doc = paper();
  doc["output"]["directory"] = "/tmp";
  expect_refused(doc, "output.directory");
}

TEST(DriverConfig, SchemaVersionMustBeTwo)
{
  json doc = paper();
  doc["schema_version"] = 1;
  expect_refused(doc, "schema_version");
}

TEST(DriverConfig, BoxNeedsItsFourWalls)
{
  json doc = paper();
  doc["walls"].erase(3);
  const std::string e = error_of(doc);
  EXPECT_NE(e.find("\"top\""), std::string::npos) << e;
  // Without a box: no Phi, so no packing-fraction criterion.
  doc["scene"]["box"]["enabled"] = false;
  expect_refused(doc, "stop.packing_fraction");
  doc["stop"]["packing_fraction"] = 0;
  const io::DriverConfig c = read(doc);
  EXPECT_FALSE(c.box);
  EXPECT_EQ(c.walls.size(), 3u);
}

TEST(DriverConfig, BodySpeciesAreIndicesOfTheSpecies)
{
  json doc = paper();
  doc["scene"]["bodies"]["species"][2] = 1; // one species only
  expect_refused(doc, "scene.bodies.species[2]");
  doc["scene"]["bodies"]["species"][2] = -1;
  expect_refused(doc, "scene.bodies.species[2]");
  const io::DriverConfig c = read(paper());
  EXPECT_NO_THROW(io::check_body_count(c, 3));
  EXPECT_THROW(io::check_body_count(c, 4), std::runtime_error);
}

TEST(DriverConfig, InitialStateIsAPathOrNull)
{
  json doc = paper();
  doc["initial_state"] = "/runs/old/raw/state.bin";
  EXPECT_EQ(read(doc).initial_state, "/runs/old/raw/state.bin");
  doc["initial_state"] = 3;
  expect_refused(doc, "initial_state");
}

TEST(DriverConfig, ServoWallsAreReadAndBadOnesRefusedNamingTheKey)
{
  json doc = paper();
  doc["walls"][1]["control"] = "pressure";
  doc["walls"][1]["pressure"] = 4000.0;
  doc["walls"][1]["mass"] = 7.0;
  // a wall is driven by one of velocity, pressure or force, as in a stage
  const std::string twice = error_of(doc);
  EXPECT_NE(twice.find("walls[1]: a wall is driven by one of velocity, "
                       "pressure or force"),
            std::string::npos)
      << twice;
  doc["walls"][1]["velocity"] = {0.0, 0.0};
  const io::DriverConfig c = read(doc);
  EXPECT_EQ(c.walls[1].control, dynamics::WallControl::pressure);
  EXPECT_EQ(c.walls[1].pressure, 4000.0);
  EXPECT_EQ(c.walls[1].mass, 7.0);
  doc["walls"][1]["mass"] = 0.0;
  expect_refused(doc, "walls[1].mass");
  doc["walls"][1]["control"] = "stress";
  expect_refused(doc, "walls[1].control");
  doc = paper();
  doc["walls"][0]["force"] = "large";
  expect_refused(doc, "walls[0].force");
}
