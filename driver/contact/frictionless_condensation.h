#pragma once
// Frictionless contacts condensed out of the sweeps: each small set of them
// (a body's nodes on a lubricated base) held exactly, its reactions solved
// from the others', an active set deciding which of them touch.
#include "nlgs.h"

#include <cstddef>
#include <memory>
#include <span>
#include <string>

namespace softpack::contact
{

/// Outcome of FrictionlessCondensation::solve()
struct CondensedResult
{
  /// The sweeps of every reduced solve summed, the drifts they followed,
  /// and the error of the whole problem at the answer
  NlgsResult nlgs;
  /// Contacts condensed (frictionless, in small sets), and of those the
  /// ones held at the end (their reactions solved, not swept)
  std::size_t condensed = 0, held = 0;
  /// Reduced problems solved: one more per release
  int rounds = 0;
  /// The last reduced W's rank-one terms from held sets (one per held
  /// contact of a set held as terms; the other sets' corrections are
  /// blocks)
  std::size_t held_terms = 0;
  /// Sweeps of the whole problem after the held ones (0: none), when
  /// those used half the budget without an answer
  int swept_whole = 0;
};

/// The frictionless contacts (mu = 0, no cohesion, in no rank-one term of
/// W) that W couples in sets of at most `largest_set`, condensed out of
/// the NLGS. A frictionless contact carries a normal reaction only, so a
/// set S of them held closed (u_n = 0 at each: a body's nodes pressed on a
/// lubricated glass) answers the others' reactions r_P exactly:
/// \f[
///   r_S = -W_{SS}^{-1} (q_S + W_{SP} r_P), \qquad
///   u_P = (W_{PP} - W_{PS} W_{SS}^{-1} W_{SP}) r_P
///         + q_P - W_{PS} W_{SS}^{-1} q_S,
/// \f]
/// W_SS the set's normal block (dense: the set's size squared). The NLGS
/// sweeps the reduced problem (its W the Schur complement, coupling only
/// what W coupled already: the contacts of a set's bodies). A set's
/// correction W_PS W_SS^-1 W_SP is kept as blocks (p^2 for p neighbours)
/// or, when the set holds fewer contacts m than it has neighbours, as m
/// rank-one terms (from W_SS = P^T L D L^T P: a sweep reads 2 m terms at a
/// neighbour instead of p blocks). A solve holds
/// the condensable contacts that push in its start (the last time step's
/// answer; from r = 0, those whose free velocity closes; the later solves
/// on the same W, a step's other Newton iterations, start from the last
/// one's held set) and sweeps the others with the rest; a held contact
/// whose reaction comes out pulling is let go, swept from then on, and
/// the reduced problem solved again from the last answer. The held set
/// only shrinks within a solve (an active set that also took contacts
/// back cycled on a loose 3D packing), so the rounds end. The held rounds
/// get half of the sweeps allowed; if they end without an answer, the
/// whole problem is swept from theirs with the rest. The answer is
/// the whole problem's, its error (compute_error) the whole problem's.
///
/// Why: Gauss–Seidel on a rim node pressed on the base and by a neighbour
/// creeps for hundreds of sweeps (docs/performance_3d.md, "Gauss–Seidel's
/// drift"); with the base's contacts held, the node's two contacts are
/// one, seen through the held body.
///
/// Made for one W (its friction and cohesion too); each solve reads q
/// anew, so the Newton iterations of a time step share the reduced W, made
/// again only when the held set changes.
template <int D> class FrictionlessCondensation
{
public:
  /// @param[in] problem Its W, friction and cohesion (q is read by each
  /// solve)
  /// @param[in] largest_set Larger sets stay in the sweeps (W_SS is dense)
  explicit FrictionlessCondensation(const FrictionContactProblem<D>& problem,
                                    std::size_t largest_set = 2000);
  ~FrictionlessCondensation();
  FrictionlessCondensation(FrictionlessCondensation&&) noexcept;
  FrictionlessCondensation& operator=(FrictionlessCondensation&&) noexcept;

  /// Solve `problem` (the W, friction and cohesion of the construction,
  /// any q)
  /// @param[in,out] r Reactions (the start when options.warm_start)
  /// @param[out] u Velocities W r + q at the answer
  /// @param[in] options The sweeps' options (max_sweeps bounds all rounds
  /// together)
  /// @throws std::invalid_argument for another W
  CondensedResult solve(const FrictionContactProblem<D>& problem,
                        std::span<double> r, std::span<double> u,
                        const NlgsOptions& options);

  /// Contacts condensed
  std::size_t condensed() const;

private:
  /// Sweep the whole problem from r with the rest of the budget (after
  /// result's sweeps), adding its sweeps to result's
  static void sweep_whole(const FrictionContactProblem<D>& problem,
                          std::span<double> r, std::span<double> u,
                          const NlgsOptions& options, CondensedResult& result);
  struct Sets;
  std::unique_ptr<Sets> _sets;
};

/// Whether a D-dimensional run condenses (the schema's
/// contact.nlgs_condensation: "auto", on in 3D; "on", 3D only; "off")
/// @throws std::invalid_argument naming the allowed names, or for "on" in
/// 2D
bool condenses(const std::string& name, int dim);

extern template class FrictionlessCondensation<2>;
extern template class FrictionlessCondensation<3>;

} // namespace softpack::contact
