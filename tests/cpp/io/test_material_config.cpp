// Materials and friction per species as driver.json gives them
// (docs/materials.md, driver/io/material_config.cpp): each body takes its
// species' material, each contact the Coulomb coefficient of its pair
// (species-species, species-wall, species-"walls"), every pair not named the
// default; a name that matches nothing is refused naming driver.json and the
// key.
#include "read_driver_json.h"
#include <detection/detection.h>
#include <gtest/gtest.h>
#include <material_registry.h>

using namespace softpack;
using nlohmann::json;

namespace
{
/// A Signorini–Coulomb [[friction]] pair as driver.json has it
json pair(const char* species, const char* against, double coefficient)
{
  return {{"species", species},
          {"against", against},
          {"coefficient", coefficient},
          {"law", "coulomb"},
          {"cohesion", 0.0},
          {"cohesive_distance", 0.0},
          {"tensile_strength", 0.0},
          {"shear_strength", 0.0},
          {"bonding_distance", 0.0}};
}

/// Body 0 of species "soft" (the default material), bodies 1 and 2 of
/// species "hard" (materials[0], "stiff"); three friction pairs; walls
/// left, right, bottom, top (indices 0-3); [contact] friction 0.3.
json two_species()
{
  json doc = test::driver_json("/runs/materials", "/runs/mesh.xdmf", 3);
  json& species = doc["scene"]["species"];
  species[0]["name"] = "soft";
  species[0]["count"] = 1;
  species[0]["material"] = "";
  json hard = species[0];
  hard["name"] = "hard";
  hard["count"] = 2;
  hard["material"] = "stiff";
  species.push_back(hard);
  doc["scene"]["bodies"]["species"] = {0, 1, 1};
  doc["materials"] = json::array(
      {{{"name", "stiff"},
        {"law", "saint_venant_kirchhoff"},
        {"density", 3000.0},
        {"rigid", false},
        {"parameters", {{"shear_modulus", 1e6}, {"lame_lambda", 2e6}}}}});
  doc["friction"] =
      json::array({pair("soft", "hard", 0.1), pair("hard", "right", 0.7),
                   pair("soft", "walls", 0.5)});
  return doc;
}

softpack::io::DriverConfig read(const json& doc)
{
  return test::read_driver_json(doc, "material-config");
}

/// The message refusing `doc`; checks it names driver.json and `key`.
std::string refused(const json& doc, const std::string& key)
{
  const std::string e = test::driver_json_error(doc, "material-config");
  EXPECT_NE(e.find("driver.json: " + key + ": "), std::string::npos)
      << "expected " << key << ": " << e;
  return e;
}

dynamics::Contact between_bodies(int candidate, int antagonist)
{
  dynamics::Contact c{};
  c.candidate_body = candidate;
  c.antagonist_body = antagonist;
  c.wall = -1;
  return c;
}

dynamics::Contact against_wall(int candidate, int wall)
{
  dynamics::Contact c{};
  c.candidate_body = candidate;
  c.antagonist_body = -1;
  c.wall = wall;
  return c;
}
} // namespace

TEST(MaterialConfig, EachBodyTakesItsSpeciesMaterial)
{
  const softpack::io::BodyMaterials m = read(two_species()).body_materials;
  ASSERT_EQ(m.materials.size(), 2u);
  // materials[0] is the default `material`, then driver.json's materials
  EXPECT_EQ(m.materials[0].name, "material");
  EXPECT_EQ(m.materials[0].law, &forms::find_material("neo_hookean"));
  EXPECT_EQ(m.materials[0].density, 1180.0);
  EXPECT_EQ(m.materials[1].name, "materials[0]");
  EXPECT_EQ(m.materials[1].law,
            &forms::find_material("saint_venant_kirchhoff"));
  EXPECT_EQ(m.materials[1].density, 3000.0);
  EXPECT_EQ(m.materials[1].parameters.at("shear_modulus"), 1e6);
  EXPECT_FALSE(m.materials[1].rigid);
  EXPECT_EQ(m.body_material, (std::vector<int>{0, 1, 1}));
}

TEST(MaterialConfig, EveryPairTakesItsCoefficientOrTheDefault)
{
  const io::DriverConfig c = read(two_species());
  const dynamics::FrictionTable& f = c.friction;
  // the default is contact.friction's, stored there only
  const double mu = c.parameters.contact.friction;
  EXPECT_EQ(mu, 0.3);
  // species pair, in both orders
  EXPECT_EQ(f(between_bodies(0, 1), mu), 0.1);
  EXPECT_EQ(f(between_bodies(2, 0), mu), 0.1);
  // a pair not named: the default
  EXPECT_EQ(f(between_bodies(1, 2), mu), 0.3);
  // a species against one wall by name; its other walls keep the default
  EXPECT_EQ(f(against_wall(1, 1), mu), 0.7);
  EXPECT_EQ(f(against_wall(2, 0), mu), 0.3);
  EXPECT_EQ(f(against_wall(2, 3), mu), 0.3);
  // "walls": every wall
  for (int w = 0; w < 4; ++w)
    EXPECT_EQ(f(against_wall(0, w), mu), 0.5) << "wall " << w;

  json none = two_species();
  none["friction"] = json::array();
  const dynamics::FrictionTable d = read(none).friction;
  // A table with no pair set (0.5: the default is the caller's)
  EXPECT_EQ(d(between_bodies(0, 1), 0.5), 0.5);
  EXPECT_EQ(d(against_wall(0, 2), 0.5), 0.5);
  EXPECT_FALSE(f.cohesive());
}

TEST(MaterialConfig, ACohesivePairCarriesItsCohesion)
{
  json doc = two_species();
  doc["friction"][1]["law"] = "cohesive";
  doc["friction"][1]["cohesion"] = 2e3;
  doc["friction"][1]["cohesive_distance"] = 5e-5;
  const dynamics::FrictionTable f = read(doc).friction;
  ASSERT_TRUE(f.cohesive());
  EXPECT_EQ(f(against_wall(1, 1), 0.3), 0.7);
  EXPECT_EQ(f.cohesion(against_wall(1, 1)).traction, 2e3);
  EXPECT_EQ(f.cohesion(against_wall(1, 1)).distance, 5e-5);
  // the other pairs have none
  EXPECT_EQ(f.cohesion(against_wall(1, 0)).traction, 0.0);
  EXPECT_EQ(f.cohesion(between_bodies(0, 1)).traction, 0.0);

  doc["friction"][1]["cohesion"] = 0.0;
  refused(doc, "friction[1].cohesion");
  doc["friction"][1]["law"] = "coulomb";
  doc["friction"][1]["cohesion"] = 1.0;
  refused(doc, "friction[1]");
  doc["friction"][1]["law"] = "glue";
  const std::string law = refused(doc, "friction[1].law");
  EXPECT_NE(law.find("cohesive"), std::string::npos) << law;
}

TEST(MaterialConfig, ABondedPairCarriesItsStrengths)
{
  json doc = two_species();
  doc["friction"][1]["law"] = "bonded";
  doc["friction"][1]["tensile_strength"] = 2e4;
  doc["friction"][1]["shear_strength"] = 1e4;
  doc["friction"][1]["bonding_distance"] = 5e-5;
  const dynamics::FrictionTable f = read(doc).friction;
  ASSERT_TRUE(f.bonded());
  EXPECT_FALSE(f.cohesive());
  EXPECT_EQ(f(against_wall(1, 1), 0.3), 0.7);
  EXPECT_EQ(f.bond(against_wall(1, 1)).tensile, 2e4);
  EXPECT_EQ(f.bond(against_wall(1, 1)).shear, 1e4);
  EXPECT_EQ(f.bond(against_wall(1, 1)).distance, 5e-5);
  EXPECT_EQ(f.bond(against_wall(1, 0)).tensile, 0.0);
  EXPECT_EQ(f.bond(between_bodies(0, 1)).tensile, 0.0);

  doc["friction"][1]["shear_strength"] = 0.0;
  refused(doc, "friction[1].shear_strength");
  doc["friction"][1]["shear_strength"] = 1e4;
  doc["friction"][1]["tensile_strength"] = 0.0;
  refused(doc, "friction[1].tensile_strength");
  doc["friction"][1]["tensile_strength"] = 2e4;
  doc["friction"][1]["cohesion"] = 1.0;
  refused(doc, "friction[1]");
  doc["friction"][1]["cohesion"] = 0.0;
  doc["friction"][1]["law"] = "coulomb";
  const std::string law = refused(doc, "friction[1]");
  EXPECT_NE(law.find("bonded"), std::string::npos) << law;
}

TEST(MaterialConfig, UnknownNamesAreRefusedNamingTheKey)
{
  json doc = two_species();
  doc["scene"]["species"][1]["material"] = "stif";
  refused(doc, "scene.species[1].material");
  EXPECT_NE(refused(doc, "scene.species[1].material")
                .find("= \"stif\" names no entry of materials"),
            std::string::npos);

  doc = two_species();
  doc["materials"][0]["law"] = "mooney";
  const std::string law = refused(doc, "materials[0].law");
  EXPECT_NE(law.find("neo_hookean"), std::string::npos) << law;

  doc = two_species();
  doc["materials"][0].erase("parameters");
  refused(doc, "materials[0].parameters");

  // a wall is no species: only `against` may name one
  doc = two_species();
  doc["friction"][0]["species"] = "right";
  const std::string species = refused(doc, "friction[0].species");
  EXPECT_NE(species.find("= \"right\" is not a species"), std::string::npos);
  EXPECT_EQ(species.find("a wall"), std::string::npos) << species;

  doc = two_species();
  doc["friction"][1]["against"] = "lid";
  const std::string against = refused(doc, "friction[1].against");
  EXPECT_NE(against.find("= \"lid\" is not a species, a wall or \"walls\""),
            std::string::npos)
      << against;

  doc = two_species();
  doc["friction"][2]["coefficient"] = -0.1;
  refused(doc, "friction[2].coefficient");
  doc["friction"][2]["coefficient"] = "high";
  const std::string high = refused(doc, "friction[2].coefficient");
  EXPECT_NE(high.find("must be a number"), std::string::npos) << high;
}
