// Siconos numerics' text format of a local frictional contact problem.
#include "siconos_io.h"

#include "fclib_io.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

using namespace softpack::contact;

namespace
{
[[noreturn]] void fail(const std::string& what)
{
  throw FclibError(what);
}

/// The file as whitespace-separated tokens, read in order
class Tokens
{
public:
  explicit Tokens(const std::filesystem::path& path) : _in(path)
  {
    if (!_in)
      fail("cannot be opened");
  }
  double number(const std::string& what)
  {
    std::string token;
    if (!(_in >> token))
      fail("ends before " + what);
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end == token.c_str() or *end != '\0' or !std::isfinite(v))
      fail(what + ": \"" + token + "\" is not a finite number");
    return v;
  }
  long integer(const std::string& what, long lo, long hi)
  {
    const double v = number(what);
    if (v != std::floor(v) or v < lo or v > hi)
      fail(what + " = " + std::to_string(v) + ": expected an integer in [" +
           std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return static_cast<long>(v);
  }

private:
  std::ifstream _in;
};
//-----------------------------------------------------------------------------
template <int D> DelassusMatrixD<D> read_dense(Tokens& in, std::size_t nc)
{
  const long n = static_cast<long>(D * nc);
  in.integer("the dense W's rows", n, n);
  in.integer("the dense W's columns", n, n);
  Eigen::MatrixXd dense(n, n);
  for (long j = 0; j < n; ++j) // column by column
    for (long i = 0; i < n; ++i)
      dense(i, j) =
          in.number("W(" + std::to_string(i) + ", " + std::to_string(j) + ")");
  DelassusMatrixD<D> W(nc);
  for (std::size_t a = 0; a < nc; ++a)
    for (std::size_t b = 0; b < nc; ++b)
    {
      const typename DelassusMatrixD<D>::Block block =
          dense.block<D, D>(D * a, D * b);
      if (a == b or !block.isZero(0))
        W.add_block(a, b, block);
    }
  W.finalize();
  return W;
}
//-----------------------------------------------------------------------------
template <int D>
DelassusMatrixD<D> read_sparse_blocks(Tokens& in, std::size_t nc)
{
  const long n = static_cast<long>(nc);
  const long blocks = in.integer("nbblocks", 0, n * n);
  in.integer("the block rows", n, n);
  in.integer("the block columns", n, n);
  for (const char* side : {"row", "column"})
    for (long k = 0; k < n; ++k)
      in.integer(std::string("the cumulative ") + side + " block size " +
                     std::to_string(k),
                 D * (k + 1), D * (k + 1));
  in.integer("filled1", n + 1, n + 1);
  in.integer("filled2", blocks, blocks);
  std::vector<long> row_start(n + 1), column(blocks);
  for (long k = 0; k <= n; ++k)
    row_start[k] = in.integer("index1_data", k == n ? blocks : 0, blocks);
  for (long k = 0; k < blocks; ++k)
    column[k] = in.integer("index2_data", 0, n - 1);
  DelassusMatrixD<D> W(nc);
  for (long a = 0; a < n; ++a)
  {
    if (row_start[a + 1] < row_start[a])
      fail("index1_data decreases at block row " + std::to_string(a));
    for (long k = row_start[a]; k < row_start[a + 1]; ++k)
    {
      in.integer("the block number", k, k);
      typename DelassusMatrixD<D>::Block block;
      for (int j = 0; j < D; ++j) // column by column
        for (int i = 0; i < D; ++i)
          block(i, j) = in.number("block " + std::to_string(k));
      W.add_block(a, column[k], block);
    }
  }
  W.finalize();
  return W;
}
//-----------------------------------------------------------------------------
template <int D> FrictionContactProblem<D> read_problem(Tokens& in)
{
  const long dim = in.integer("the dimension", 2, 3);
  if (dim != D)
    fail("dimension " + std::to_string(dim) + ": expected a " +
         std::to_string(D) + "D problem");
  const auto nc = static_cast<std::size_t>(
      in.integer("the number of contacts", 1, 1L << 28));
  const long storage = in.integer("W's storage", 0, 2);
  const long n = static_cast<long>(D * nc);
  in.integer("W's rows", n, n);
  in.integer("W's columns", n, n);
  FrictionContactProblem<D> problem;
  if (storage == 0)
    problem.W = read_dense<D>(in, nc);
  else if (storage == 1)
    problem.W = read_sparse_blocks<D>(in, nc);
  else
    fail("W's storage 2 (CSparse, printed with 6 digits) is not read: use "
         "the problem's HDF5 copy");
  problem.q.resize(D * nc);
  for (std::size_t k = 0; k < D * nc; ++k)
    problem.q[k] = in.number("q[" + std::to_string(k) + "]");
  problem.friction.resize(nc);
  for (std::size_t a = 0; a < nc; ++a)
    problem.friction[a] = in.number("mu[" + std::to_string(a) + "]");
  validate(problem);
  return problem;
}
} // namespace
//-----------------------------------------------------------------------------
template <int D>
FrictionContactProblem<D>
softpack::contact::read_siconos_dat(const std::filesystem::path& path)
{
  try
  {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
      fail("no such file");
    Tokens in(path);
    return read_problem<D>(in);
  }
  catch (const FclibError& e)
  {
    throw FclibError(path.string() + ": " + e.what());
  }
  catch (const std::invalid_argument& e) // validate()
  {
    throw FclibError(path.string() + ": " + e.what());
  }
}
template FrictionContactProblem<2>
softpack::contact::read_siconos_dat(const std::filesystem::path&);
template FrictionContactProblem<3>
softpack::contact::read_siconos_dat(const std::filesystem::path&);
