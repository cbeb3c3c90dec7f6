#include "nlgs.h"

#include "error.h"
#include "local_solver.h"
#include "sweep_split.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <omp.h>
#include <stdexcept>

using namespace softpack::contact;

namespace
{
//-----------------------------------------------------------------------------
void check_arguments(const FrictionContactProblem2D& problem,
                     std::span<double> r, std::span<double> u,
                     const NlgsOptions& options)
{
  const std::size_t n = 2 * problem.num_contacts();
  if (!problem.W.finalized() or problem.W.num_contacts() != n / 2 or
      problem.q.size() != n)
    throw std::invalid_argument(
        "solve_nlgs: problem not validated (W, q, friction "
        "sizes or W not finalized)");
  if (r.size() != n or u.size() != n)
    throw std::invalid_argument("solve_nlgs: r and u need 2 per contact");
  if (!(options.relaxation > 0 and options.relaxation < 2))
    throw std::invalid_argument("solve_nlgs: relaxation must be in (0, 2)");
  if (!(options.tolerance >= 0) or options.max_sweeps < 0)
    throw std::invalid_argument("solve_nlgs: negative tolerance or sweeps");
}
//-----------------------------------------------------------------------------
/// Squared change of the reactions and squared norm of the new ones over
/// (part of) a sweep.
struct SweepSums
{
  double change = 0, norm = 0;
};
//-----------------------------------------------------------------------------
/// Gauss–Seidel over the given contacts, in their order (all contacts in
/// order when `contacts` is empty and `all` is set).
SweepSums sweep(const FrictionContactProblem2D& problem, double* r,
                double omega, std::span<const std::int32_t> contacts,
                bool all = false)
{
  const DelassusMatrix& W = problem.W;
  const std::size_t count = all ? problem.num_contacts() : contacts.size();
  SweepSums sums;
  for (std::size_t i = 0; i < count; ++i)
  {
    const std::size_t a = all ? i : static_cast<std::size_t>(contacts[i]);
    const Eigen::Vector2d qa =
        Eigen::Vector2d(problem.q[2 * a], problem.q[2 * a + 1]) +
        W.offdiagonal_product(a, r);
    const double mu = problem.friction[a];
    Eigen::Vector2d ra = solve_local(W.diagonal(a), qa, mu).r;
    const Eigen::Vector2d old(r[2 * a], r[2 * a + 1]);
    if (omega != 1.0)
    {
      ra = omega * ra + (1.0 - omega) * old;
      if (omega > 1.0)
        ra = project_on_cone(ra, mu);
    }
    sums.change += (ra - old).squaredNorm();
    sums.norm += ra.squaredNorm();
    r[2 * a] = ra[0];
    r[2 * a + 1] = ra[1];
  }
  return sums;
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
class Monitor
{
public:
  Monitor(const FrictionContactProblem2D& problem, std::span<double> r,
          std::span<double> u, const NlgsOptions& options, NlgsResult& result,
          const SweepDomain* domain)
      : omega(options.relaxation), _problem(problem), _r(r), _u(u),
        _options(options), _result(result), _domain(domain),
        _working_tolerance(options.tolerance)
  {
    if (domain)
      for (const std::vector<std::int32_t>& stage : domain->stages)
        _rows.insert(_rows.end(), stage.begin(), stage.end());
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
    if (!_domain)
    {
      _full = compute_error(_problem, _r, _u, _options.q_zero_tolerance);
      return;
    }
    const ErrorSums mine = error_sums(_problem, _r, _u, _rows);
    double sums[4] = {mine.residual, mine.r, mine.u, mine.q};
    _domain->reduce(sums);
    _full = natural_map_error({sums[0], sums[1], sums[2], sums[3]},
                              is_q_zero(_problem, _options.q_zero_tolerance));
  }
  /// Relaxation of the next sweep
  double omega;

private:
  const FrictionContactProblem2D& _problem;
  std::span<double> _r, _u;
  const NlgsOptions& _options;
  NlgsResult& _result;
  const SweepDomain* _domain;
  /// The domain's contacts (all stages)
  std::vector<std::int32_t> _rows;
  double _working_tolerance;
  double _window_start_error = std::numeric_limits<double>::infinity();
  bool _full_error_current = false;
  NaturalMapError _full;
};
//-----------------------------------------------------------------------------
bool Monitor::after_sweep(const SweepSums& sums)
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
void Monitor::finish()
{
  if (!_full_error_current)
    full_error();
  _result.error = _full.value;
  _result.converged = _full.value <= _options.tolerance;
}
//-----------------------------------------------------------------------------
/// The split of split_for_two_threads(), each set in the options' order
SweepSplit split_in_order(const DelassusMatrix& W, const NlgsOptions& options)
{
  SweepSplit split = split_for_two_threads(W);
  for (std::vector<std::int32_t>* set :
       {&split.part[0], &split.part[1], &split.separator})
    *set = in_order(std::move(*set), options);
  return split;
}
//-----------------------------------------------------------------------------
/// Sweeps in the split order, the two parts on two threads when there are
/// two (the separator on one, between two barriers).
void split_sweeps(const FrictionContactProblem2D& problem, double* r,
                  const SweepSplit& split, int threads, Monitor& monitor)
{
  SweepSums partial[2];
  bool more = true;
#pragma omp parallel num_threads(2) if (threads > 1)
  {
    const int t = omp_get_thread_num();
    const int parts_here = omp_get_num_threads() > 1 ? 1 : 2;
    while (more)
    {
      for (int k = 0; k < parts_here; ++k)
        partial[t + k] = sweep(problem, r, monitor.omega, split.part[t + k]);
#pragma omp barrier
#pragma omp single
      {
        const SweepSums s = sweep(problem, r, monitor.omega, split.separator);
        more = monitor.after_sweep(combine(partial[0], partial[1], s));
      } // the implicit barrier: `more` and `omega` are read after it
    }
  }
}
//-----------------------------------------------------------------------------
/// Sweeps of one domain's contacts stage by stage, exchanging after each
/// interface stage (SweepDomain).
void domain_sweeps(const FrictionContactProblem2D& problem, std::span<double> r,
                   const SweepDomain& domain, const NlgsOptions& options,
                   Monitor& monitor)
{
  std::vector<std::vector<std::int32_t>> stages;
  for (const std::vector<std::int32_t>& stage : domain.stages)
    stages.push_back(in_order(stage, options));
  bool more = true;
  while (more)
  {
    double sums[2] = {0, 0};
    for (std::size_t s = 0; s < domain.stages.size(); ++s)
    {
      const SweepSums part = sweep(problem, r.data(), monitor.omega, stages[s]);
      sums[0] += part.change;
      sums[1] += part.norm;
      if (s > 0)
        domain.exchange(static_cast<int>(s), r);
    }
    domain.reduce(sums);
    more = monitor.after_sweep({sums[0], sums[1]});
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
NlgsResult softpack::contact::solve_nlgs(
    const FrictionContactProblem2D& problem, std::span<double> r,
    std::span<double> u, const NlgsOptions& options, const SweepDomain* domain)
{
  check_arguments(problem, r, u, options);
  if (!options.warm_start)
    std::fill(r.begin(), r.end(), 0.0);

  NlgsResult result;
  result.q_zero = is_q_zero(problem, options.q_zero_tolerance);
  if (result.q_zero)
    std::fill(r.begin(), r.end(), 0.0);

  Monitor monitor(problem, r, u, options, result, domain);
  const bool split = options.split_min_contacts > 0 and
                     problem.num_contacts() >= options.split_min_contacts;
  if (!result.q_zero and options.max_sweeps > 0)
  {
    if (domain)
      domain_sweeps(problem, r, *domain, options, monitor);
    else if (split)
      split_sweeps(problem, r.data(), split_in_order(problem.W, options),
                   options.threads, monitor);
    else if (options.order != SweepOrder::contact)
    {
      std::vector<std::int32_t> all(problem.num_contacts());
      std::iota(all.begin(), all.end(), 0);
      all = in_order(std::move(all), options);
      while (monitor.after_sweep(sweep(problem, r.data(), monitor.omega, all)))
        ;
    }
    else
      while (monitor.after_sweep(
          sweep(problem, r.data(), monitor.omega, {}, true)))
        ;
  }
  monitor.finish();
  // The reactions are made whole (the caller's next Newton iterate needs
  // every impulse); u is not: each domain has it at its own contacts.
  if (domain)
    domain->gather(r);
  return result;
}
//-----------------------------------------------------------------------------
