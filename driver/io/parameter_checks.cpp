#include "parameter_checks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace softpack::parameters::detail
{
using json = nlohmann::json;

[[noreturn]] void fail(const std::string& where, const std::string& path,
                       const std::string& what)
{
  throw std::runtime_error(where + ": " + path + ": " + what);
}

/// Refuse a non-object, a missing key and an unknown key.
void check_keys(const json& j, const std::string& where,
                const std::string& section,
                const std::vector<std::string>& keys)
{
  std::string allowed;
  for (const std::string& k : keys)
    allowed += (allowed.empty() ? "" : ", ") + k;
  if (!j.is_object())
    fail(where, section, "must be a table with the keys " + allowed);
  for (const std::string& k : keys)
    if (!j.contains(k))
      fail(where, section + "." + k,
           "missing (" + section + " needs " + allowed + ")");
  for (const auto& item : j.items())
    if (std::find(keys.begin(), keys.end(), item.key()) == keys.end())
      fail(where, section + "." + item.key(),
           "unknown key (" + section + " has " + allowed + ")");
}

namespace
{
std::string shown(const json& v)
{
  return v.dump();
}
} // namespace

double read_number(const json& v, const std::string& where,
                   const std::string& path, double lo, bool lo_closed,
                   double hi, bool hi_closed, const char* range)
{
  if (!v.is_number())
    fail(where, path, "= " + shown(v) + " must be a number in " + range);
  const double x = v.get<double>();
  const bool above = lo_closed ? x >= lo : x > lo;
  const bool below = hi_closed ? x <= hi : x < hi;
  if (!(above && below))
    fail(where, path, "= " + shown(v) + " is out of the range " + range);
  return x;
}

int read_int(const json& v, const std::string& where, const std::string& path,
             double lo, bool lo_closed, double hi, bool hi_closed,
             const char* range)
{
  if (!v.is_number_integer())
    fail(where, path, "= " + shown(v) + " must be an integer in " + range);
  const double x =
      read_number(v, where, path, lo, lo_closed, hi, hi_closed, range);
  if (std::abs(x) > std::numeric_limits<int>::max())
    fail(where, path, "= " + shown(v) + " is too large");
  return v.get<int>();
}

bool read_bool(const json& v, const std::string& where, const std::string& path)
{
  if (!v.is_boolean())
    fail(where, path, "= " + shown(v) + " must be true or false");
  return v.get<bool>();
}

std::string read_string(const json& v, const std::string& where,
                        const std::string& path,
                        const std::vector<std::string>& choices)
{
  if (!v.is_string())
    fail(where, path, "= " + shown(v) + " must be a string");
  std::string s = v.get<std::string>();
  if (!choices.empty() &&
      std::find(choices.begin(), choices.end(), s) == choices.end())
  {
    std::string allowed;
    for (const std::string& c : choices)
      allowed += (allowed.empty() ? "\"" : ", \"") + c + "\"";
    fail(where, path, "= " + shown(v) + " is not one of " + allowed);
  }
  return s;
}

std::array<double, 2> read_pair(const json& v, const std::string& where,
                                const std::string& path)
{
  if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
    fail(where, path, "= " + shown(v) + " must be a pair of numbers [x, y]");
  return {v[0].get<double>(), v[1].get<double>()};
}

std::vector<double> read_vector(const json& v, const std::string& where,
                                const std::string& path)
{
  const bool numbers = v.is_array() && (v.size() == 2 || v.size() == 3) &&
                       std::all_of(v.begin(), v.end(),
                                   [](const json& x) { return x.is_number(); });
  if (!numbers)
    fail(where, path,
         "= " + shown(v) + " must be 2 or 3 numbers [x, y] or [x, y, z]");
  return v.get<std::vector<double>>();
}

/// The law's parameters: a table of numbers (its keys are checked against
/// the law's constants by the body set).
std::map<std::string, double> read_number_table(const json& v,
                                                const std::string& where,
                                                const std::string& path)
{
  if (!v.is_object())
    fail(where, path, "must be a table of numbers");
  std::map<std::string, double> out;
  for (const auto& item : v.items())
  {
    if (!item.value().is_number())
      fail(where, path + "." + item.key(),
           "= " + shown(item.value()) + " must be a number");
    out[item.key()] = item.value().get<double>();
  }
  return out;
}

std::string read_name(const json& v, const std::string& where,
                      const std::string& path)
{
  if (!v.is_string() || v.get<std::string>().empty())
    fail(where, path, "= " + shown(v) + " must be a non-empty string");
  return v.get<std::string>();
}
} // namespace softpack::parameters::detail
