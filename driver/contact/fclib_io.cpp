#include "fclib_io.h"

#include "fclib_detail.h"

#include <io/h5_helpers.h>

#include <cmath>
#include <limits>
#include <optional>

using namespace softpack::contact;
namespace h5 = softpack::io::h5;

namespace
{
const std::string local = "/fclib_local";
const std::string global = "/fclib_global";

//-----------------------------------------------------------------------------
[[noreturn]] void fail(const std::string& what)
{
  throw FclibError(what);
}
//-----------------------------------------------------------------------------
/// The group of the problem, its spacedim checked: /fclib_local, or
/// /fclib_global when `global_too`
std::string problem_group(hid_t file, int D, bool global_too)
{
  std::string group = local;
  if (!h5::exists(file, local))
  {
    if (!h5::exists(file, global))
      fail("missing group " + local);
    if (!global_too)
      fail("holds a global problem (/fclib_global), not a local one "
           "(/fclib_local)");
    group = global;
  }
  const std::int64_t dim = fclib::read_scalar(file, group + "/spacedim");
  if (dim != D)
    fail("dimension " + std::to_string(dim) + " (" + group +
         "/spacedim): expected a " + std::to_string(D) + "D problem");
  return group;
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
/// The local problem of /fclib_local
template <int D> FrictionContactProblem<D> read_local_problem(hid_t file)
{
  FrictionContactProblem<D> problem;
  problem.friction = h5::read_doubles(file, local + "/vectors/mu");
  const std::size_t nc = problem.friction.size();
  problem.q = h5::read_doubles(file, local + "/vectors/q");
  if (problem.q.size() != D * nc)
  {
    fail("dataset " + local + "/vectors/q: " +
         std::to_string(problem.q.size()) + " values, expected " +
         std::to_string(D * nc) + " (" + std::to_string(D) + " per contact, " +
         std::to_string(nc) + " contacts in mu)");
  }
  problem.W = fclib::blocks_of<D>(
      fclib::read_csparse(file, local + "/W", "W",
                          [nc](std::int64_t m, std::int64_t n)
                          { fclib::check_delassus_size(m, n, D, nc); }),
      nc);
  // softpack's own dataset, beside FCLIB's: a cohesive problem's c
  // (problem.h); absent from FCLIB's files, where c = 0
  if (std::optional<std::vector<double>> c =
          optional_vector(file, local + "/vectors/cohesion", nc))
    problem.cohesion = std::move(*c);
  return problem;
}
//-----------------------------------------------------------------------------
template <int D> FclibFile<D> read_open_file(hid_t file, bool global_too)
{
  const std::string group = problem_group(file, D, global_too);
  FclibFile<D> out;
  out.problem = group == local ? read_local_problem<D>(file)
                               : fclib::read_global_problem<D>(file);
  try
  {
    validate(out.problem);
  }
  catch (const std::invalid_argument& e)
  {
    fail(e.what());
  }
  const std::size_t n = D * out.problem.num_contacts();
  out.title = h5::read_string_or_empty(file, group + "/info/title");
  out.solution_r = optional_vector(file, "/solution/r", n);
  out.solution_u = optional_vector(file, "/solution/u", n);
  out.guess_r = optional_vector(file, "/guesses/1/r", n);
  return out;
}
//-----------------------------------------------------------------------------
/// `read(file)` on the HDF5 file at `path`, opened read-only; every error
/// prefixed with the file's name
template <typename Read>
auto read_hdf5(const std::filesystem::path& path, const Read& read)
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
    return read(file.get());
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
/// W as compressed scalar rows (CSparse, nz = -2): every stored DxD block
/// contributes its D^2 values, so a read-back gives the same blocks.
struct CsrMatrix
{
  std::vector<std::int32_t> p, i;
  std::vector<double> x;
};
//-----------------------------------------------------------------------------
template <int D> CsrMatrix to_csr(const DelassusMatrixD<D>& W)
{
  const std::size_t nc = W.num_contacts();
  if (D * D * (nc + W.num_offdiagonal_blocks()) >
      static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    fail("W too large for 32-bit CSparse indices");
  CsrMatrix csr;
  csr.p.push_back(0);
  for (std::size_t a = 0; a < nc; ++a)
  {
    const auto cols = W.row_columns(a);
    const auto blocks = W.row_blocks(a);
    for (int k = 0; k < D; ++k)
    {
      auto add = [&](std::size_t b, const typename DelassusMatrixD<D>::Block& B)
      {
        for (int l = 0; l < D; ++l)
        {
          csr.i.push_back(static_cast<std::int32_t>(D * b + l));
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
template <int D>
void write_problem(hid_t file, const FrictionContactProblem<D>& problem,
                   const std::string& title, const std::string& description)
{
  const auto m = static_cast<std::int32_t>(D * problem.num_contacts());
  // A file has blocks only: W's rank-one terms are written as theirs.
  std::optional<DelassusMatrixD<D>> expanded;
  if (!problem.W.rank_one_terms().empty())
    expanded = problem.W.expanded();
  const CsrMatrix W = to_csr(expanded ? *expanded : problem.W);
  const auto nnz = static_cast<std::int32_t>(W.x.size());
  for (const char* g : {"", "/W", "/vectors", "/info"})
    h5::create_group(file, local + g);
  const std::int32_t dim = D, compressed_rows = -2;
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
template <int D>
DelassusMatrixD<D> softpack::contact::fclib::blocks_of(const SparseEntries& W,
                                                       std::size_t nc)
{
  check_delassus_size(W.rows, W.cols, D, nc);
  DelassusMatrixD<D> delassus(nc);
  for (const Entry& e : W.entries)
  {
    typename DelassusMatrixD<D>::Block block =
        DelassusMatrixD<D>::Block::Zero();
    block(e.row % D, e.col % D) = e.value;
    delassus.add_block(e.row / D, e.col / D, block);
  }
  delassus.finalize();
  return delassus;
}
template DelassusMatrixD<2>
softpack::contact::fclib::blocks_of(const SparseEntries&, std::size_t);
template DelassusMatrixD<3>
softpack::contact::fclib::blocks_of(const SparseEntries&, std::size_t);
//-----------------------------------------------------------------------------
FclibLocalFile
softpack::contact::read_fclib_local_file(const std::filesystem::path& path)
{
  return read_hdf5(path,
                   [](hid_t file) { return read_open_file<2>(file, false); });
}
//-----------------------------------------------------------------------------
template <int D>
FclibFile<D>
softpack::contact::read_fclib_file(const std::filesystem::path& path)
{
  return read_hdf5(path,
                   [](hid_t file) { return read_open_file<D>(file, true); });
}
template FclibFile<2>
softpack::contact::read_fclib_file(const std::filesystem::path&);
template FclibFile<3>
softpack::contact::read_fclib_file(const std::filesystem::path&);
//-----------------------------------------------------------------------------
FrictionContactProblem2D
softpack::contact::read_fclib_local(const std::filesystem::path& path)
{
  return std::move(read_fclib_local_file(path).problem);
}
//-----------------------------------------------------------------------------
template <int D>
void softpack::contact::dump_problem(const FrictionContactProblem<D>& problem,
                                     const std::filesystem::path& path,
                                     const std::string& description,
                                     std::span<const double> guess)
{
  const std::string name = path.string();
  if (!problem.W.finalized())
    throw FclibError(name + ": cannot dump a problem whose W is not finalized");
  if (!guess.empty() and guess.size() != D * problem.num_contacts())
    throw FclibError(name + ": guess needs " + std::to_string(D) +
                     " values per contact");
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
template void softpack::contact::dump_problem(const FrictionContactProblem2D&,
                                              const std::filesystem::path&,
                                              const std::string&,
                                              std::span<const double>);
template void softpack::contact::dump_problem(const FrictionContactProblem3D&,
                                              const std::filesystem::path&,
                                              const std::string&,
                                              std::span<const double>);
//-----------------------------------------------------------------------------
