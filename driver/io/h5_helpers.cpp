#include "h5_helpers.h"

#include <algorithm>
#include <utility>

using namespace softpack::io;
using namespace softpack::io::h5;

namespace
{
//-----------------------------------------------------------------------------
[[noreturn]] void fail(const std::string& path, const std::string& what)
{
  throw H5Error("dataset " + path + ": " + what);
}
//-----------------------------------------------------------------------------
/// An open dataset and its number of values.
struct OpenVector
{
  Handle set;
  std::size_t count;
};
//-----------------------------------------------------------------------------
/// Open a numeric dataset of rank <= 1.
OpenVector open_vector(hid_t loc, const std::string& path, bool integer_only)
{
  if (!exists(loc, path))
    fail(path, "missing");
  Handle set(H5Dopen2(loc, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!set.valid())
    fail(path, "cannot be opened as a dataset");
  Handle type(H5Dget_type(set.get()), H5Tclose);
  const H5T_class_t cls = H5Tget_class(type.get());
  const bool ok = cls == H5T_INTEGER or (!integer_only and cls == H5T_FLOAT);
  if (!ok)
    fail(path, integer_only ? "not an integer dataset" : "not numeric");
  Handle space(H5Dget_space(set.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0 or rank > 1)
    fail(path, "rank " + std::to_string(rank) + ", expected a vector");
  const hssize_t count = H5Sget_simple_extent_npoints(space.get());
  if (count < 0)
    fail(path, "unreadable extent");
  return {std::move(set), static_cast<std::size_t>(count)};
}
//-----------------------------------------------------------------------------
/// Write n values as a vector (columns 0) or a table of n / columns rows
void write_array(hid_t loc, const std::string& path, hid_t file_type,
                 hid_t mem_type, const void* data, std::size_t n,
                 std::size_t columns = 0)
{
  const hsize_t dims[2] = {static_cast<hsize_t>(columns ? n / columns : n),
                           static_cast<hsize_t>(columns)};
  Handle space(H5Screate_simple(columns ? 2 : 1, dims, nullptr), H5Sclose);
  Handle set(H5Dcreate2(loc, path.c_str(), file_type, space.get(), H5P_DEFAULT,
                        H5P_DEFAULT, H5P_DEFAULT),
             H5Dclose);
  if (!set.valid())
    throw H5Error("cannot create dataset " + path);
  if (n > 0 and
      H5Dwrite(set.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    throw H5Error("cannot write dataset " + path);
}
} // namespace

//-----------------------------------------------------------------------------
SilenceErrors::SilenceErrors()
{
  H5Eget_auto2(H5E_DEFAULT, &_func, &_data);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}
//-----------------------------------------------------------------------------
SilenceErrors::~SilenceErrors()
{
  H5Eset_auto2(H5E_DEFAULT, _func, _data);
}
//-----------------------------------------------------------------------------
bool h5::exists(hid_t loc, const std::string& path)
{
  // H5Lexists needs every parent to exist: check the path link by link.
  std::size_t pos = 0;
  while (pos != std::string::npos)
  {
    pos = path.find('/', pos + 1);
    const std::string prefix = path.substr(0, pos);
    if (prefix.empty() or prefix == "/")
      continue;
    if (H5Lexists(loc, prefix.c_str(), H5P_DEFAULT) <= 0)
      return false;
  }
  return true;
}
//-----------------------------------------------------------------------------
std::vector<std::int64_t> h5::read_integers(hid_t loc, const std::string& path)
{
  OpenVector v = open_vector(loc, path, true);
  std::vector<std::int64_t> values(v.count);
  if (v.count > 0 and H5Dread(v.set.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL,
                              H5P_DEFAULT, values.data()) < 0)
    fail(path, "read failed");
  return values;
}
//-----------------------------------------------------------------------------
std::vector<double> h5::read_doubles(hid_t loc, const std::string& path)
{
  OpenVector v = open_vector(loc, path, false);
  std::vector<double> values(v.count);
  if (v.count > 0 and H5Dread(v.set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL,
                              H5P_DEFAULT, values.data()) < 0)
    fail(path, "read failed");
  return values;
}
//-----------------------------------------------------------------------------
std::string h5::read_string_or_empty(hid_t loc, const std::string& path)
{
  if (!exists(loc, path))
    return {};
  Handle set(H5Dopen2(loc, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!set.valid())
    return {};
  Handle type(H5Dget_type(set.get()), H5Tclose);
  if (H5Tget_class(type.get()) != H5T_STRING)
    return {};
  Handle space(H5Dget_space(set.get()), H5Sclose);
  if (H5Sget_simple_extent_npoints(space.get()) != 1)
    return {};
  if (H5Tis_variable_str(type.get()) > 0)
  {
    char* buffer = nullptr;
    if (H5Dread(set.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &buffer) <
            0 or
        buffer == nullptr)
      return {};
    std::string s(buffer);
    H5free_memory(buffer);
    return s;
  }
  std::string s(H5Tget_size(type.get()), '\0');
  if (H5Dread(set.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, s.data()) <
      0)
    return {};
  s.erase(std::find(s.begin(), s.end(), '\0'), s.end());
  return s;
}
//-----------------------------------------------------------------------------
void h5::create_group(hid_t loc, const std::string& path)
{
  Handle g(H5Gcreate2(loc, path.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
           H5Gclose);
  if (!g.valid())
    throw H5Error("cannot create group " + path);
}
//-----------------------------------------------------------------------------
void h5::write_integers(hid_t loc, const std::string& path,
                        std::span<const std::int32_t> values)
{
  write_array(loc, path, H5T_STD_I32LE, H5T_NATIVE_INT32, values.data(),
              values.size());
}
//-----------------------------------------------------------------------------
void h5::write_doubles(hid_t loc, const std::string& path,
                       std::span<const double> values)
{
  write_array(loc, path, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, values.data(),
              values.size());
}
//-----------------------------------------------------------------------------
void h5::write_table(hid_t loc, const std::string& path,
                     std::span<const double> values, std::size_t columns)
{
  write_array(loc, path, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, values.data(),
              values.size(), columns);
}
//-----------------------------------------------------------------------------
void h5::write_table(hid_t loc, const std::string& path,
                     std::span<const std::int64_t> values, std::size_t columns)
{
  write_array(loc, path, H5T_STD_I64LE, H5T_NATIVE_INT64, values.data(),
              values.size(), columns);
}
//-----------------------------------------------------------------------------
void h5::write_string(hid_t loc, const std::string& path, const std::string& s)
{
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), std::max<std::size_t>(s.size(), 1));
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle set(H5Dcreate2(loc, path.c_str(), type.get(), space.get(), H5P_DEFAULT,
                        H5P_DEFAULT, H5P_DEFAULT),
             H5Dclose);
  std::string buffer = s.empty() ? std::string(1, '\0') : s;
  if (!set.valid() or H5Dwrite(set.get(), type.get(), H5S_ALL, H5S_ALL,
                               H5P_DEFAULT, buffer.data()) < 0)
    throw H5Error("cannot write dataset " + path);
}
//-----------------------------------------------------------------------------
