#include "nlgs.h"

#include "gauss_seidel.h"

#include "drift_extrapolation.h"
#include "error.h"
#include "local_solver.h"
#include "running_sums.h"
#include "sweep_split.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <omp.h>
#include <optional>
#include <ranges>
#include <stdexcept>
#include <string>

using namespace softpack::contact;

namespace
{
using namespace softpack::contact::gauss_seidel;
//-----------------------------------------------------------------------------
template <int D>
void check_arguments(const FrictionContactProblem<D>& problem,
                     std::span<double> r, std::span<double> u,
                     const NlgsOptions& options)
{
  const std::size_t n = D * problem.num_contacts();
  if (!problem.W.finalized() or problem.W.num_contacts() != n / D or
      problem.q.size() != n)
    throw std::invalid_argument(
        "solve_nlgs: problem not validated (W, q, friction "
        "sizes or W not finalized)");
  if (r.size() != n or u.size() != n)
    throw std::invalid_argument("solve_nlgs: r and u need " +
                                std::to_string(D) + " per contact");
  if (!(options.relaxation > 0 and options.relaxation < 2))
    throw std::invalid_argument("solve_nlgs: relaxation must be in (0, 2)");
  if (!(options.tolerance >= 0) or options.max_sweeps < 0)
    throw std::invalid_argument("solve_nlgs: negative tolerance or sweeps");
}
//-----------------------------------------------------------------------------
/// A plan made for another problem or other options is refused (its
/// numbering would scramble the reactions)
template <int D>
void check_plan(const SweepPlanD<D>& plan,
                const FrictionContactProblem<D>& problem,
                const NlgsOptions& options)
{
  if (plan.problem.num_contacts() != problem.num_contacts() or
      plan.problem.W.num_offdiagonal_blocks() !=
          problem.W.num_offdiagonal_blocks() or
      plan.split != splits(problem, options) or
      plan.sweep_order != options.order)
    throw std::invalid_argument(
        "solve_nlgs: the sweep plan was made for another W or other "
        "options (order, split)");
}
//-----------------------------------------------------------------------------
/// The sets swept in the order the options ask for (SweepOrder)
std::vector<std::int32_t> in_order(std::vector<std::int32_t> contacts,
                                   const NlgsOptions& options)
{
  if (options.order == SweepOrder::contact)
    return contacts;
  std::vector<std::int32_t> alternate;
  alternate.reserve(contacts.size());
  for (std::size_t first : {0, 1})
    for (std::size_t i = first; i < contacts.size(); i += 2)
      alternate.push_back(contacts[i]);
  return alternate;
}
//-----------------------------------------------------------------------------
/// The sums of a split sweep, added in one fixed order: the same bits
/// whether the two parts ran on one thread or two.
SweepSums combine(const SweepSums& p0, const SweepSums& p1, const SweepSums& s)
{
  return {(p0.change + p1.change) + s.change, (p0.norm + p1.norm) + s.norm};
}
//-----------------------------------------------------------------------------
/// The stopping test and the relaxation fallback, applied after each sweep
/// (Siconos' "light with full final" test, see solve_nlgs()).
template <int D> class Monitor
{
public:
  /// @param[in] rows The contacts whose error terms are summed, in this
  ///   order (empty and no domain: all, ascending)
  /// @param[in] domain When given, the sums are reduced over the domains
  Monitor(const FrictionContactProblem<D>& problem, std::span<double> r,
          std::span<double> u, const NlgsOptions& options, NlgsResult& result,
          std::span<const std::int32_t> rows,
          const SweepDomain* domain = nullptr)
      : omega(options.relaxation), _problem(problem), _r(r), _u(u),
        _options(options), _result(result), _domain(domain), _rows(rows),
        _working_tolerance(options.tolerance)
  {
  }
  /// Account for a finished sweep; false when the solve should stop.
  bool after_sweep(const SweepSums& sums);
  /// The full error at the end (computed unless the last test did)
  void finish();
  /// The full error of the whole problem (a domain's rows read current
  /// reactions after a whole sweep: the neighbours' interface ones came in
  /// its exchanges)
  void full_error()
  {
    if (_rows.empty() and !_domain)
    {
      _full = compute_error(_problem, _r, _u, _options.q_zero_tolerance);
      return;
    }
    const ErrorSums mine = error_sums(_problem, _r, _u, _rows);
    double sums[4] = {mine.residual, mine.r, mine.u, mine.q};
    if (_domain)
      _domain->reduce(sums);
    _full = natural_map_error({sums[0], sums[1], sums[2], sums[3]},
                              is_q_zero(_problem, _options.q_zero_tolerance));
  }
  /// Relaxation of the next sweep
  double omega;
  /// Sweeps so far
  int sweeps() const { return _result.iterations; }

private:
  const FrictionContactProblem<D>& _problem;
  std::span<double> _r, _u;
  const NlgsOptions& _options;
  NlgsResult& _result;
  const SweepDomain* _domain;
  /// The contacts of the full error, in the order of its sums (a domain's
  /// own; or every contact in its original order, of a renumbered problem),
  /// read in place: the caller keeps them for the solve
  std::span<const std::int32_t> _rows;
  double _working_tolerance;
  double _window_start_error = std::numeric_limits<double>::infinity();
  bool _full_error_current = false;
  NaturalMapError _full;
};
//-----------------------------------------------------------------------------
template <int D> bool Monitor<D>::after_sweep(const SweepSums& sums)
{
  ++_result.iterations;
  const double scale = std::sqrt(sums.norm);
  _result.cheap_error = std::sqrt(sums.change);
  if (scale > std::numeric_limits<double>::epsilon())
    _result.cheap_error /= scale;
  _full_error_current = false;
  if (!std::isfinite(_result.cheap_error))
    return false;
  if (omega != 1.0 and _options.relaxation_window > 0 and
      _result.iterations % _options.relaxation_window == 0)
  {
    if (_result.cheap_error > 0.9 * _window_start_error)
    {
      omega = 1.0;
      _result.relaxation_dropped = true;
    }
    _window_start_error = _result.cheap_error;
  }
  const bool more = _result.iterations < _options.max_sweeps;
  const bool scheduled = _options.full_error_interval > 0 and
                         _result.iterations % _options.full_error_interval == 0;
  if (_result.cheap_error > _working_tolerance and !scheduled)
    return more;
  full_error();
  _full_error_current = true;
  if (_full.value <= _options.tolerance)
    return false;
  if (_full.value > 0)
    _working_tolerance = _result.cheap_error / _full.value * _options.tolerance;
  return more;
}
//-----------------------------------------------------------------------------
template <int D> void Monitor<D>::finish()
{
  if (!_full_error_current)
    full_error();
  _result.error = _full.value;
  _result.converged = _full.value <= _options.tolerance;
}
//-----------------------------------------------------------------------------
/// A velocity-updated solve makes its velocities again from r after this
/// many sweeps (NlgsUpdate::velocity)
constexpr int velocity_reset_sweeps = 50;
//-----------------------------------------------------------------------------
/// Sweeps of a swept problem: its two parts on two threads when `threads`
/// > 1 (the separator on one, between two barriers), else all in order.
/// The contacts of W's rank-one terms are in the separator of a split
/// (split_for_two_threads), so that one thread alone updates the terms'
/// sums; they are made again from r between two sweeps, on one thread.
template <int D>
void swept_sweeps(const SweepPlanD<D>& swept, double* r, int threads,
                  bool update_velocities, Monitor<D>& monitor,
                  DriftExtrapolation<D>* drift)
{
  const FrictionContactProblem<D>& problem = swept.problem;
  const std::size_t bounds[4] = {0, swept.ends[0], swept.ends[1],
                                 problem.num_contacts()};
  RunningSums<D> terms(problem.W);
  terms.reset(r);
  // the parts' contacts keep velocities, the separator's read their rows
  std::optional<Velocities<D>> velocities;
  if (update_velocities)
  {
    velocities.emplace();
    velocities->kept = bounds[2];
    velocities->reset(problem, r);
  }
  Velocities<D>* v = velocities ? &*velocities : nullptr;
  SweepSums partial[2];
  bool more = true;
#pragma omp parallel num_threads(2) if (threads > 1)
  {
    const int t = omp_get_thread_num();
    const int parts_here = omp_get_num_threads() > 1 ? 1 : 2;
    while (more)
    {
      for (int k = t; k < t + parts_here; ++k)
        partial[k] = sweep(problem, r, terms.data(), monitor.omega, bounds[k],
                           bounds[k + 1], v);
#pragma omp barrier
#pragma omp single
      {
        const SweepSums s = sweep(problem, r, terms.data(), monitor.omega,
                                  bounds[2], bounds[3], v);
        more = monitor.after_sweep(combine(partial[0], partial[1], s));
        const bool moved = more and drift and
                           drift->after_sweep({r, D * problem.num_contacts()});
        terms.reset(r);
        if (v and more and
            (moved or monitor.sweeps() % velocity_reset_sweeps == 0))
          v->reset(problem, r);
      } // the implicit barrier: `more` and `omega` are read after it
    }
  }
}
//-----------------------------------------------------------------------------
/// Sweeps of one domain's contacts stage by stage, exchanging after each
/// interface stage (SweepDomain).
template <int D>
void domain_sweeps(const FrictionContactProblem<D>& problem,
                   std::span<double> r, const SweepDomain& domain,
                   const NlgsOptions& options, Monitor<D>& monitor)
{
  std::vector<std::vector<std::int32_t>> stages;
  for (const std::vector<std::int32_t>& stage : domain.stages)
    stages.push_back(in_order(stage, options));
  // A rank-one term's contacts on several domains are interface contacts
  // that read one another (plan_domain): after each exchange this domain
  // holds all their current reactions and makes the sums again.
  RunningSums<D> terms(problem.W);
  bool more = true;
  while (more)
  {
    double sums[2] = {0, 0};
    terms.reset(r.data());
    for (std::size_t s = 0; s < domain.stages.size(); ++s)
    {
      const SweepSums part =
          sweep(problem, r.data(), terms.data(), monitor.omega, stages[s]);
      sums[0] += part.change;
      sums[1] += part.norm;
      if (s > 0)
      {
        domain.exchange(static_cast<int>(s), r);
        terms.reset(r.data());
      }
    }
    domain.reduce(sums);
    more = monitor.after_sweep({sums[0], sums[1]});
  }
}
//-----------------------------------------------------------------------------
/// solve_nlgs() on the plan's renumbered problem with the caller's q; r and
/// u in the caller's numbering
template <int D>
void solve_swept(const FrictionContactProblem<D>& problem, std::span<double> r,
                 std::span<double> u, const NlgsOptions& options,
                 SweepPlanD<D>& plan, NlgsResult& result)
{
  const std::size_t n = problem.num_contacts();
  std::vector<double> r_here(D * n), u_here(D * n);
  for (std::size_t i = 0; i < n; ++i)
    for (int j = 0; j < D; ++j)
    {
      r_here[D * i + j] = r[D * plan.order[i] + j];
      plan.problem.q[D * i + j] = problem.q[D * plan.order[i] + j];
    }
  Monitor<D> monitor(plan.problem, r_here, u_here, options, result,
                     plan.position);
  std::optional<DriftExtrapolation<D>> drift;
  if (extrapolates<D>(options))
    drift.emplace(plan.problem);
  swept_sweeps(plan, r_here.data(), plan.split ? options.threads : 1,
               updates_velocities<D>(options), monitor,
               drift ? &*drift : nullptr);
  monitor.finish();
  result.extrapolations = drift ? drift->extrapolations() : 0;
  for (std::size_t i = 0; i < n; ++i)
    for (int j = 0; j < D; ++j)
    {
      r[D * plan.order[i] + j] = r_here[D * i + j];
      u[D * plan.order[i] + j] = u_here[D * i + j];
    }
}
} // namespace

//-----------------------------------------------------------------------------
SweepOrder softpack::contact::sweep_order(const std::string& name)
{
  if (name == "contact")
    return SweepOrder::contact;
  if (name == "alternate")
    return SweepOrder::alternate;
  throw std::invalid_argument("sweep order \"" + name +
                              "\": must be \"contact\" or \"alternate\"");
}
//-----------------------------------------------------------------------------
NlgsUpdate softpack::contact::nlgs_update(const std::string& name)
{
  if (name == "row")
    return NlgsUpdate::row;
  if (name == "velocity")
    return NlgsUpdate::velocity;
  if (name == "auto")
    return NlgsUpdate::automatic;
  throw std::invalid_argument("NLGS update \"" + name +
                              "\": must be \"row\", \"velocity\" or \"auto\"");
}
//-----------------------------------------------------------------------------
NlgsExtrapolation softpack::contact::nlgs_extrapolation(const std::string& name)
{
  if (name == "auto")
    return NlgsExtrapolation::automatic;
  if (name == "on")
    return NlgsExtrapolation::on;
  if (name == "off")
    return NlgsExtrapolation::off;
  throw std::invalid_argument("NLGS extrapolation \"" + name +
                              "\": must be \"auto\", \"on\" or \"off\"");
}
//-----------------------------------------------------------------------------
template <int D>
SweepPlanD<D>::SweepPlanD(const FrictionContactProblem<D>& problem,
                          const NlgsOptions& options)
    : split(splits(problem, options)), sweep_order(options.order)
{
  const std::size_t n = problem.num_contacts();
  if (split)
  {
    SweepSplit sets = split_for_two_threads(problem.W);
    int k = 0;
    for (std::vector<std::int32_t>* set :
         {&sets.part[0], &sets.part[1], &sets.separator})
    {
      const std::vector<std::int32_t> ordered =
          in_order(std::move(*set), options);
      order.insert(order.end(), ordered.begin(), ordered.end());
      if (k < 2)
        ends[k++] = order.size();
    }
  }
  else
  {
    std::vector<std::int32_t> all(n);
    std::iota(all.begin(), all.end(), 0);
    order = in_order(std::move(all), options);
    ends[0] = ends[1] = n;
  }
  position.resize(n);
  this->problem.q.resize(D * n);
  this->problem.friction.resize(n);
  this->problem.cohesion.resize(problem.cohesion.empty() ? 0 : n);
  for (std::size_t i = 0; i < n; ++i)
  {
    position[order[i]] = static_cast<std::int32_t>(i);
    this->problem.friction[i] = problem.friction[order[i]];
    if (!problem.cohesion.empty())
      this->problem.cohesion[i] = problem.cohesion[order[i]];
  }
  this->problem.W = problem.W.renumbered(order);
}
//-----------------------------------------------------------------------------
template struct softpack::contact::SweepPlanD<2>;
template struct softpack::contact::SweepPlanD<3>;
//-----------------------------------------------------------------------------
namespace
{
template <int D>
NlgsResult solve(const FrictionContactProblem<D>& problem, std::span<double> r,
                 std::span<double> u, const NlgsOptions& options,
                 const SweepDomain* domain, SweepPlanD<D>* plan)
{
  check_arguments(problem, r, u, options);
  if (domain and plan)
    throw std::invalid_argument("solve_nlgs: a domain or a plan, not both");
  if (!options.warm_start)
    std::fill(r.begin(), r.end(), 0.0);

  NlgsResult result;
  result.q_zero = is_q_zero(problem, options.q_zero_tolerance);
  if (result.q_zero)
    std::fill(r.begin(), r.end(), 0.0);

  const bool sweeps = !result.q_zero and options.max_sweeps > 0;
  if (domain)
  {
    std::vector<std::int32_t> rows;
    for (const std::vector<std::int32_t>& stage : domain->stages)
      rows.insert(rows.end(), stage.begin(), stage.end());
    Monitor<D> monitor(problem, r, u, options, result, rows, domain);
    if (sweeps)
      domain_sweeps(problem, r, *domain, options, monitor);
    monitor.finish();
  }
  else if (sweeps and (plan or renumbers(problem, options)))
  {
    if (plan)
      check_plan(*plan, problem, options);
    std::optional<SweepPlanD<D>> own;
    if (!plan)
      own.emplace(problem, options);
    solve_swept(problem, r, u, options, plan ? *plan : *own, result);
  }
  else
  {
    Monitor<D> monitor(problem, r, u, options, result, {});
    RunningSums<D> terms(problem.W);
    std::optional<DriftExtrapolation<D>> drift;
    if (extrapolates<D>(options))
      drift.emplace(problem);
    bool more = sweeps;
    while (more)
    {
      terms.reset(r.data());
      more =
          monitor.after_sweep(sweep(problem, r.data(), terms.data(),
                                    monitor.omega, 0, problem.num_contacts()));
      if (more and drift)
        drift->after_sweep(r);
    }
    monitor.finish();
    result.extrapolations = drift ? drift->extrapolations() : 0;
  }
  // The reactions are made whole (the caller's next Newton iterate needs
  // every impulse); u is not: each domain has it at its own contacts.
  if (domain)
    domain->gather(r);
  return result;
}
} // namespace
//-----------------------------------------------------------------------------
NlgsResult
softpack::contact::solve_nlgs(const FrictionContactProblem2D& problem,
                              std::span<double> r, std::span<double> u,
                              const NlgsOptions& options,
                              const SweepDomain* domain, SweepPlan* plan)
{
  return solve(problem, r, u, options, domain, plan);
}
//-----------------------------------------------------------------------------
NlgsResult
softpack::contact::solve_nlgs(const FrictionContactProblem3D& problem,
                              std::span<double> r, std::span<double> u,
                              const NlgsOptions& options,
                              const SweepDomain* domain, SweepPlan3D* plan)
{
  return solve(problem, r, u, options, domain, plan);
}
//-----------------------------------------------------------------------------
