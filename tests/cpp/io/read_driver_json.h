#pragma once

#include "driver_json.h"
#include <io/driver_config.h>
#include <stdexcept>
#include <string>

/// Reading a driver.json document written by hand, for the tests that check
/// what the driver accepts and how it names what it refuses.
namespace softpack::test
{

/// `doc` written as driver.json in a fresh directory `name` and read; the
/// directory is removed afterwards, whatever happens.
inline io::DriverConfig read_driver_json(const nlohmann::json& doc,
                                         const std::string& name)
{
  const std::filesystem::path dir = fresh_directory(name);
  struct Cleanup
  {
    std::filesystem::path dir;
    ~Cleanup() { std::filesystem::remove_all(dir); }
  } cleanup{dir};
  write_json(doc, dir / "driver.json");
  return io::read_driver_config(dir / "driver.json");
}

/// The message of the error reading `doc`, "" if it is accepted.
inline std::string driver_json_error(const nlohmann::json& doc,
                                     const std::string& name)
{
  try
  {
    read_driver_json(doc, name);
  }
  catch (const std::runtime_error& e)
  {
    return e.what();
  }
  return "";
}

} // namespace softpack::test
