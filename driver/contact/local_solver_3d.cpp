// The exact local solver of one 3D contact (circular Coulomb cone).
#include "local_solver.h"

#include "error.h"
#include "local_solver_detail.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <limits>
#include <vector>

using namespace softpack::contact;

namespace
{
//-----------------------------------------------------------------------------
double residual(const Eigen::Matrix3d& W, const Eigen::Vector3d& q, double mu,
                const Eigen::Vector3d& r)
{
  return detail::local_residual<3>(W, q, mu, r);
}
//-----------------------------------------------------------------------------
/// Stick: W r = -q; valid when r lies in the cone.
bool try_stick(const Eigen::Matrix3d& W, const Eigen::Vector3d& q, double mu,
               Eigen::Vector3d& r)
{
  const Eigen::PartialPivLU<Eigen::Matrix3d> lu(W);
  if (!(std::abs(lu.determinant()) > 0))
    return false;
  r = -lu.solve(q);
  return r.allFinite() and r[0] >= 0 and
         std::sqrt(r[1] * r[1] + r[2] * r[2]) <= mu * r[0];
}
//-----------------------------------------------------------------------------
/// The slide condition \f$g(\theta) = a_0 + a_1 \cos\theta + b_1 \sin\theta
/// + a_2 \cos 2\theta + b_2 \sin 2\theta\f$ (local_solver.h)
struct SlideCondition
{
  double a0, a1, b1, a2, b2;

  SlideCondition(const Eigen::Matrix3d& W, const Eigen::Vector3d& q, double mu)
  {
    const Eigen::Vector2d qt = q.tail<2>();
    const Eigen::Vector2d h0 = W(0, 0) * qt - q[0] * W.block<2, 1>(1, 0);
    const Eigen::Matrix2d H1 =
        mu * (q[0] * W.block<2, 2>(1, 1) - qt * W.block<1, 2>(0, 1));
    // s_perp . h0 = h0_y cos - h0_x sin;
    // s_perp^T H1 s = (H22 - H11) sin cos + H21 cos^2 - H12 sin^2
    a0 = 0.5 * (H1(1, 0) - H1(0, 1));
    a1 = h0[1];
    b1 = -h0[0];
    a2 = 0.5 * (H1(1, 0) + H1(0, 1));
    b2 = 0.5 * (H1(1, 1) - H1(0, 0));
  }
  double value(double t) const
  {
    return a0 + a1 * std::cos(t) + b1 * std::sin(t) + a2 * std::cos(2 * t) +
           b2 * std::sin(2 * t);
  }
  double slope(double t) const
  {
    return -a1 * std::sin(t) + b1 * std::cos(t) - 2 * a2 * std::sin(2 * t) +
           2 * b2 * std::cos(2 * t);
  }
  /// The size of g's coefficients (the scale of a root's |g|)
  double scale() const
  {
    return std::abs(a0) + std::abs(a1) + std::abs(b1) + std::abs(a2) +
           std::abs(b2);
  }
  /// Angles of the roots: z^2 g with z = e^{i theta} is the quartic
  /// sum_k c_k z^k, c_4 = (a2 - i b2)/2, c_3 = (a1 - i b1)/2, c_2 = a0,
  /// c_1 = conj(c_3), c_0 = conj(c_4); the roots near the unit circle,
  /// each polished by Newton on g.
  std::vector<double> roots() const;
};
//-----------------------------------------------------------------------------
std::vector<double> SlideCondition::roots() const
{
  using complex = std::complex<double>;
  const complex c[5] = {{0.5 * a2, 0.5 * b2},
                        {0.5 * a1, 0.5 * b1},
                        {a0, 0},
                        {0.5 * a1, -0.5 * b1},
                        {0.5 * a2, -0.5 * b2}};
  double largest = 0;
  for (const complex& ck : c)
    largest = std::max(largest, std::abs(ck));
  std::vector<double> angles;
  if (!(largest > 0) or !std::isfinite(largest))
    return angles;
  // Trim negligible end coefficients (roots at 0 or infinity, off the circle)
  const double negligible = 1e-14 * largest;
  int lo = 0, hi = 4;
  while (hi > lo and std::abs(c[hi]) <= negligible)
    --hi;
  while (lo < hi and std::abs(c[lo]) <= negligible)
    ++lo;
  const int degree = hi - lo;
  if (degree < 1)
    return angles;
  // at most 4 x 4: no allocation in the sweep's hot loop
  using Companion =
      Eigen::Matrix<complex, Eigen::Dynamic, Eigen::Dynamic, 0, 4, 4>;
  Companion companion = Companion::Zero(degree, degree);
  for (int k = 0; k < degree; ++k)
    companion(0, k) = -c[hi - 1 - k] / c[hi];
  for (int k = 1; k < degree; ++k)
    companion(k, k - 1) = 1.0;
  const Eigen::ComplexEigenSolver<Companion> eigen(companion, false);
  for (Eigen::Index k = 0; k < eigen.eigenvalues().size(); ++k)
  {
    const complex z = eigen.eigenvalues()[k];
    if (!(std::abs(std::abs(z) - 1.0) < 0.5))
      continue; // far from the circle: no real root nearby
    double t = std::arg(z);
    for (int it = 0; it < 30; ++it)
    {
      const double d = slope(t);
      if (!(std::abs(d) > 0))
        break;
      const double step = value(t) / d;
      if (!std::isfinite(step) or std::abs(step) > 0.5)
        break; // not converging to a root near the eigenvalue's angle
      t -= step;
      if (std::abs(step) <= 1e-15 * (1.0 + std::abs(t)))
        break;
    }
    if (std::abs(value(t)) <= 1e-10 * scale())
      angles.push_back(t);
  }
  return angles;
}
//-----------------------------------------------------------------------------
/// The slide in direction theta: r = r_n (1, -mu s) with u_n = 0 (none
/// when r_n is not a positive finite value); it holds when
/// s . u_t >= 0.
bool slide_at(const Eigen::Matrix3d& W, const Eigen::Vector3d& q, double mu,
              double theta, Eigen::Vector3d& r, bool& holds)
{
  const Eigen::Vector2d s(std::cos(theta), std::sin(theta));
  const double d = W(0, 0) - mu * (W(0, 1) * s[0] + W(0, 2) * s[1]);
  const double rn = -q[0] / d;
  if (!(d > 0) or !std::isfinite(rn))
    return false;
  r = {rn, -mu * rn * s[0], -mu * rn * s[1]};
  const Eigen::Vector3d u = W * r + q;
  holds = s[0] * u[1] + s[1] * u[2] >= 0;
  return true;
}
} // namespace

//-----------------------------------------------------------------------------
LocalSolution3D softpack::contact::solve_local(const Eigen::Matrix3d& W,
                                               const Eigen::Vector3d& q,
                                               double mu)
{
  if (q[0] >= 0)
    return {Eigen::Vector3d::Zero(), ContactStatus::separated};
  if (mu == 0)
    return {Eigen::Vector3d(-q[0] / W(0, 0), 0, 0), ContactStatus::slide};

  std::vector<Eigen::Vector3d> candidates;
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  if (try_stick(W, q, mu, r))
    return {r, ContactStatus::stick};
  candidates.push_back(r);

  LocalSolution3D best{Eigen::Vector3d::Zero(), ContactStatus::slide};
  double best_res = std::numeric_limits<double>::infinity();
  for (const double theta : SlideCondition(W, q, mu).roots())
  {
    bool holds = false;
    if (!slide_at(W, q, mu, theta, r, holds))
      continue;
    if (!holds)
    {
      candidates.push_back(r);
      continue;
    }
    const double res = residual(W, q, mu, r);
    if (res < best_res)
    {
      best_res = res;
      best.r = r;
    }
  }
  if (best_res < std::numeric_limits<double>::infinity())
    return best;

  // Rounding at a branch boundary: the best candidate projected on the
  // cone (an admissible reaction), or separation.
  return detail::closest_candidate<LocalSolution3D, 3>(W, q, mu, candidates);
}
//-----------------------------------------------------------------------------
LocalSolution3D softpack::contact::solve_local(const Eigen::Matrix3d& W,
                                               const Eigen::Vector3d& q,
                                               double mu, double c)
{
  return detail::solve_shifted<3>(
      W, q, mu, c,
      [](const Eigen::Matrix3d& W, const Eigen::Vector3d& q, double mu)
      { return solve_local(W, q, mu); });
}
//-----------------------------------------------------------------------------
