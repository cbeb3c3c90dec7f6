#pragma once

#include <array>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

/// The checks of the generated readers: each throws std::runtime_error
/// "WHERE: PATH: what is wrong and what is allowed".
namespace softpack::parameters::detail
{
/// Throw "where: path: what".
[[noreturn]] void fail(const std::string& where, const std::string& path,
                       const std::string& what);
/// Refuse a non-object, a missing key and an unknown key of `section`.
void check_keys(const nlohmann::json& j, const std::string& where,
                const std::string& section,
                const std::vector<std::string>& keys);
/// A number in the interval (ends closed or open), else refused naming
/// `range`.
double read_number(const nlohmann::json& v, const std::string& where,
                   const std::string& path, double lo, bool lo_closed,
                   double hi, bool hi_closed, const char* range);
/// An integer in the interval.
int read_int(const nlohmann::json& v, const std::string& where,
             const std::string& path, double lo, bool lo_closed, double hi,
             bool hi_closed, const char* range);
/// true or false.
bool read_bool(const nlohmann::json& v, const std::string& where,
               const std::string& path);
/// A string, one of `choices` when they are given.
std::string read_string(const nlohmann::json& v, const std::string& where,
                        const std::string& path,
                        const std::vector<std::string>& choices);
/// A pair of numbers [x, y].
std::array<double, 2> read_pair(const nlohmann::json& v,
                                const std::string& where,
                                const std::string& path);
/// A vector of the plane or of space: 2 or 3 numbers [x, y] or [x, y, z].
std::vector<double> read_vector(const nlohmann::json& v,
                                const std::string& where,
                                const std::string& path);
/// A table of numbers (a law's parameters).
std::map<std::string, double> read_number_table(const nlohmann::json& v,
                                                const std::string& where,
                                                const std::string& path);
/// A non-empty string: a name other keys refer to.
std::string read_name(const nlohmann::json& v, const std::string& where,
                      const std::string& path);
} // namespace softpack::parameters::detail
