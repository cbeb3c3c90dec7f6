#include "fclib_io.h"

#include <io/h5_helpers.h>

#include <cmath>
#include <limits>

using namespace softpack::contact;
namespace h5 = softpack::io::h5;

namespace
{
const std::string local = "/fclib_local";

/// One scalar entry of W.
struct Entry
{
  std::int64_t row, col;
  double value;
};

//-----------------------------------------------------------------------------
[[noreturn]] void fail(const std::string& what)
{
  throw FclibError(what);
}
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
                                      bool by_rows)
{
  const std::string W = local + "/W/";
  if (p.size() != static_cast<std::size_t>(outer + 1))
  {
    fail("dataset " + W + "p: " + std::to_string(p.size()) +
         " pointers, expected " + std::to_string(outer + 1));
  }
  if (p[0] != 0)
    fail("dataset " + W + "p: first pointer is not 0");
  for (std::size_t k = 0; k + 1 < p.size(); ++k)
    if (p[k + 1] < p[k])
      fail("dataset " + W + "p: pointers decrease at " + std::to_string(k));
  const std::size_t nnz = static_cast<std::size_t>(p.back());
  if (i.size() < nnz or x.size() < nnz)
  {
    fail("W has " + std::to_string(nnz) + " nonzeros but W/i has " +
         std::to_string(i.size()) + " and W/x " + std::to_string(x.size()) +
         " values");
  }
  std::vector<Entry> entries;
  entries.reserve(nnz);
  for (std::int64_t o = 0; o < outer; ++o)
    for (std::int64_t k = p[o]; k < p[o + 1]; ++k)
    {
      check_index(i[k], inner, W + "i", k);
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
                                   std::int64_t n)
{
  const std::string W = local + "/W/";
  const std::size_t count = static_cast<std::size_t>(nz);
  if (p.size() < count or i.size() < count or x.size() < count)
    fail("W is a triplet matrix with nz = " + std::to_string(nz) +
         " but W/p, W/i or W/x is shorter");
  std::vector<Entry> entries;
  entries.reserve(count);
  for (std::size_t k = 0; k < count; ++k)
  {
    check_index(i[k], m, W + "i", k);
    check_index(p[k], n, W + "p", k);
    entries.push_back({i[k], p[k], x[k]});
  }
  return entries;
}
//-----------------------------------------------------------------------------
/// Read /fclib_local/W, check it is 2 nc x 2 nc and convert to 2x2 blocks.
DelassusMatrix read_delassus(hid_t file, std::size_t nc)
{
  const std::string W = local + "/W/";
  const std::int64_t m = read_scalar(file, W + "m");
  const std::int64_t n = read_scalar(file, W + "n");
  const std::int64_t nz = read_scalar(file, W + "nz");
  read_scalar(file, W + "nzmax");
  const std::int64_t size = 2 * static_cast<std::int64_t>(nc);
  if (m != size or n != size)
  {
    fail("W is " + std::to_string(m) + " x " + std::to_string(n) +
         ", expected " + std::to_string(size) + " x " + std::to_string(size) +
         " (2 per contact, " + std::to_string(nc) + " contacts in mu)");
  }
  const std::vector<std::int64_t> p = h5::read_integers(file, W + "p");
  const std::vector<std::int64_t> i = h5::read_integers(file, W + "i");
  const std::vector<double> x = h5::read_doubles(file, W + "x");

  std::vector<Entry> entries;
  if (nz == -2)
    entries = compressed_entries(p, i, x, m, n, true);
  else if (nz == -1)
    entries = compressed_entries(p, i, x, n, m, false);
  else if (nz >= 0)
    entries = triplet_entries(p, i, x, nz, m, n);
  else
    fail("W/nz = " + std::to_string(nz) +
         " is no CSparse storage (-2 rows, -1 columns, >= 0 triplets)");

  DelassusMatrix delassus(nc);
  for (std::size_t k = 0; k < entries.size(); ++k)
  {
    const Entry& e = entries[k];
    if (!std::isfinite(e.value))
      fail("W entry (" + std::to_string(e.row) + ", " + std::to_string(e.col) +
           ") is not finite");
    Eigen::Matrix2d block = Eigen::Matrix2d::Zero();
    block(e.row % 2, e.col % 2) = e.value;
    delassus.add_block(e.row / 2, e.col / 2, block);
  }
  delassus.finalize();
  return delassus;
}
//-----------------------------------------------------------------------------
void check_dimension(hid_t file)
{
  if (!h5::exists(file, local))
  {
    if (h5::exists(file, "/fclib_global"))
      fail("holds a global problem (/fclib_global), not a local one "
           "(/fclib_local)");
    fail("missing group " + local);
  }
  const std::int64_t dim = read_scalar(file, local + "/spacedim");
  if (dim != 2)
    fail("dimension " + std::to_string(dim) + " (" + local +
         "/spacedim): only 2D problems are supported");
}
//-----------------------------------------------------------------------------
std::optional<std::vector<double>>
optional_vector(hid_t file, const std::string& path, std::size_t size)
{
  if (!h5::exists(file, path))
    return std::nullopt;
  std::vector<double> v = h5::read_doubles(file, path);
  if (v.size() != size)
    fail("dataset " + path + ": " + std::to_string(v.size()) +
         " values, expected " + std::to_string(size));
  return v;
}
//-----------------------------------------------------------------------------
FclibLocalFile read_open_file(hid_t file)
{
  check_dimension(file);
  FclibLocalFile out;
  FrictionContactProblem2D& problem = out.problem;
  problem.friction = h5::read_doubles(file, local + "/vectors/mu");
  const std::size_t nc = problem.friction.size();
  problem.q = h5::read_doubles(file, local + "/vectors/q");
  if (problem.q.size() != 2 * nc)
  {
    fail("dataset " + local +
         "/vectors/q: " + std::to_string(problem.q.size()) +
         " values, expected " + std::to_string(2 * nc) + " (2 per contact, " +
         std::to_string(nc) + " contacts in mu)");
  }
  problem.W = read_delassus(file, nc);
  // softpack's own dataset, beside FCLIB's: a cohesive problem's c
  // (problem.h); absent from FCLIB's files, where c = 0
  if (std::optional<std::vector<double>> c =
          optional_vector(file, local + "/vectors/cohesion", nc))
    problem.cohesion = std::move(*c);
  try
  {
    validate(problem);
  }
  catch (const std::invalid_argument& e)
  {
    fail(e.what());
  }
  out.title = h5::read_string_or_empty(file, local + "/info/title");
  out.solution_r = optional_vector(file, "/solution/r", 2 * nc);
  out.solution_u = optional_vector(file, "/solution/u", 2 * nc);
  out.guess_r = optional_vector(file, "/guesses/1/r", 2 * nc);
  return out;
}
//-----------------------------------------------------------------------------
/// W as compressed scalar rows (CSparse, nz = -2): every stored 2x2 block
/// contributes its 4 values, so a read-back gives the same blocks.
struct CsrMatrix
{
  std::vector<std::int32_t> p, i;
  std::vector<double> x;
};
//-----------------------------------------------------------------------------
CsrMatrix to_csr(const DelassusMatrix& W)
{
  const std::size_t nc = W.num_contacts();
  if (4 * (nc + W.num_offdiagonal_blocks()) >
      static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    fail("W too large for 32-bit CSparse indices");
  CsrMatrix csr;
  csr.p.push_back(0);
  for (std::size_t a = 0; a < nc; ++a)
  {
    const auto cols = W.row_columns(a);
    const auto blocks = W.row_blocks(a);
    for (int k = 0; k < 2; ++k)
    {
      auto add = [&](std::size_t b, const Eigen::Matrix2d& B)
      {
        for (int l = 0; l < 2; ++l)
        {
          csr.i.push_back(static_cast<std::int32_t>(2 * b + l));
          csr.x.push_back(B(k, l));
        }
      };
      bool diagonal_done = false;
      for (std::size_t j = 0; j < cols.size(); ++j)
      {
        const auto b = static_cast<std::size_t>(cols[j]);
        if (!diagonal_done and b > a)
        {
          add(a, W.diagonal(a));
          diagonal_done = true;
        }
        add(b, blocks[j]);
      }
      if (!diagonal_done)
        add(a, W.diagonal(a));
      csr.p.push_back(static_cast<std::int32_t>(csr.x.size()));
    }
  }
  return csr;
}
//-----------------------------------------------------------------------------
void write_problem(hid_t file, const FrictionContactProblem2D& problem,
                   const std::string& title, const std::string& description)
{
  const auto m = static_cast<std::int32_t>(2 * problem.num_contacts());
  const CsrMatrix W = to_csr(problem.W);
  const auto nnz = static_cast<std::int32_t>(W.x.size());
  for (const char* g : {"", "/W", "/vectors", "/info"})
    h5::create_group(file, local + g);
  const std::int32_t dim = 2, compressed_rows = -2;
  h5::write_integers(file, local + "/spacedim", {&dim, 1});
  h5::write_integers(file, local + "/W/m", {&m, 1});
  h5::write_integers(file, local + "/W/n", {&m, 1});
  h5::write_integers(file, local + "/W/nz", {&compressed_rows, 1});
  h5::write_integers(file, local + "/W/nzmax", {&nnz, 1});
  h5::write_integers(file, local + "/W/p", W.p);
  h5::write_integers(file, local + "/W/i", W.i);
  h5::write_doubles(file, local + "/W/x", W.x);
  h5::write_doubles(file, local + "/vectors/q", problem.q);
  h5::write_doubles(file, local + "/vectors/mu", problem.friction);
  if (!problem.cohesion.empty())
    h5::write_doubles(file, local + "/vectors/cohesion", problem.cohesion);
  h5::write_string(file, local + "/info/title", title);
  h5::write_string(file, local + "/info/description", description);
}
} // namespace

//-----------------------------------------------------------------------------
FclibLocalFile
softpack::contact::read_fclib_local_file(const std::filesystem::path& path)
{
  const std::string name = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw FclibError(name + ": no such file");
  h5::SilenceErrors quiet;
  if (H5Fis_hdf5(name.c_str()) <= 0)
    throw FclibError(name + ": not an HDF5 file");
  h5::Handle file(H5Fopen(name.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.valid())
    throw FclibError(name + ": cannot be opened");
  try
  {
    return read_open_file(file.get());
  }
  catch (const FclibError& e)
  {
    throw FclibError(name + ": " + e.what());
  }
  catch (const h5::H5Error& e) // a dataset of the layout missing or wrong
  {
    throw FclibError(name + ": " + e.what());
  }
}
//-----------------------------------------------------------------------------
FrictionContactProblem2D
softpack::contact::read_fclib_local(const std::filesystem::path& path)
{
  return std::move(read_fclib_local_file(path).problem);
}
//-----------------------------------------------------------------------------
void softpack::contact::dump_problem(const FrictionContactProblem2D& problem,
                                     const std::filesystem::path& path,
                                     const std::string& description,
                                     std::span<const double> guess)
{
  const std::string name = path.string();
  if (!problem.W.finalized())
    throw FclibError(name + ": cannot dump a problem whose W is not finalized");
  if (!guess.empty() and guess.size() != 2 * problem.num_contacts())
    throw FclibError(name + ": guess needs 2 values per contact");
  h5::SilenceErrors quiet;
  h5::Handle file(
      H5Fcreate(name.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
      H5Fclose);
  if (!file.valid())
    throw FclibError(name + ": cannot create file");
  try
  {
    write_problem(file.get(), problem, path.stem().string(), description);
    if (!guess.empty())
    {
      const std::int32_t one = 1;
      h5::create_group(file.get(), "/guesses");
      h5::write_integers(file.get(), "/guesses/number_of_guesses", {&one, 1});
      h5::create_group(file.get(), "/guesses/1");
      h5::write_doubles(file.get(), "/guesses/1/r", guess);
    }
  }
  catch (const FclibError& e)
  {
    throw FclibError(name + ": " + e.what());
  }
  catch (const h5::H5Error& e) // a dataset of the layout missing or wrong
  {
    throw FclibError(name + ": " + e.what());
  }
}
//-----------------------------------------------------------------------------
