#pragma once

// The Gauss–Seidel update of one contact and the sweeps over a list of
// contacts, row- or velocity-updated (nlgs.h, NlgsUpdate): the inner loops
// of solve_nlgs() (nlgs.cpp), which adds the orders, the split, the
// domains and the stopping test.
#include "error.h"
#include "local_solver.h"
#include "problem.h"

#include <Eigen/Core>
#include <cstdint>
#include <ranges>
#include <span>
#include <vector>

namespace softpack::contact::gauss_seidel
{
//-----------------------------------------------------------------------------
/// Squared change of the reactions and squared norm of the new ones over
/// (part of) a sweep.
struct SweepSums
{
  double change = 0, norm = 0;
};
//-----------------------------------------------------------------------------
/// Contact a's new reaction from its free velocity qa (the others' reactions
/// in it): its local solution, relaxed, projected on its cone when
/// over-relaxed. `Cohesive`: the problem has a cohesion vector; without one
/// the update is the plain Signorini–Coulomb one, instruction for
/// instruction (the sweep is the simulator's hot loop). D: 2 or 3, the
/// local solver and the cone of that dimension (the same operations on
/// 2-vectors as before it was a template).
template <bool Cohesive, int D>
inline Eigen::Matrix<double, D, 1>
relaxed(const FrictionContactProblem<D>& problem,
        const Eigen::Matrix<double, D, 1>& qa,
        const Eigen::Matrix<double, D, 1>& old, double omega, std::size_t a)
{
  using Vector = Eigen::Matrix<double, D, 1>;
  const DelassusMatrixD<D>& W = problem.W;
  const double mu = problem.friction[a];
  const double c = Cohesive ? problem.cohesion[a] : 0.0;
  Vector ra = Cohesive ? solve_local(W.diagonal(a), qa, mu, c).r
                       : solve_local(W.diagonal(a), qa, mu).r;
  if (omega != 1.0)
  {
    ra = omega * ra + (1.0 - omega) * old;
    // (a cohesive contact's cone is in r + c e_n)
    if (omega > 1.0)
    {
      if constexpr (Cohesive)
        ra = project_on_cone(shifted_reaction(ra, c), mu) - c * Vector::Unit(0);
      else
        ra = project_on_cone(ra, mu);
    }
  }
  return ra;
}
//-----------------------------------------------------------------------------
/// Contact a's reaction ra written, its change and norm added to `sums`,
/// its rank-one terms' running sums `terms` (null: W has none) updated
template <int D>
inline void store(const FrictionContactProblem<D>& problem, double* r,
                  double* terms, std::size_t a,
                  const Eigen::Matrix<double, D, 1>& ra,
                  const Eigen::Matrix<double, D, 1>& old, SweepSums& sums)
{
  sums.change += (ra - old).squaredNorm();
  sums.norm += ra.squaredNorm();
  for (int j = 0; j < D; ++j)
    r[D * a + j] = ra[j];
  if (terms)
    problem.W.update_sums(a, ra - old, terms);
}
//-----------------------------------------------------------------------------
/// Contact a's Gauss–Seidel update (NlgsUpdate::row): its free velocity
/// from its row of W and the current reactions
template <bool Cohesive, int D>
inline void relax(const FrictionContactProblem<D>& problem, double* r,
                  double* terms, double omega, std::size_t a, SweepSums& sums)
{
  using Vector = Eigen::Matrix<double, D, 1>;
  const DelassusMatrixD<D>& W = problem.W;
  const Vector qa = contact_vector<D>(problem.q.data(), a) +
                    W.offdiagonal_product(a, r, terms);
  const Vector old = contact_vector<D>(r, a);
  store(problem, r, terms, a, relaxed<Cohesive>(problem, qa, old, omega, a),
        old, sums);
}
//-----------------------------------------------------------------------------
/// The velocities v = q + W r (W's blocks; the rank-one terms are read
/// from their sums) of the contacts [0, kept) of a velocity-updated sweep
/// (NlgsUpdate::velocity), made from r
template <int D> struct Velocities
{
  std::vector<double> v;
  std::size_t kept = 0;
  void reset(const FrictionContactProblem<D>& problem, const double* r)
  {
    v.resize(D * problem.num_contacts());
    for (std::size_t a = 0; a < kept; ++a)
    {
      const Eigen::Matrix<double, D, 1> va =
          contact_vector<D>(problem.q.data(), a) + problem.W.row_product(a, r);
      for (int j = 0; j < D; ++j)
        v[D * a + j] = va[j];
    }
  }
};
//-----------------------------------------------------------------------------
/// Contact a's Gauss–Seidel update (NlgsUpdate::velocity): its free
/// velocity from v (a kept contact) or its row (the others), and its
/// change added to the kept contacts' velocities
template <bool Cohesive, int D>
inline void relax_velocity(const FrictionContactProblem<D>& problem, double* r,
                           double* terms, Velocities<D>& velocities,
                           double omega, std::size_t a, SweepSums& sums)
{
  using Vector = Eigen::Matrix<double, D, 1>;
  const DelassusMatrixD<D>& W = problem.W;
  const Vector old = contact_vector<D>(r, a);
  double* v = velocities.v.data();
  const bool kept = a < velocities.kept;
  Vector qa = kept ? Vector(contact_vector<D>(v, a) - W.diagonal(a) * old)
                   : Vector(contact_vector<D>(problem.q.data(), a) +
                            W.offdiagonal_product(a, r));
  if (terms)
    W.add_rank_one_offdiagonal(a, r, terms, qa);
  const Vector ra = relaxed<Cohesive>(problem, qa, old, omega, a);
  store(problem, r, terms, a, ra, old, sums);
  const Vector dr = ra - old;
  if ((dr.array() == 0).all())
    return;
  if (kept)
  {
    const Vector dv = W.diagonal(a) * dr;
    for (int j = 0; j < D; ++j)
      v[D * a + j] += dv[j];
  }
  W.scatter_change(a, dr, v, velocities.kept);
}
//-----------------------------------------------------------------------------
/// Gauss–Seidel over the contacts, in the order `contacts` gives them;
/// velocity-updated when `velocities` is given
template <bool Cohesive, int D, typename Contacts>
SweepSums sweep_law(const FrictionContactProblem<D>& problem, double* r,
                    double* terms, Velocities<D>* velocities, double omega,
                    const Contacts& contacts)
{
  SweepSums sums;
  if (velocities)
    for (const auto a : contacts)
      relax_velocity<Cohesive>(problem, r, terms, *velocities, omega,
                               static_cast<std::size_t>(a), sums);
  else
    for (const auto a : contacts)
      relax<Cohesive>(problem, r, terms, omega, static_cast<std::size_t>(a),
                      sums);
  return sums;
}
//-----------------------------------------------------------------------------
template <int D, typename Contacts>
SweepSums sweep_contacts(const FrictionContactProblem<D>& problem, double* r,
                         double* terms, Velocities<D>* velocities, double omega,
                         const Contacts& contacts)
{
  return problem.cohesion.empty()
             ? sweep_law<false>(problem, r, terms, velocities, omega, contacts)
             : sweep_law<true>(problem, r, terms, velocities, omega, contacts);
}
//-----------------------------------------------------------------------------
/// Gauss–Seidel over the contacts [begin, end), in order
template <int D>
SweepSums sweep(const FrictionContactProblem<D>& problem, double* r,
                double* terms, double omega, std::size_t begin, std::size_t end,
                Velocities<D>* velocities = nullptr)
{
  return sweep_contacts(problem, r, terms, velocities, omega,
                        std::views::iota(begin, end));
}
//-----------------------------------------------------------------------------
/// Gauss–Seidel over the listed contacts, in their order (a domain's stage)
template <int D>
SweepSums sweep(const FrictionContactProblem<D>& problem, double* r,
                double* terms, double omega,
                std::span<const std::int32_t> contacts)
{
  return sweep_contacts(problem, r, terms, static_cast<Velocities<D>*>(nullptr),
                        omega, contacts);
}
} // namespace softpack::contact::gauss_seidel
