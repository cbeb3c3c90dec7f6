#include "static_newton.h"

#include <Eigen/SparseCholesky>
#include <cmath>
#include <stdexcept>

namespace softpack::bodies
{
namespace
{
/// Replace prescribed rows and columns by the identity.
void constrain(BodyMatrix& A, const std::vector<char>& fixed)
{
  for (int col = 0; col < A.outerSize(); ++col)
    for (BodyMatrix::InnerIterator it(A, col); it; ++it)
      if (fixed[it.row()] || fixed[it.col()])
        it.valueRef() = it.row() == it.col() ? 1.0 : 0.0;
}
/// u += du of body b, with K_b du = -r_b on its free DOFs (its constrained
/// tangent factorized; its pattern analysed at the first iteration)
void update_body(const BodySet& bodies, int b, BodyMatrix& K,
                 Eigen::SimplicialLDLT<BodyMatrix>& factor, bool first,
                 std::span<const char> fixed, std::span<const double> r,
                 std::span<double> u)
{
  const Body& body = bodies.body(b);
  std::vector<char> body_fixed(body.num_dofs());
  Eigen::VectorXd rb(body.num_dofs());
  const int d = body.dim;
  for (std::size_t k = 0; k < body.nodes.size(); ++k)
    for (int c = 0; c < d; ++c)
    {
      body_fixed[d * k + c] = fixed[d * body.nodes[k] + c];
      rb[d * k + c] = r[d * body.nodes[k] + c];
    }
  constrain(K, body_fixed);
  if (first)
    factor.analyzePattern(K);
  factor.factorize(K);
  if (factor.info() != Eigen::Success)
    throw std::runtime_error("static Newton: tangent of body " +
                             std::to_string(b) + " is singular");
  const Eigen::VectorXd du = factor.solve(-rb);
  for (std::size_t k = 0; k < body.nodes.size(); ++k)
    for (int c = 0; c < d; ++c)
      u[d * body.nodes[k] + c] += du[d * k + c];
}
} // namespace

NewtonHistory solve_static_equilibrium(BodySet& bodies,
                                       std::span<const double> f_ext,
                                       std::span<const std::int32_t> fixed_dofs,
                                       std::span<const double> fixed_values,
                                       const NewtonOptions& options)
{
  const std::size_t n = bodies.num_dofs();
  if (f_ext.size() != n || fixed_dofs.size() != fixed_values.size())
    throw std::invalid_argument("solve_static_equilibrium: size mismatch");
  std::vector<char> fixed(n, 0);
  std::span<double> u = bodies.displacement();
  for (std::size_t i = 0; i < fixed_dofs.size(); ++i)
  {
    fixed[fixed_dofs[i]] = 1;
    u[fixed_dofs[i]] = fixed_values[i];
  }

  std::vector<BodyMatrix> K = bodies.create_matrices();
  std::vector<Eigen::SimplicialLDLT<BodyMatrix>> factor(bodies.num_bodies());
  std::vector<double> r(n);
  NewtonHistory history;
  for (int it = 0;; ++it)
  {
    bodies.internal_force(r);
    double norm2 = 0;
    for (std::size_t i = 0; i < n; ++i)
    {
      r[i] = fixed[i] ? 0.0 : r[i] - f_ext[i];
      norm2 += r[i] * r[i];
    }
    history.residual_norms.push_back(std::sqrt(norm2));
    const double norm = history.residual_norms.back();
    if (norm <= options.absolute_tolerance ||
        norm <= options.relative_tolerance * history.residual_norms[0])
    {
      history.converged = true;
      return history;
    }
    if (it == options.max_iterations || !std::isfinite(norm))
      return history;

    bodies.tangent(K);
    for (int b = 0; b < bodies.num_bodies(); ++b)
      update_body(bodies, b, K[b], factor[b], it == 0, fixed, r, u);
  }
}

} // namespace softpack::bodies
