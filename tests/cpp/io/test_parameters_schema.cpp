// The generated structs and reader against schema/parameters.toml itself,
// parsed here independently of the generator (toml++ instead of Python's
// tomllib): every driver key has the schema's default, and every range end
// is enforced as the schema writes it (closed: the end is accepted; open:
// refused; just beyond: refused, naming the key and the range).
#include <cmath>
#include <gtest/gtest.h>
#include <limits>
#include <nlohmann/json.hpp>
#include <regex>
#include <softpack/list_sections.h>
#include <softpack/parameters.h>
#include <toml++/toml.h>

using nlohmann::json;
namespace p = softpack::parameters;

namespace
{
json to_json(const toml::node& node)
{
  if (auto v = node.value_exact<bool>())
    return *v;
  if (auto v = node.value_exact<std::int64_t>())
    return *v;
  if (auto v = node.value_exact<double>())
    return *v;
  if (auto v = node.value_exact<std::string>())
    return *v;
  if (const toml::array* a = node.as_array())
  {
    json out = json::array();
    for (const toml::node& e : *a)
      out.push_back(to_json(e));
    return out;
  }
  return nullptr;
}

/// The driver sections read into structs: _stage "driver", not _list/_map.
std::vector<std::pair<std::string, const toml::table*>>
driver_sections(const toml::table& schema)
{
  std::vector<std::pair<std::string, const toml::table*>> out;
  for (auto&& [name, node] : schema)
  {
    const toml::table* t = node.as_table();
    if (t && (*t)["_stage"].value_or(std::string()) == "driver" &&
        !(*t)["_list"].value_or(false) && !(*t)["_map"].value_or(false))
      out.emplace_back(std::string(name.str()), t);
  }
  return out;
}

/// "" if `doc` is accepted, else the error message.
std::string error_of(const json& doc)
{
  p::Parameters out;
  try
  {
    p::read(doc, out, "schema-test");
  }
  catch (const std::runtime_error& e)
  {
    return e.what();
  }
  return "";
}

/// Check one end of the range of `section.key`: `at` is the end, `out`
/// the direction away from the interval.
void check_end(const json& defaults, const std::string& section,
               const std::string& key, bool is_int, double at, bool closed,
               double out, const std::string& range)
{
  if (std::isinf(at))
    return;
  const std::string path = section + "." + key;
  auto with = [&](double x)
  {
    json doc = defaults;
    if (is_int)
      doc[section][key] = static_cast<std::int64_t>(x);
    else
      doc[section][key] = x;
    return error_of(doc);
  };
  const double step = is_int ? 1 : 0;
  const double beyond =
      is_int ? at + out * step : std::nextafter(at, out * 1e300);
  const double inside =
      is_int ? at - out * step : std::nextafter(at, -out * 1e300);
  EXPECT_EQ(with(at).empty(), closed) << path << " = " << at << " " << range;
  const std::string e = with(beyond);
  EXPECT_NE(e.find(path), std::string::npos) << path << ": " << e;
  EXPECT_NE(e.find(range), std::string::npos) << path << ": " << e;
  EXPECT_EQ(with(inside), "") << path << " = " << inside;
}
} // namespace

TEST(ParametersSchema, DefaultsAndRangesAreTheSchemas)
{
  const toml::table schema = toml::parse_file(SOFTPACK_SCHEMA);
  EXPECT_EQ(schema["schema_version"].value_or(0), p::schema_version);
  json defaults = p::to_json(p::Parameters{});
  const auto sections = driver_sections(schema);
  ASSERT_EQ(sections.size(), defaults.size());
  const std::regex interval(
      R"(\s*([\[(])\s*([^,]+?)\s*,\s*([^,]+?)\s*([\])])\s*)");
  int ranges = 0;
  for (const auto& [name, table] : sections)
  {
    ASSERT_TRUE(defaults.contains(name)) << name;
    std::size_t keys = 0;
    for (auto&& [key_view, node] : *table)
    {
      const std::string key(key_view.str());
      if (key.starts_with("_"))
        continue;
      ++keys;
      const toml::table& spec = *node.as_table();
      EXPECT_EQ(defaults[name].at(key), to_json(*spec.get("default")))
          << name << "." << key;
      const auto range = spec["range"].value<std::string>();
      if (!range)
        continue;
      std::smatch m;
      ASSERT_TRUE(std::regex_match(*range, m, interval)) << *range;
      ++ranges;
      const bool is_int = spec["type"].value_or(std::string()) == "int";
      check_end(defaults, name, key, is_int, std::stod(m[2]), m[1] == "[", -1,
                *range);
      check_end(defaults, name, key, is_int, std::stod(m[3]), m[4] == "]", 1,
                *range);
    }
    // The material struct adds the law's parameters to the schema's keys.
    EXPECT_EQ(defaults[name].size(), keys + (name == "material" ? 1 : 0))
        << name;
  }
  EXPECT_GT(ranges, 0); // the schema was read, not skipped
}

// The named tables of [walls]: driver.json's list entries, with their name,
// read into the driver's one wall type.
TEST(ParametersSchema, WallEntriesAreTheSchemas)
{
  const toml::table schema = toml::parse_file(SOFTPACK_SCHEMA);
  const toml::table& walls = *schema["walls"].as_table();
  softpack::dynamics::Wall schema_wall;
  schema_wall.mass = 1.0; // the schema's default (derived in Python)
  const json defaults = p::to_json(schema_wall);
  std::size_t keys = 0;
  for (auto&& [key_view, node] : walls)
  {
    const std::string key(key_view.str());
    if (key.starts_with("_"))
      continue;
    ++keys;
    EXPECT_EQ(defaults.at(key), to_json(*node.as_table()->get("default")))
        << key;
  }
  EXPECT_EQ(defaults.size(), keys);
  EXPECT_EQ(p::walls_keys.size(), keys);
  json entry = defaults;
  entry["name"] = "right";
  softpack::dynamics::Wall read;
  EXPECT_NO_THROW(p::read(entry, read, "f", "walls[1]"));
  entry["speed"] = 1.0;
  try
  {
    p::read(entry, read, "f", "walls[1]");
    ADD_FAILURE() << "an unknown key was accepted";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_NE(std::string(e.what()).find("walls[1].speed"), std::string::npos)
        << e.what();
  }
}
