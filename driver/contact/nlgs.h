#pragma once

#include "problem.h"

#include <functional>
#include <span>
#include <string>
#include <vector>

namespace softpack::contact
{

/// The order in which a sweep visits the contacts (NlgsOptions::order).
enum class SweepOrder
{
  /// Ascending contact index (within each part of a split sweep and each
  /// stage of a domain's)
  contact,
  /// Every other contact of the ascending order first (the even positions,
  /// then the odd ones), as red-black Gauss–Seidel visits a line. Measured,
  /// not derived: on the paper case's problems (Phi 0.80 to 0.88, warm
  /// started, relaxation 1.6-1.8) it needs 2.3 to 3.5 times fewer sweeps
  /// than the ascending order, where the contacts of one body pair come
  /// node after node; on a plain row of contacts coupled by a smooth
  /// kernel it needs more (test_sweep_order.cpp). docs/performance.md.
  alternate
};

/// The SweepOrder of a name ("contact" or "alternate": the schema's
/// contact.nlgs_order choices)
/// @throws std::invalid_argument naming the allowed names
SweepOrder sweep_order(const std::string& name);

/// How a sweep finds each contact's free velocity (NlgsOptions::update).
enum class NlgsUpdate
{
  /// From its row of W and the current reactions: \f$q_a + \sum_{b \ne a}
  /// W_{ab} r_b\f$, every contact's row read at every sweep
  row,
  /// From the velocities \f$v = q + W r\f$, kept current: a contact whose
  /// reaction changes by dr adds \f$W_{ba}\,dr\f$ to its neighbours' (its
  /// row read transposed); a contact that stays open (r = 0 before and
  /// after, most of the candidates of a 3D packing) reads no row at all.
  /// The same iteration as `row` to rounding (v drifts by the rounding of
  /// its updates: made again from r every 50 sweeps). In a split sweep the
  /// separator's contacts read their rows (they are swept between the two
  /// parts' threads' barriers); a domain's sweeps (MPI) read rows.
  velocity,
  /// `row` in 2D (its answers as before this option), `velocity` in 3D
  automatic
};

/// The NlgsUpdate of a name ("row", "velocity" or "auto": the schema's
/// contact.nlgs_update choices)
/// @throws std::invalid_argument naming the allowed names
NlgsUpdate nlgs_update(const std::string& name);

/// Whether a solve follows a constant drift of its sweeps to where a cone
/// stops it (DriftExtrapolation, drift_extrapolation.h; not in a domain's
/// solve). Over-relaxed sweeps seldom drift by a constant change: it saves
/// most at relaxation 1, which only a loose packing prefers
/// (docs/performance_3d.md, "Gauss–Seidel's drift").
enum class NlgsExtrapolation
{
  off,
  on,
  /// `off` in 2D (its answers as before this option), `on` in 3D
  automatic
};

/// The NlgsExtrapolation of a name ("auto", "on" or "off": the schema's
/// contact.nlgs_extrapolation choices)
/// @throws std::invalid_argument naming the allowed names
NlgsExtrapolation nlgs_extrapolation(const std::string& name);

/// Options of solve_nlgs().
struct NlgsOptions
{
  /// Target of the full natural-map error (see compute_error())
  double tolerance = 1e-8;

  /// Maximum number of sweeps over all contacts
  int max_sweeps = 10000;

  /// Relaxation \f$\omega \in (0, 2)\f$: \f$r_a \leftarrow \omega
  /// r_a^{local} + (1 - \omega) r_a\f$, projected on the cone if
  /// \f$\omega > 1\f$. Over-relaxation cuts the sweeps several times on
  /// the well-conditioned problems of deformable bodies, but need not
  /// converge on others (rigid granular ones): when the cheap error has
  /// not dropped by 10 % over `relaxation_window` sweeps, the solve goes on
  /// with \f$\omega = 1\f$.
  double relaxation = 1.0;

  /// Sweeps over which an over-relaxed solve must make progress
  int relaxation_window = 50;

  /// The order of a sweep (SweepOrder)
  SweepOrder order = SweepOrder::contact;

  /// How a sweep finds the contacts' free velocities (NlgsUpdate)
  NlgsUpdate update = NlgsUpdate::automatic;

  /// Also compute the full error after every this many sweeps, whatever
  /// the cheap error says (0: only when the cheap error passes). The cheap
  /// error of an over-relaxed sweep can stay above the tolerance long after
  /// the full error is below it (on the paper case's problems two to three
  /// times as many sweeps); a full error costs about one sweep, and each
  /// one also rescales the working tolerance (Siconos' NSGS can likewise
  /// evaluate its full error at a set frequency).
  int full_error_interval = 10;

  /// Start from the reactions passed in (else from r = 0)
  bool warm_start = true;

  /// Whether the sweeps' constant drifts are followed (NlgsExtrapolation)
  NlgsExtrapolation extrapolation = NlgsExtrapolation::off;

  /// Problems with at least this many contacts are swept in the order of
  /// split_for_two_threads() (sweep_split.h): its two independent parts,
  /// then its separator, whatever `threads` is, so that the answer does
  /// not depend on the thread count (0: never; the plain contact order)
  std::size_t split_min_contacts = 0;

  /// Threads that sweep the two parts of a split problem (1 or 2; more
  /// count as 2)
  int threads = 1;

  /// \f$\|q\|_\infty\f$ at or below this (absolute, velocity units) means
  /// q = 0: the solution is r = 0 without a sweep and the error is absolute
  double q_zero_tolerance = 1e-12;
};

/// Outcome of solve_nlgs().
struct NlgsResult
{
  /// Number of sweeps done
  int iterations = 0;

  /// Full natural-map error at the end (NaturalMapError::value)
  double error = 0;

  /// Last cheap error: \f$\|r^{k} - r^{k-1}\| / \|r^k\|\f$ over a sweep
  double cheap_error = 0;

  /// error <= tolerance
  bool converged = false;

  /// q was zero (see NlgsOptions::q_zero_tolerance): r = 0, no sweep
  bool q_zero = false;

  /// The relaxation was dropped to 1 for lack of progress
  bool relaxation_dropped = false;

  /// Drifts followed (NlgsOptions::extrapolate)
  int extrapolations = 0;
};

/// One domain's share of a distributed solve: the domain-wise NLGS of
/// docs/mpi_design.md, in the stages of a DomainPlan (domain_plan.h). The
/// solver itself knows nothing of how domains talk: the caller does. A
/// domain needs W's rows of its own contacts only: the full error is summed
/// from the domains' rows.
struct SweepDomain
{
  /// This domain's contacts by stage, swept in order; the same number of
  /// stages on every domain
  std::span<const std::vector<std::int32_t>> stages;
  /// After every stage but the first: make current here the reactions the
  /// other domains changed in that stage and this domain's rows read (and
  /// send this domain's where others read them)
  std::function<void(int stage, std::span<double> r)> exchange;
  /// Sum `values` over the domains, the same on every domain (after each
  /// sweep: its squared change and norm; for a full error: ErrorSums)
  std::function<void(std::span<double> values)> reduce;
  /// Make the entries of every contact (D per contact: the reactions)
  /// those its domain holds, here (at the end of the solve)
  std::function<void(std::span<double> x)> gather;
};

/// true when solve_nlgs() sweeps the problem in the order of
/// split_for_two_threads() (NlgsOptions::split_min_contacts)
template <int D>
bool splits(const FrictionContactProblem<D>& problem,
            const NlgsOptions& options)
{
  return options.split_min_contacts > 0 and
         problem.num_contacts() >= options.split_min_contacts;
}

/// true when the sweeps of a D-dimensional problem update the velocities
/// (NlgsUpdate)
template <int D> bool updates_velocities(const NlgsOptions& options)
{
  return options.update == NlgsUpdate::velocity or
         (options.update == NlgsUpdate::automatic and D == 3);
}

/// true when the solves of a D-dimensional problem follow the sweeps'
/// drifts (NlgsExtrapolation)
template <int D> bool extrapolates(const NlgsOptions& options)
{
  return options.extrapolation == NlgsExtrapolation::on or
         (options.extrapolation == NlgsExtrapolation::automatic and D == 3);
}

/// true when solve_nlgs() sweeps the problem renumbered (SweepPlan): when
/// it splits(), the order is not the contact order or the sweeps update the
/// velocities
template <int D>
bool renumbers(const FrictionContactProblem<D>& problem,
               const NlgsOptions& options)
{
  return splits(problem, options) or options.order != SweepOrder::contact or
         updates_velocities<D>(options);
}

/// A problem's contacts renumbered in the order of its sweeps, so that a
/// sweep reads W's rows one after the other: the split's part 0, part 1
/// and separator (when splits()) become contiguous ranges, each in the
/// options' SweepOrder. Over rows kept in detection order a sweep in the
/// alternate order cost 1.1-1.5 times one in the ascending order
/// (docs/performance.md); renumbered, every product and sum is the
/// original one, in the same order: the same bits.
///
/// Made from W, the friction and the cohesion; q is filled in by each
/// solve. solve_nlgs() makes one per call unless it is given one: a caller
/// that solves with one W and several q (the Newton iterations of a time
/// step) makes it once. SweepPlan: 2D, SweepPlan3D: 3D.
template <int D> struct SweepPlanD
{
  /// @param[in] problem Its W, friction and cohesion (q is not read)
  /// @param[in] options Its order, split_min_contacts
  SweepPlanD(const FrictionContactProblem<D>& problem,
             const NlgsOptions& options);
  /// The problem renumbered (q: the last solve's)
  FrictionContactProblem<D> problem;
  /// The original number of each contact here
  std::vector<std::int32_t> order;
  /// Where each original contact is here (the full error sums its terms in
  /// the original order through it)
  std::vector<std::int32_t> position;
  /// The split sweep's sets: part 0 is [0, ends[0]), part 1 [ends[0],
  /// ends[1]), the separator [ends[1], n); without a split ends[0] = n
  std::size_t ends[2];
  /// What the plan was made for (a solve with other options refuses it)
  bool split;
  SweepOrder sweep_order;
};

using SweepPlan = SweepPlanD<2>;
using SweepPlan3D = SweepPlanD<3>;
extern template struct SweepPlanD<2>;
extern template struct SweepPlanD<3>;

/// Nonlinear (block) Gauss–Seidel for the 2D or 3D frictional contact
/// problem \f$u = W r + q\f$ (Moreau, Jean; Siconos `fc2d_nsgs`,
/// `fc3d_nsgs`): one solver, the dimension a template parameter of its
/// implementation; the 2D and the 3D problem differ only in the local
/// solver and the cone (solve_local(), project_on_cone()).
///
/// A sweep visits the contacts in order; contact \f$a\f$ solves its 2x2
/// (3x3) problem exactly (solve_local()) with
/// \f$q_a + \sum_{b \ne a} W_{ab} r_b\f$, the others' current reactions,
/// so a sweep costs O(number of stored blocks) and W is never formed dense.
/// After each sweep the cheap error \f$\|\Delta r\| / \|r\|\f$ is compared
/// with a working tolerance (initially the tolerance); when it passes, the
/// full error (compute_error()) decides, and if it is still too large the
/// working tolerance is scaled down by the ratio of the two (as Siconos'
/// "light with full final" test). The full error is always computed at the
/// end.
///
/// @param[in] problem A validated problem (see validate())
/// @param[in,out] r Reactions, D per contact (n, t...): the start when
///   options.warm_start, the solution on return
/// @param[out] u Velocities \f$W r + q\f$ at the returned r
/// @param[in] options Tolerance, sweeps, relaxation, ...
/// @return Sweeps, error and convergence flag. The solver writes nothing:
///   a caller that keeps unsolved problems (for replay) copies the problem
///   and the starting r, and writes them with dump_problem() (fclib_io.h).
/// @param[in] domain When given, this process sweeps only its domain's
///   contacts and exchanges as SweepDomain says; every domain returns the
///   same r and result, and u at its own contacts only (the stages; the
///   other entries are left as passed)
/// @param[in,out] plan The problem's SweepPlan, made beforehand for this W
///   and these options (not with a domain); its q is overwritten
/// @throws std::invalid_argument for a plan of another size or options
NlgsResult solve_nlgs(const FrictionContactProblem2D& problem,
                      std::span<double> r, std::span<double> u,
                      const NlgsOptions& options = {},
                      const SweepDomain* domain = nullptr,
                      SweepPlan* plan = nullptr);
NlgsResult solve_nlgs(const FrictionContactProblem3D& problem,
                      std::span<double> r, std::span<double> u,
                      const NlgsOptions& options = {},
                      const SweepDomain* domain = nullptr,
                      SweepPlan3D* plan = nullptr);

} // namespace softpack::contact
