#pragma once

// Small RAII layer over the HDF5 C API, for the field writer
// (io/field_output.cpp) and the FCLIB files (contact/fclib_io.cpp). Its own
// library (softpack_h5: HDF5 only, no dolfinx) so that the contact solver can
// link it. Failures throw H5Error.

#include <hdf5.h>

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace softpack::io::h5
{

/// An HDF5 call that failed or a dataset that is missing or not of the
/// kind asked for; the message names the dataset.
class H5Error : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// An HDF5 identifier closed on destruction.
class Handle
{
public:
  using Closer = herr_t (*)(hid_t);

  /// @param[in] id Identifier (negative: invalid)
  /// @param[in] close Function releasing it (H5Fclose, H5Dclose, ...)
  Handle(hid_t id, Closer close) : _id(id), _close(close) {}
  Handle(Handle&& other) noexcept : _id(other._id), _close(other._close)
  {
    other._id = -1;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle& operator=(Handle&&) = delete;
  ~Handle()
  {
    if (_id >= 0)
      _close(_id);
  }

  /// @return The identifier
  hid_t get() const { return _id; }

  /// @return true if the identifier is valid
  bool valid() const { return _id >= 0; }

private:
  hid_t _id;
  Closer _close;
};

/// Turns off HDF5's automatic error printing for its lifetime; our own
/// messages say what is wrong.
class SilenceErrors
{
public:
  SilenceErrors();
  SilenceErrors(const SilenceErrors&) = delete;
  SilenceErrors& operator=(const SilenceErrors&) = delete;
  ~SilenceErrors();

private:
  H5E_auto2_t _func = nullptr;
  void* _data = nullptr;
};

/// @param[in] loc File or group
/// @param[in] path Absolute path "/a/b/c"
/// @return true if every link along the path exists
bool exists(hid_t loc, const std::string& path);

/// Read a numeric dataset of rank 0 or 1 as integers (integer type only).
/// @throws H5Error "dataset PATH: ..." when missing or not integer
std::vector<std::int64_t> read_integers(hid_t loc, const std::string& path);

/// Read a numeric dataset of rank 0 or 1 as doubles.
/// @throws H5Error "dataset PATH: ..." when missing or not numeric
std::vector<double> read_doubles(hid_t loc, const std::string& path);

/// Read a string dataset (fixed or variable length).
/// @return The string, or empty if absent or not a string
std::string read_string_or_empty(hid_t loc, const std::string& path);

/// Create a group (parents must exist).
/// @throws H5Error on failure
void create_group(hid_t loc, const std::string& path);

/// Write a 1-D int32 dataset.
void write_integers(hid_t loc, const std::string& path,
                    std::span<const std::int32_t> values);

/// Write a 1-D float64 dataset.
void write_doubles(hid_t loc, const std::string& path,
                   std::span<const double> values);

/// Write a 2-D dataset of values.size() / columns rows (row-major).
void write_table(hid_t loc, const std::string& path,
                 std::span<const double> values, std::size_t columns);
void write_table(hid_t loc, const std::string& path,
                 std::span<const std::int64_t> values, std::size_t columns);

/// Write a fixed-length string dataset.
void write_string(hid_t loc, const std::string& path, const std::string& s);

} // namespace softpack::io::h5
