// The CSparse matrices of FCLIB's HDF5 files (the local W, the global M
// and H), read as lists of entries.
#include "fclib_detail.h"

#include "fclib_io.h"

#include <io/h5_helpers.h>

#include <cmath>

namespace h5 = softpack::io::h5;

namespace softpack::contact::fclib
{
namespace
{
//-----------------------------------------------------------------------------
[[noreturn]] void fail(const std::string& what)
{
  throw FclibError(what);
}
//-----------------------------------------------------------------------------
void check_index(std::int64_t value, std::int64_t bound,
                 const std::string& path, std::size_t k)
{
  if (value < 0 or value >= bound)
  {
    fail("dataset " + path + ": entry " + std::to_string(k) + " = " +
         std::to_string(value) + " outside [0, " + std::to_string(bound) + ")");
  }
}
//-----------------------------------------------------------------------------
/// Entries of a compressed matrix (outer = rows for CSR, columns for CSC).
std::vector<Entry> compressed_entries(const std::vector<std::int64_t>& p,
                                      const std::vector<std::int64_t>& i,
                                      const std::vector<double>& x,
                                      std::int64_t outer, std::int64_t inner,
                                      bool by_rows, const std::string& group,
                                      const std::string& name)
{
  const std::string M = group + "/";
  if (p.size() != static_cast<std::size_t>(outer + 1))
  {
    fail("dataset " + M + "p: " + std::to_string(p.size()) +
         " pointers, expected " + std::to_string(outer + 1));
  }
  if (p[0] != 0)
    fail("dataset " + M + "p: first pointer is not 0");
  for (std::size_t k = 0; k + 1 < p.size(); ++k)
    if (p[k + 1] < p[k])
      fail("dataset " + M + "p: pointers decrease at " + std::to_string(k));
  const std::size_t nnz = static_cast<std::size_t>(p.back());
  if (i.size() < nnz or x.size() < nnz)
  {
    fail(name + " has " + std::to_string(nnz) + " nonzeros but " + name +
         "/i has " + std::to_string(i.size()) + " and " + name + "/x " +
         std::to_string(x.size()) + " values");
  }
  std::vector<Entry> entries;
  entries.reserve(nnz);
  for (std::int64_t o = 0; o < outer; ++o)
    for (std::int64_t k = p[o]; k < p[o + 1]; ++k)
    {
      check_index(i[k], inner, M + "i", k);
      if (by_rows)
        entries.push_back({o, i[k], x[k]});
      else
        entries.push_back({i[k], o, x[k]});
    }
  return entries;
}
//-----------------------------------------------------------------------------
std::vector<Entry> triplet_entries(const std::vector<std::int64_t>& p,
                                   const std::vector<std::int64_t>& i,
                                   const std::vector<double>& x,
                                   std::int64_t nz, std::int64_t m,
                                   std::int64_t n, const std::string& group,
                                   const std::string& name)
{
  const std::string M = group + "/";
  const std::size_t count = static_cast<std::size_t>(nz);
  if (p.size() < count or i.size() < count or x.size() < count)
    fail(name + " is a triplet matrix with nz = " + std::to_string(nz) +
         " but " + name + "/p, " + name + "/i or " + name + "/x is shorter");
  std::vector<Entry> entries;
  entries.reserve(count);
  for (std::size_t k = 0; k < count; ++k)
  {
    check_index(i[k], m, M + "i", k);
    check_index(p[k], n, M + "p", k);
    entries.push_back({i[k], p[k], x[k]});
  }
  return entries;
}
} // namespace
//-----------------------------------------------------------------------------
std::int64_t read_scalar(hid_t file, const std::string& path)
{
  const std::vector<std::int64_t> v = h5::read_integers(file, path);
  if (v.size() != 1)
    fail("dataset " + path + ": " + std::to_string(v.size()) +
         " values, expected one");
  return v[0];
}
//-----------------------------------------------------------------------------
SparseEntries
read_csparse(hid_t file, const std::string& group, const std::string& name,
             const std::function<void(std::int64_t, std::int64_t)>& check_size)
{
  const std::string M = group + "/";
  SparseEntries out;
  out.rows = read_scalar(file, M + "m");
  out.cols = read_scalar(file, M + "n");
  const std::int64_t nz = read_scalar(file, M + "nz");
  read_scalar(file, M + "nzmax");
  if (check_size)
    check_size(out.rows, out.cols);
  const std::vector<std::int64_t> p = h5::read_integers(file, M + "p");
  const std::vector<std::int64_t> i = h5::read_integers(file, M + "i");
  const std::vector<double> x = h5::read_doubles(file, M + "x");
  const std::int64_t m = out.rows, n = out.cols;
  if (nz == -2)
    out.entries = compressed_entries(p, i, x, m, n, true, group, name);
  else if (nz == -1)
    out.entries = compressed_entries(p, i, x, n, m, false, group, name);
  else if (nz >= 0)
    out.entries = triplet_entries(p, i, x, nz, m, n, group, name);
  else
    fail(name + "/nz = " + std::to_string(nz) +
         " is no CSparse storage (-2 rows, -1 columns, >= 0 triplets)");
  for (const Entry& e : out.entries)
    if (!std::isfinite(e.value))
      fail(name + " entry (" + std::to_string(e.row) + ", " +
           std::to_string(e.col) + ") is not finite");
  return out;
}

//-----------------------------------------------------------------------------
void check_delassus_size(std::int64_t rows, std::int64_t cols, int D,
                         std::size_t nc)
{
  const auto size = static_cast<std::int64_t>(D * nc);
  if (rows != size or cols != size)
  {
    fail("W is " + std::to_string(rows) + " x " + std::to_string(cols) +
         ", expected " + std::to_string(size) + " x " + std::to_string(size) +
         " (" + std::to_string(D) + " per contact, " + std::to_string(nc) +
         " contacts in mu)");
  }
}

} // namespace softpack::contact::fclib
