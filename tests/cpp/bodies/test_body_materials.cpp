// One material's constants for its forms (driver/bodies/body_materials.h):
// exactly the constants the law declares, with their values, plus the
// density "rho"; a law missing, a density not positive, a parameter missing
// or unknown are refused naming the material where it was given. The
// defaults C++ takes for a law's parameters (forms/material_defaults.h) are
// the registry's, the one declaration in forms/materials/LAW.py.
#include <algorithm>
#include <bodies/body_materials.h>
#include <bodies/material_parameters.h>
#include <fstream>
#include <gtest/gtest.h>
#include <material_defaults.h>
#include <material_registry.h>
#include <nlohmann/json.hpp>
#include <stdexcept>

using namespace softpack;

namespace
{
bodies::BodyMaterial stiff()
{
  bodies::BodyMaterial m;
  m.law = &forms::find_material("saint_venant_kirchhoff");
  m.parameters = {{"shear_modulus", 1e6}, {"lame_lambda", 2e6}};
  m.density = 3000;
  m.name = "materials[1]";
  return m;
}

/// The message refusing `m`, "" if it is accepted.
std::string error_of(const bodies::BodyMaterial& m)
{
  try
  {
    bodies::material_constants(m);
  }
  catch (const std::invalid_argument& e)
  {
    return e.what();
  }
  return "";
}
} // namespace

TEST(BodyMaterials, ConstantsAreTheLawsAndTheDensity)
{
  const bodies::ConstantMap c = bodies::material_constants(stiff());
  std::vector<std::string> keys;
  for (const auto& [key, value] : c)
    keys.push_back(key);
  EXPECT_EQ(keys,
            (std::vector<std::string>{"lame_lambda", "rho", "shear_modulus"}));
  EXPECT_EQ(c.at("shear_modulus")->value, std::vector<double>{1e6});
  EXPECT_EQ(c.at("lame_lambda")->value, std::vector<double>{2e6});
  EXPECT_EQ(c.at("rho")->value, std::vector<double>{3000});
}

TEST(BodyMaterials, BadMaterialsAreRefusedNamingWhereTheyWereGiven)
{
  bodies::BodyMaterial m = stiff();
  m.law = nullptr;
  EXPECT_EQ(error_of(m), "materials[1].law: no law given");

  m = stiff();
  m.density = 0;
  EXPECT_NE(error_of(m).find("materials[1].density must be positive"),
            std::string::npos);

  m = stiff();
  m.parameters.erase("lame_lambda");
  const std::string missing = error_of(m);
  EXPECT_EQ(missing.rfind("materials[1].parameters.lame_lambda: missing (law "
                          "'saint_venant_kirchhoff' has the parameters ",
                          0),
            0u)
      << missing;
  const std::string listed = missing.substr(missing.find("parameters "));
  for (const char* key : {"shear_modulus", "lame_lambda"})
    EXPECT_NE(listed.find(key), std::string::npos) << missing;

  m = stiff();
  m.parameters["nu"] = 0.3;
  EXPECT_NE(error_of(m).find("materials[1].parameters.nu: unknown parameter"),
            std::string::npos)
      << error_of(m);
}

TEST(MaterialDefaults, AreTheRegistrysDeclaredDefaults)
{
  std::ifstream in(SOFTPACK_MATERIALS_JSON);
  ASSERT_TRUE(in) << SOFTPACK_MATERIALS_JSON;
  const nlohmann::json materials = nlohmann::json::parse(in).at("materials");
  for (const std::string& law : forms::material_names())
  {
    // every parameter the compiled law uses, and nothing else
    const forms::ParameterValues p = forms::with_defaults(law, {});
    std::vector<std::string> keys,
        compiled = forms::material_parameters(forms::find_material(law));
    for (const auto& [key, value] : p)
      keys.push_back(key);
    std::sort(compiled.begin(), compiled.end());
    EXPECT_EQ(keys, compiled) << law;
    // a number declared is the value; a given value is kept
    for (const auto& [key, spec] : materials.at(law).at("parameters").items())
      if (spec.at("default").is_number())
        EXPECT_EQ(p.at(key), spec.at("default").get<double>()) << law << key;
    const forms::ParameterValues given =
        forms::with_defaults(law, {{"shear_modulus", 7.0}, {"lame_lambda", 1}});
    EXPECT_EQ(given.at("lame_lambda"), 1.0);
  }
  EXPECT_THROW(forms::with_defaults("mooney", {}), std::invalid_argument);
}

TEST(MaterialDefaults, ExpressionsUseTheGivenParameters)
{
  // neo_hookean.py declares lame_lambda = "2 * shear_modulus" (nu~ = 1/3,
  // the paper's plane-strain match): evaluated with the shear modulus given
  const forms::ParameterValues p =
      forms::with_defaults("neo_hookean", {{"shear_modulus", 3.0}});
  EXPECT_EQ(p.at("lame_lambda"), 6.0);
  EXPECT_EQ(bodies::plane_strain_parameters(3.0), p);
  EXPECT_EQ(bodies::plane_strain_parameters(3.0, 4.0).at("lame_lambda"), 4.0);
}
