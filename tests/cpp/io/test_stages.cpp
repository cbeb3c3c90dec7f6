// Loading stages in driver.json (docs/loading.md): read with every key (a
// stage's friction too), bad drives and stop keys refused naming the key
// path; the box's wall pressure and a wall's facing distance against values
// by hand.
#include "read_driver_json.h"
#include <gtest/gtest.h>
#include <io/driver_config.h>
#include <simulation/stages.h>
#include <stdexcept>

using namespace softpack;
using nlohmann::json;

namespace
{
json two_stages()
{
  json doc = test::driver_json("/runs/stages", "/runs/mesh.xdmf", 3);
  doc["stop"]["packing_fraction"] = 0.0;
  const json stop = {{"packing_fraction", 0.0}, {"strain", 0.0},
                     {"strain_wall", ""},       {"pressure", 0.0},
                     {"equilibrium", 1e-3},     {"max_time", 0.5}};
  doc["stages"] = json::array();
  doc["stages"].push_back({{"name", "consolidate"},
                           {"bond", false},
                           {"walls",
                            {{"top",
                              {{"control", "pressure"},
                               {"velocity", {0.0, 0.0}},
                               {"pressure", 1e4},
                               {"force", 0.0}}}}},
                           {"contact", {{"friction", 0.0}}},
                           {"cell", test::stage_cell()},
                           {"stop", stop}});
  json axial = stop;
  axial["strain"] = 0.1;
  axial["strain_wall"] = "right";
  axial["equilibrium"] = 0.0;
  doc["stages"].push_back({{"name", "axial"},
                           {"bond", false},
                           {"walls",
                            {{"right",
                              {{"control", "velocity"},
                               {"velocity", {-0.1, 0.0}},
                               {"pressure", 0.0},
                               {"force", 0.0}}}}},
                           {"contact", {{"friction", 0.3}}},
                           {"cell", test::stage_cell()},
                           {"stop", axial}});
  return doc;
}

std::string error_of(const json& doc)
{
  return test::driver_json_error(doc, "stages-config");
}

softpack::io::DriverConfig read(const json& doc)
{
  return test::read_driver_json(doc, "stages-config");
}
} // namespace

TEST(Stages, AreReadWithTheirWallsAndStopKeys)
{
  const softpack::io::DriverConfig c = read(two_stages());
  ASSERT_EQ(c.stages.size(), 2u);
  EXPECT_EQ(c.stages[0].name, "consolidate");
  ASSERT_EQ(c.stages[0].walls.size(), 1u);
  const dynamics::WallDrive& top = c.stages[0].walls.at("top");
  EXPECT_EQ(top.control, dynamics::WallControl::pressure);
  EXPECT_EQ(top.pressure, 1e4);
  EXPECT_EQ(c.stages[0].stop.equilibrium, 1e-3);
  EXPECT_EQ(c.stages[1].stop.strain_wall, "right");
  EXPECT_EQ(c.stages[1].stop.strain, 0.1);
  EXPECT_EQ(c.stages[0].contact.friction, 0.0);
  EXPECT_EQ(c.stages[1].contact.friction, 0.3);
  // the Newton test's velocity scale sees the stages' speeds
  EXPECT_EQ(c.velocity_scale, 0.1);
}

TEST(Stages, NoneIsAnEmptyList)
{
  json doc = test::driver_json("/runs/stages", "/runs/mesh.xdmf", 3);
  doc["stages"] = json::array();
  EXPECT_TRUE(read(doc).stages.empty());
}

TEST(Stages, BadOnesAreRefusedNamingTheKey)
{
  json doc = two_stages();
  doc["stages"][0]["walls"]["top"]["velocity"] = {0.0, -0.1};
  EXPECT_NE(error_of(doc).find("stages[0].walls.top: a wall is driven by "
                               "one of velocity, pressure or force"),
            std::string::npos)
      << error_of(doc);
  doc = two_stages();
  doc["stages"][0]["walls"]["top"]["control"] = "stress";
  EXPECT_NE(error_of(doc).find("stages[0].walls.top.control: = \"stress\" is "
                               "not one of \"velocity\", \"pressure\", "
                               "\"force\""),
            std::string::npos)
      << error_of(doc);
  doc = two_stages();
  doc["stages"][0]["walls"]["top"]["pressure"] = -1.0;
  EXPECT_NE(error_of(doc).find("stages[0].walls.top.pressure"),
            std::string::npos);
  doc = two_stages();
  doc["stages"][0]["name"] = "";
  EXPECT_NE(error_of(doc).find("stages[0].name"), std::string::npos);
  doc = two_stages();
  doc["stages"][1]["walls"]["lid"] = doc["stages"][1]["walls"]["right"];
  EXPECT_NE(error_of(doc).find("stages[1].walls.lid: no such wall"),
            std::string::npos);
  doc = two_stages();
  doc["stages"][1]["stop"].erase("max_time");
  EXPECT_NE(error_of(doc).find("stages[1].stop.max_time: missing"),
            std::string::npos);
  doc = two_stages();
  doc["stages"][1]["stop"]["max_time"] = 0.0;
  EXPECT_NE(error_of(doc).find("stages[1].stop.max_time"), std::string::npos);
  doc = two_stages();
  doc["stages"][1]["stop"]["strain_wall"] = "lid";
  EXPECT_NE(error_of(doc).find("stages[1].stop.strain_wall"),
            std::string::npos);
  doc = two_stages();
  doc["stages"][1]["contact"]["friction"] = -0.1;
  EXPECT_NE(error_of(doc).find("stages[1].contact.friction"), std::string::npos)
      << error_of(doc);
  doc = two_stages();
  doc["stages"][0].erase("contact");
  EXPECT_NE(error_of(doc).find("stages[0].contact"), std::string::npos)
      << error_of(doc);
  doc = two_stages();
  doc["stop"]["packing_fraction"] = 0.88;
  EXPECT_NE(error_of(doc).find("stop.packing_fraction"), std::string::npos);
}

TEST(Stages, BoxPressureAndFacingDistanceByHand)
{
  // A 0.2 x 0.1 box whose right wall moved to x = 0.18.
  std::vector<dynamics::Wall> walls =
      dynamics::box_walls(0.0, 0.2, 0.0, 0.1, 0.0);
  walls[1].name = "right";
  walls[1].point = {0.18, 0.0};
  EXPECT_DOUBLE_EQ(simulation::facing_distance(walls, 1), 0.18);
  EXPECT_DOUBLE_EQ(simulation::facing_distance(walls, 2), 0.1);
  EXPECT_EQ(simulation::facing_wall(walls, 0), 1);
  // Forces received: pushed outward, along -normal; sxx = (F_l + F_r) /
  // (2 x 0.1), syy = (F_b + F_t) / (2 x 0.18).
  const std::vector<std::array<double, 2>> f = {
      {-100.0, 0.0}, {120.0, 0.0}, {0.0, -90.0}, {0.0, 90.0}};
  const double sxx = 220.0 / 0.2, syy = 180.0 / 0.36;
  EXPECT_NEAR(simulation::box_pressure(walls, f), 0.5 * (sxx + syy), 1e-9);
}
