// An FCLIB global problem (M v = H r + f, u = H^T v + w) condensed to the
// local form of the solvers: W = H^T M^-1 H, q = H^T M^-1 f + w.
#include "fclib_detail.h"
#include "fclib_io.h"

#include <io/h5_helpers.h>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

namespace h5 = softpack::io::h5;

namespace softpack::contact::fclib
{
namespace
{
const std::string global = "/fclib_global";

[[noreturn]] void fail(const std::string& what)
{
  throw FclibError(what);
}
//-----------------------------------------------------------------------------
Eigen::SparseMatrix<double> sparse(const SparseEntries& m)
{
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(m.entries.size());
  for (const Entry& e : m.entries)
    t.emplace_back(static_cast<int>(e.row), static_cast<int>(e.col), e.value);
  Eigen::SparseMatrix<double> out(m.rows, m.cols);
  out.setFromTriplets(t.begin(), t.end()); // duplicates summed
  return out;
}
//-----------------------------------------------------------------------------
std::vector<double> vector_of_size(hid_t file, const std::string& name,
                                   std::size_t size, const std::string& what)
{
  std::vector<double> v = h5::read_doubles(file, global + "/vectors/" + name);
  if (v.size() != size)
    fail("dataset " + global + "/vectors/" + name + ": " +
         std::to_string(v.size()) + " values, expected " +
         std::to_string(size) + " (" + what + ")");
  return v;
}
//-----------------------------------------------------------------------------
/// M's sparse LDL^T factorization, M checked symmetric positive definite
/// (a body without mass or a mistyped M would make W meaningless)
void factorize(const Eigen::SparseMatrix<double>& M,
               Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>& ldlt)
{
  const Eigen::SparseMatrix<double> Mt = M.transpose();
  if (!((M - Mt).norm() <= 1e-12 * M.norm()))
    fail("M is not symmetric");
  ldlt.compute(M);
  if (ldlt.info() != Eigen::Success or !(ldlt.vectorD().minCoeff() > 0))
    fail("M is not positive definite (its LDL^T factorization failed or "
         "has a pivot <= 0)");
}
} // namespace
//-----------------------------------------------------------------------------
template <int D> FrictionContactProblem<D> read_global_problem(hid_t file)
{
  FrictionContactProblem<D> problem;
  problem.friction = h5::read_doubles(file, global + "/vectors/mu");
  const std::size_t nc = problem.friction.size();
  const std::vector<double> f = h5::read_doubles(file, global + "/vectors/f");
  const std::vector<double> w = vector_of_size(
      file, "w", D * nc, std::to_string(D) + " per contact in mu");
  const auto nv = static_cast<std::int64_t>(f.size());
  const auto nr = static_cast<std::int64_t>(D * nc);
  const Eigen::SparseMatrix<double> M =
      sparse(read_csparse(file, global + "/M", "M",
                          [nv](std::int64_t m, std::int64_t n)
                          {
                            if (m != nv or n != nv)
                              fail("M is " + std::to_string(m) + " x " +
                                   std::to_string(n) + ", expected " +
                                   std::to_string(nv) + " square (f's size)");
                          }));
  const Eigen::SparseMatrix<double> H = sparse(read_csparse(
      file, global + "/H", "H",
      [nv, nr](std::int64_t m, std::int64_t n)
      {
        if (m != nv or n != nr)
          fail("H is " + std::to_string(m) + " x " + std::to_string(n) +
               ", expected " + std::to_string(nv) + " x " + std::to_string(nr) +
               " (f's size x " + std::to_string(D) + " per contact)");
      }));
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
  factorize(M, ldlt);
  const Eigen::SparseMatrix<double> X = ldlt.solve(H); // M^-1 H
  const Eigen::SparseMatrix<double> W = H.transpose() * X;
  const Eigen::VectorXd q =
      H.transpose() * ldlt.solve(Eigen::Map<const Eigen::VectorXd>(
                          f.data(), static_cast<Eigen::Index>(f.size()))) +
      Eigen::Map<const Eigen::VectorXd>(w.data(), nr);
  problem.q.assign(q.data(), q.data() + q.size());

  SparseEntries entries{nr, nr, {}};
  entries.entries.reserve(static_cast<std::size_t>(W.nonZeros()));
  for (int k = 0; k < W.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(W, k); it; ++it)
      entries.entries.push_back({it.row(), it.col(), it.value()});
  problem.W = blocks_of<D>(entries, nc);
  return problem;
}
template FrictionContactProblem<2> read_global_problem<2>(hid_t);
template FrictionContactProblem<3> read_global_problem<3>(hid_t);

} // namespace softpack::contact::fclib
