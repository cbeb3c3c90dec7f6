// The reader generated from schema/parameters.toml: every key required,
// unknown keys refused, ranges (open and closed ends), types and choices
// checked, errors naming the file and the key path; to_json the inverse.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <softpack/parameters.h>
#include <stdexcept>
#include <string>

using nlohmann::json;
namespace p = softpack::parameters;

namespace
{
/// The paper's defaults, written by hand (not from the structs) so that a
/// generator that lost a default would fail here.
json paper_sections()
{
  return json::parse(R"({
    "stop": {"packing_fraction": 0.88, "max_time": 1.43, "steps": 0,
             "base_area_fraction": 0.0},
    "contact": {"friction": 0.3, "alert_distance": 2e-4, "max_penetration": 5e-4,
                "nlgs_tolerance": 1e-6, "nlgs_max_sweeps": 2000,
                "nlgs_relaxation": 1.7, "nlgs_order": "alternate", "nlgs_update": "auto", "nlgs_condensation": "auto", "nlgs_extrapolation": "auto",
                "delassus_drop_tolerance": 1e-9},
    "time": {"time_step": 7.2e-5, "max_step_factor": 1.0, "theta": 0.55,
             "mass": "consistent",
             "newton_tolerance": 1e-4, "newton_max_iterations": 20,
             "full_newton": false, "tangent_reuse_steps": 50,
             "refactor_above_iterations": 5},
    "damping": {"alpha": 30.0, "beta": 1e-5},
    "gravity": {"acceleration": [0.0, 0.0]},
    "output": {"every_steps": 12, "fields": true, "fields_every": 10,
               "state": true},
    "parallel": {"rebalance_tolerance": 0.1},
    "cell": {"enabled": false, "a1": [0.1, 0.0], "a2": [0.0, 0.1],
             "velocity_gradient_x": [0.0, 0.0],
             "velocity_gradient_y": [0.0, 0.0], "control_xx": "velocity",
             "control_yy": "velocity", "stress_xx": 0.0, "stress_yy": 0.0,
             "control_xy": "velocity", "stress_xy": 0.0,
             "control_mean": "velocity", "stress_mean": 0.0, "stress_rate": 0.0, "mass": 1.0,
             "damping_time": 0.0},
    "material": {"law": "neo_hookean", "density": 1180.0, "rigid": false,
                 "parameters": {"shear_modulus": 150000.0,
                                "lame_lambda": 300000.0}}
  })");
}

/// The message of the runtime_error thrown by reading `doc`.
std::string error_of(const json& doc)
{
  p::Parameters out;
  try
  {
    p::read(doc, out, "run/driver.json");
  }
  catch (const std::runtime_error& e)
  {
    return e.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part)
{
  return text.find(part) != std::string::npos;
}
} // namespace

TEST(Parameters, DefaultsAreTheSchemas)
{
  const p::Parameters defaults;
  EXPECT_EQ(p::to_json(defaults).at("contact"), paper_sections().at("contact"));
  EXPECT_EQ(p::to_json(defaults).at("time"), paper_sections().at("time"));
  EXPECT_EQ(defaults.stop.packing_fraction, 0.88);
  EXPECT_EQ(defaults.damping.alpha, 30.0);
  EXPECT_EQ(defaults.output.every_steps, 12);
  EXPECT_EQ(defaults.material.law, "neo_hookean");
}

TEST(Parameters, RoundTrip)
{
  json doc = paper_sections();
  doc["time"]["theta"] = 0.5;
  doc["time"]["mass"] = "lumped";
  doc["stop"]["steps"] = 7;
  doc["contact"]["friction"] = 0; // an integer is a valid float
  p::Parameters read;
  p::read(doc, read, "driver.json");
  EXPECT_EQ(read.time.theta, 0.5);
  EXPECT_EQ(read.stop.steps, 7);
  EXPECT_EQ(read.material.parameters.at("lame_lambda"), 300000.0);
  EXPECT_EQ(p::to_json(read), doc);
}

TEST(Parameters, MissingKeyIsNamed)
{
  json doc = paper_sections();
  doc["contact"].erase("friction");
  const std::string e = error_of(doc);
  EXPECT_TRUE(contains(e, "run/driver.json")) << e;
  EXPECT_TRUE(contains(e, "contact.friction")) << e;
  EXPECT_TRUE(contains(e, "missing")) << e;
}

TEST(Parameters, UnknownKeyIsNamed)
{
  json doc = paper_sections();
  doc["damping"]["gamma"] = 1.0;
  const std::string e = error_of(doc);
  EXPECT_TRUE(contains(e, "damping.gamma")) << e;
  EXPECT_TRUE(contains(e, "unknown")) << e;
  doc = paper_sections();
  doc["material"]["young"] = 1.0;
  EXPECT_TRUE(contains(error_of(doc), "material.young"));
}

TEST(Parameters, RangeEndsOpenAndClosed)
{
  // time.theta in [0.5, 1]: both ends allowed, beyond refused.
  for (double theta : {0.5, 1.0})
  {
    json doc = paper_sections();
    doc["time"]["theta"] = theta;
    EXPECT_EQ(error_of(doc), "") << theta;
  }
  json doc = paper_sections();
  doc["time"]["theta"] = 0.49;
  std::string e = error_of(doc);
  EXPECT_TRUE(contains(e, "time.theta")) << e;
  EXPECT_TRUE(contains(e, "[0.5, 1]")) << e;
  // contact.nlgs_relaxation in (0, 2): both ends refused.
  for (double w : {0.0, 2.0})
  {
    doc = paper_sections();
    doc["contact"]["nlgs_relaxation"] = w;
    e = error_of(doc);
    EXPECT_TRUE(contains(e, "contact.nlgs_relaxation")) << e;
    EXPECT_TRUE(contains(e, "(0, 2)")) << e;
  }
  // stop.packing_fraction in [0, 1): 0 allowed, 1 refused.
  doc = paper_sections();
  doc["stop"]["packing_fraction"] = 0;
  EXPECT_EQ(error_of(doc), "");
  doc["stop"]["packing_fraction"] = 1.0;
  EXPECT_TRUE(contains(error_of(doc), "stop.packing_fraction"));
  // An integer range: output.every_steps in [1, inf).
  doc = paper_sections();
  doc["output"]["every_steps"] = 0;
  EXPECT_TRUE(contains(error_of(doc), "output.every_steps"));
}

TEST(Parameters, WrongTypeIsNamed)
{
  json doc = paper_sections();
  doc["damping"]["alpha"] = "30";
  EXPECT_TRUE(contains(error_of(doc), "damping.alpha")) << error_of(doc);
  doc = paper_sections();
  doc["stop"]["steps"] = 2.5; // an int must be an integer
  EXPECT_TRUE(contains(error_of(doc), "stop.steps")) << error_of(doc);
  doc = paper_sections();
  doc["output"]["state"] = 1; // a bool is not a number
  EXPECT_TRUE(contains(error_of(doc), "output.state")) << error_of(doc);
  doc = paper_sections();
  doc["time"]["mass"] = "diagonal"; // a choice
  const std::string e = error_of(doc);
  EXPECT_TRUE(contains(e, "time.mass")) << e;
  EXPECT_TRUE(contains(e, "consistent")) << e;
  doc = paper_sections();
  doc["material"]["parameters"]["shear_modulus"] = "soft";
  EXPECT_TRUE(contains(error_of(doc), "material.parameters.shear_modulus"));
  doc = paper_sections();
  doc["time"] = 1;
  EXPECT_TRUE(contains(error_of(doc), "time")) << error_of(doc);
}
