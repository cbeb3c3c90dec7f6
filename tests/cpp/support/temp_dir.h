#pragma once

// A fresh temporary directory per test. CTest runs the tests of one
// executable (and the instances of one parameterized test) in parallel
// processes, so a fixed file name under /tmp is shared between them: one
// test's remove() races another's read.

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace softpack::test
{

/// A unique directory under the system's temporary directory, removed with
/// everything in it on destruction.
class TempDir
{
public:
  TempDir()
  {
    std::string tmpl =
        (std::filesystem::temp_directory_path() / "softpack-test-XXXXXX")
            .string();
    if (::mkdtemp(tmpl.data()) == nullptr)
      throw std::runtime_error("cannot create a temporary directory " + tmpl);
    _path = tmpl;
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  ~TempDir()
  {
    std::error_code ec;
    std::filesystem::remove_all(_path, ec);
  }
  const std::filesystem::path& path() const { return _path; }

private:
  std::filesystem::path _path;
};

} // namespace softpack::test
