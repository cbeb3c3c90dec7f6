#include "frictionless_condensation.h"

#include "coupling_graph.h"
#include "error.h"
#include "held_set.h"

#include <algorithm>
#include <optional>
#include <stdexcept>

using namespace softpack::contact;

namespace
{
/// The condensable contacts' sets: the frictionless sets of contacts in
/// no rank-one term (a servo wall's); sets larger than `largest` are left
/// out (their contacts are swept)
template <int D>
std::vector<std::vector<std::int32_t>>
condensable_sets(const FrictionContactProblem<D>& problem, std::size_t largest)
{
  std::vector<char> in_terms(problem.num_contacts());
  for (std::size_t a = 0; a < in_terms.size(); ++a)
    in_terms[a] = !problem.W.terms_of(a).empty();
  std::vector<std::vector<std::int32_t>> sets =
      frictionless_sets(problem, std::move(in_terms));
  std::erase_if(sets, [largest](const std::vector<std::int32_t>& set)
                { return set.size() > largest; });
  return sets;
}

/// Sweeps in one round of a solve, and rounds in a solve
constexpr int round_sweeps = 500;
constexpr int max_rounds = 200;

} // namespace

template <int D> struct FrictionlessCondensation<D>::Sets
{
  Sets(const FrictionContactProblem<D>& problem, std::size_t largest_set)
      : W(&problem.W), sets(condensable_sets(problem, largest_set)),
        set_of(problem.num_contacts(), -1),
        position(problem.num_contacts(), -1), place(problem.num_contacts(), -1),
        hold(problem.num_contacts(), 0)
  {
    for (std::size_t s = 0; s < sets.size(); ++s)
      for (const std::int32_t a : sets[s])
        set_of[a] = static_cast<std::int32_t>(s);
  }

  /// The held set a solve starts from: at the first solve on this W the
  /// condensable contacts that push in r (the last time step's answer), or
  /// when r is zero those whose free velocity closes; later solves (the
  /// step's other Newton iterations) start from the last one's. Chosen
  /// anew at each iteration from its start, the held set changed by a few
  /// contacts from one iteration to the next and the Newton iterations
  /// stalled at a change of 1-4 % of the fastest node's speed (the dense
  /// 100 cylinders: 10 iterations where the held set kept took 4)
  void hold_initial(const FrictionContactProblem<D>& p,
                    std::span<const double> r)
  {
    if (started)
      return;
    started = true;
    const bool cold =
        std::all_of(r.begin(), r.end(), [](double x) { return x == 0; });
    for (const auto& set : sets)
      for (const std::int32_t a : set)
        hold[a] = cold ? p.q[D * a] < 0 : r[D * a] > 0;
  }
  /// The reduced W (and the sets' X, C) of the held set
  void reduce(const FrictionContactProblem<D>& p);
  /// The reduced problem's W, friction and cohesion from p's and the held
  /// sets' corrections (q: set_q)
  void assemble(const FrictionContactProblem<D>& p,
                FrictionContactProblem<D>& red) const;
  /// The reduced q of p's q, and the kept contacts' reactions from r
  void set_q(const FrictionContactProblem<D>& p, std::span<const double> r,
             std::vector<double>& r_kept);
  /// r from the reduced answer: the kept contacts' and the held ones'
  void recover(std::span<const double> r_kept, std::span<double> r) const;
  /// Let go of the held contacts that pull (beyond `threshold`): they are
  /// swept from then on; returns their number
  int release(std::span<double> r, double threshold);
  /// One round: the reduced problem of the held set swept from r (at most
  /// `reduced.max_sweeps`), r the whole answer from it, the held contacts
  /// that pull let go; the result's error and convergence are the whole
  /// problem's, its sweeps the round's
  NlgsResult round(const FrictionContactProblem<D>& p, std::span<double> r,
                   std::span<double> u, const NlgsOptions& options,
                   NlgsOptions& reduced);
  HeldSet condense(const FrictionContactProblem<D>& p,
                   std::vector<std::int32_t> held,
                   std::vector<std::int32_t> neighbours) const;
  /// For each set: the kept contacts W couples to its held ones
  std::vector<std::vector<std::int32_t>>
  neighbours(const DelassusMatrixD<D>& W) const;
  bool held(std::int32_t a) const { return set_of[a] >= 0 and hold[a]; }

  const DelassusMatrixD<D>* W;
  std::vector<std::vector<std::int32_t>> sets;
  std::vector<std::int32_t> set_of;
  /// condense()'s scratch: a held contact's or neighbour's position in its
  /// set's matrices, -1 between calls (one vector of the problem's size
  /// per set was made at every time step)
  mutable std::vector<std::int32_t> position;
  /// Per contact: its number in the reduced problem (kept), or -1
  std::vector<std::int32_t> place;
  std::vector<std::int32_t> kept;
  std::vector<char> hold;
  /// Whether a solve has chosen the held set: the later solves on this W
  /// start from it
  bool started = false;
  /// The held set the reduced problem was made for
  std::vector<char> reduced_hold;
  std::vector<HeldSet> held_sets;
  std::optional<FrictionContactProblem<D>> reduced;
  std::optional<SweepPlanD<D>> plan;
};

template <int D>
std::vector<std::vector<std::int32_t>>
FrictionlessCondensation<D>::Sets::neighbours(const DelassusMatrixD<D>& w) const
{
  // Both ways: W_SP from the held rows, W_PS from the kept ones (a small
  // block dropped may leave one of the two)
  std::vector<std::vector<std::int32_t>> found(sets.size());
  for (std::size_t c = 0; c < w.num_contacts(); ++c)
    for (const std::int32_t b : w.row_columns(c))
    {
      if (held(static_cast<std::int32_t>(c)) and place[b] >= 0)
        found[set_of[c]].push_back(b);
      else if (place[c] >= 0 and held(b))
        found[set_of[b]].push_back(static_cast<std::int32_t>(c));
    }
  for (auto& list : found)
  {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return found;
}

template <int D>
HeldSet FrictionlessCondensation<D>::Sets::condense(
    const FrictionContactProblem<D>& p, std::vector<std::int32_t> held_list,
    std::vector<std::int32_t> near) const
{
  const auto m = static_cast<Eigen::Index>(held_list.size());
  const auto np = static_cast<Eigen::Index>(near.size());
  // Each held contact's and neighbour's position in the set's matrices
  std::vector<std::int32_t>& at = position;
  for (Eigen::Index i = 0; i < m; ++i)
    at[held_list[i]] = static_cast<std::int32_t>(i);
  for (Eigen::Index k = 0; k < np; ++k)
    at[near[k]] = static_cast<std::int32_t>(k);
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(m, m);
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(m, D * np);
  for (Eigen::Index i = 0; i < m; ++i)
  {
    const std::int32_t a = held_list[i];
    N(i, i) = p.W.diagonal(a)(0, 0);
    const auto columns = p.W.row_columns(a);
    const auto blocks = p.W.row_blocks(a);
    for (std::size_t k = 0; k < columns.size(); ++k)
    {
      const std::int32_t b = columns[k];
      if (held(b)) // (in this set: sets are W's connected components)
        N(i, at[b]) = blocks[k](0, 0);
      else if (place[b] >= 0)
        B.block(i, D * at[b], 1, D) = blocks[k].row(0);
    }
  }
  HeldSet s;
  s.C = Eigen::MatrixXd::Zero(D * np, m);
  for (Eigen::Index k = 0; k < np; ++k)
  {
    const auto columns = p.W.row_columns(near[k]);
    const auto blocks = p.W.row_blocks(near[k]);
    for (std::size_t j = 0; j < columns.size(); ++j)
      if (held(columns[j]) and set_of[columns[j]] == set_of[held_list[0]])
        s.C.block(D * k, at[columns[j]], D, 1) = blocks[j].col(0);
  }
  for (const std::int32_t a : held_list)
    at[a] = -1;
  for (const std::int32_t b : near)
    at[b] = -1;
  s.factor(N, B);
  s.held = std::move(held_list);
  s.neighbours = std::move(near);
  return s;
}

template <int D>
void FrictionlessCondensation<D>::Sets::reduce(
    const FrictionContactProblem<D>& p)
{
  const std::size_t n = p.num_contacts();
  kept.clear();
  for (std::size_t a = 0; a < n; ++a)
  {
    const bool swept = !held(static_cast<std::int32_t>(a));
    place[a] = swept ? static_cast<std::int32_t>(kept.size()) : -1;
    if (swept)
      kept.push_back(static_cast<std::int32_t>(a));
  }
  const std::vector<std::vector<std::int32_t>> near = neighbours(p.W);
  held_sets.clear();
  for (std::size_t s = 0; s < sets.size(); ++s)
  {
    std::vector<std::int32_t> list;
    for (const std::int32_t a : sets[s])
      if (hold[a])
        list.push_back(a);
    if (!list.empty())
      held_sets.push_back(condense(p, std::move(list), near[s]));
  }
  assemble(p, reduced.emplace());
  reduced_hold = hold;
  plan.reset();
}

template <int D>
void FrictionlessCondensation<D>::Sets::assemble(
    const FrictionContactProblem<D>& p, FrictionContactProblem<D>& red) const
{
  const std::size_t nk = kept.size();
  red.W = DelassusMatrixD<D>(nk);
  red.q.resize(D * nk);
  red.friction.resize(nk);
  if (!p.cohesion.empty())
    red.cohesion.resize(nk);
  std::size_t blocks = 0;
  for (const std::int32_t a : kept)
    blocks += p.W.row_columns(a).size();
  for (const HeldSet& s : held_sets)
    if (!s.as_terms())
      blocks += s.neighbours.size() * s.neighbours.size();
  red.W.reserve(blocks);
  std::vector<typename DelassusMatrixD<D>::Block> diagonal(nk);
  for (std::size_t i = 0; i < nk; ++i)
  {
    const std::int32_t a = kept[i];
    diagonal[i] = p.W.diagonal(a);
    const auto columns = p.W.row_columns(a);
    const auto row = p.W.row_blocks(a);
    for (std::size_t k = 0; k < columns.size(); ++k)
      if (place[columns[k]] >= 0)
        red.W.add_block(i, place[columns[k]], row[k]);
    red.friction[i] = p.friction[a];
    if (!p.cohesion.empty())
      red.cohesion[i] = p.cohesion[a];
  }
  for (const HeldSet& s : held_sets)
    s.subtract_correction(place, red.W, diagonal);
  for (std::size_t i = 0; i < nk; ++i)
    red.W.add_block(i, i, definite(diagonal[i]));
  for (const auto& term : p.W.rank_one_terms())
  {
    std::vector<std::int32_t> contacts(term.contacts.size());
    for (std::size_t k = 0; k < contacts.size(); ++k)
      contacts[k] = place[term.contacts[k]];
    red.W.add_rank_one(contacts, term.g, term.inverse_mass, false);
  }
  red.W.finalize();
}

template <int D>
void FrictionlessCondensation<D>::Sets::set_q(
    const FrictionContactProblem<D>& p, std::span<const double> r,
    std::vector<double>& r_kept)
{
  FrictionContactProblem<D>& red = *reduced;
  r_kept.resize(D * kept.size());
  for (std::size_t i = 0; i < kept.size(); ++i)
    for (int j = 0; j < D; ++j)
    {
      red.q[D * i + j] = p.q[D * kept[i] + j];
      r_kept[D * i + j] = r[D * kept[i] + j];
    }
  for (HeldSet& s : held_sets)
  {
    Eigen::VectorXd qs(static_cast<Eigen::Index>(s.held.size()));
    for (std::size_t i = 0; i < s.held.size(); ++i)
      qs(static_cast<Eigen::Index>(i)) = p.q[D * s.held[i]];
    s.y = s.ldlt.solve(qs);
    const Eigen::VectorXd dq = s.C * s.y;
    for (std::size_t k = 0; k < s.neighbours.size(); ++k)
      for (int j = 0; j < D; ++j)
        red.q[D * place[s.neighbours[k]] + j] -=
            dq(D * static_cast<Eigen::Index>(k) + j);
  }
}

template <int D>
void FrictionlessCondensation<D>::Sets::recover(std::span<const double> r_kept,
                                                std::span<double> r) const
{
  for (std::size_t a = 0; a < place.size(); ++a)
    for (int j = 0; j < D; ++j)
      r[D * a + j] = place[a] >= 0 ? r_kept[D * place[a] + j] : 0.0;
  // (a held contact's tangential reactions stay 0: it is frictionless)
  for (const HeldSet& s : held_sets)
  {
    const auto np = static_cast<Eigen::Index>(s.neighbours.size());
    Eigen::VectorXd rp(D * np);
    for (Eigen::Index k = 0; k < np; ++k)
      for (int j = 0; j < D; ++j)
        rp(D * k + j) = r_kept[D * place[s.neighbours[k]] + j];
    const Eigen::VectorXd rs = -(s.y + s.X * rp);
    for (std::size_t i = 0; i < s.held.size(); ++i)
      r[D * s.held[i]] = rs(static_cast<Eigen::Index>(i));
  }
}

template <int D>
int FrictionlessCondensation<D>::Sets::release(std::span<double> r,
                                               double threshold)
{
  int released = 0;
  for (const auto& set : sets)
    for (const std::int32_t a : set)
      if (hold[a] and r[D * a] < -threshold)
      {
        hold[a] = 0;
        r[D * a] = 0;
        ++released;
      }
  return released;
}

template <int D>
FrictionlessCondensation<D>::FrictionlessCondensation(
    const FrictionContactProblem<D>& problem, std::size_t largest_set)
    : _sets(std::make_unique<Sets>(problem, largest_set))
{
}

template <int D>
FrictionlessCondensation<D>::~FrictionlessCondensation() = default;
template <int D>
FrictionlessCondensation<D>::FrictionlessCondensation(
    FrictionlessCondensation&&) noexcept = default;
template <int D>
FrictionlessCondensation<D>& FrictionlessCondensation<D>::operator=(
    FrictionlessCondensation&&) noexcept = default;

template <int D> std::size_t FrictionlessCondensation<D>::condensed() const
{
  std::size_t n = 0;
  for (const auto& set : _sets->sets)
    n += set.size();
  return n;
}

template <int D>
NlgsResult FrictionlessCondensation<D>::Sets::round(
    const FrictionContactProblem<D>& p, std::span<double> r,
    std::span<double> u, const NlgsOptions& options,
    NlgsOptions& reduced_options)
{
  if (!reduced or hold != reduced_hold)
    reduce(p);
  std::vector<double> r_kept;
  set_q(p, r, r_kept);
  std::vector<double> u_kept(r_kept.size());
  if (!plan and renumbers(*reduced, reduced_options))
    plan.emplace(*reduced, reduced_options);
  NlgsResult nlgs =
      solve_nlgs(*reduced, std::span<double>(r_kept), u_kept, reduced_options,
                 nullptr, plan ? &*plan : nullptr);
  recover(r_kept, r);
  const NaturalMapError e = compute_error(p, r, u, options.q_zero_tolerance);
  const bool done = e.value <= options.tolerance;
  // Pulls beyond a thousandth of what the tolerance allows let go;
  // smaller ones are within the error reported
  const int released =
      done ? 0 : release(r, 1e-3 * options.tolerance * e.scale);
  // The reduced problem met its tolerance and the whole one did not (its
  // error is not the reduced one's: the Hertz octant's 1.0-1.4e-10
  // against 0.9e-10): the next round asks for less, at most 1,000 times
  if (!done and released == 0 and nlgs.converged)
    reduced_options.tolerance =
        std::max(0.5 * reduced_options.tolerance * options.tolerance / e.value,
                 1e-3 * options.tolerance);
  nlgs.error = e.value;
  nlgs.converged = done;
  return nlgs;
}

template <int D>
CondensedResult
FrictionlessCondensation<D>::solve(const FrictionContactProblem<D>& problem,
                                   std::span<double> r, std::span<double> u,
                                   const NlgsOptions& options)
{
  Sets& s = *_sets;
  if (&problem.W != s.W or problem.num_contacts() != s.place.size())
    throw std::invalid_argument(
        "FrictionlessCondensation::solve: another W than its own");
  CondensedResult result;
  result.condensed = condensed();
  if (result.condensed == 0 or is_q_zero(problem, options.q_zero_tolerance))
  {
    result.nlgs = solve_nlgs(problem, r, u, options);
    result.rounds = 1;
    return result;
  }
  if (!options.warm_start)
    std::fill(r.begin(), r.end(), 0.0);
  s.hold_initial(problem, r);
  NlgsOptions reduced_options = options;
  reduced_options.warm_start = true;
  int sweeps = 0, extrapolations = 0;
  // Held, the sweeps get half the budget; the rest sweeps the whole
  // problem from their answer (a held set kept from the step's first
  // Newton iteration, only shrinking, left a dense step's solve at 6e-6
  // after 20,000 sweeps, where the whole problem swept from its start met
  // 1e-6 in 20)
  const int held_budget = std::max(options.max_sweeps / 2, 1);
  for (;;)
  {
    // A round's sweeps are bounded, so that a held contact that should let
    // go does not keep the sweeps from an answer for all of them (the
    // piston at 2 m/s: 20,000 sweeps stalled at 1e-5 with 14 to let go)
    reduced_options.max_sweeps =
        std::min(std::max(held_budget - sweeps, 0), round_sweeps);
    NlgsResult nlgs = s.round(problem, r, u, options, reduced_options);
    sweeps += nlgs.iterations;
    extrapolations += nlgs.extrapolations;
    ++result.rounds;
    if (nlgs.converged or sweeps >= held_budget or result.rounds >= max_rounds)
    {
      nlgs.iterations = sweeps;
      nlgs.extrapolations = extrapolations;
      result.nlgs = nlgs;
      result.held = static_cast<std::size_t>(
          std::count(s.hold.begin(), s.hold.end(), char(1)));
      result.held_terms = s.reduced->W.rank_one_terms().size() -
                          problem.W.rank_one_terms().size();
      if (!nlgs.converged and sweeps < options.max_sweeps)
        sweep_whole(problem, r, u, options, result);
      return result;
    }
  }
}

template <int D>
void FrictionlessCondensation<D>::sweep_whole(
    const FrictionContactProblem<D>& problem, std::span<double> r,
    std::span<double> u, const NlgsOptions& options, CondensedResult& result)
{
  NlgsOptions whole = options;
  whole.warm_start = true;
  whole.max_sweeps = options.max_sweeps - result.nlgs.iterations;
  const NlgsResult swept = solve_nlgs(problem, r, u, whole);
  result.swept_whole = swept.iterations;
  const int held_sweeps = result.nlgs.iterations,
            held_extrapolations = result.nlgs.extrapolations;
  result.nlgs = swept;
  result.nlgs.iterations += held_sweeps;
  result.nlgs.extrapolations += held_extrapolations;
}

bool softpack::contact::condenses(const std::string& name, int dim)
{
  if (name == "auto")
    return dim == 3;
  if (name == "off")
    return false;
  if (name != "on")
    throw std::invalid_argument("contact.nlgs_condensation \"" + name +
                                "\": must be \"auto\", \"on\" or \"off\"");
  if (dim != 3)
    throw std::invalid_argument(
        "contact.nlgs_condensation = \"on\": 3D runs only (a 2D problem "
        "is swept whole, or domain by domain on several processes)");
  return true;
}

template class softpack::contact::FrictionlessCondensation<2>;
template class softpack::contact::FrictionlessCondensation<3>;
