#include "newton_loop.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace softpack::dynamics
{
namespace
{
/// The largest |entry|, or infinity if an entry is not finite (std::max
/// would pass over a NaN)
double max_abs(const std::vector<double>& v)
{
  double m = 0;
  for (double x : v)
  {
    if (!std::isfinite(x))
      return std::numeric_limits<double>::infinity();
    m = std::max(m, std::abs(x));
  }
  return m;
}
} // namespace

NewtonLoop::Vectors NewtonLoop::residual(const Vectors& vk,
                                         const Vectors& f_int) const
{
  // r = (M + h th C) v_k + h th (F_int(q_k) - F_ext) - b
  const double h = _s._h, th = _s._options.time.theta;
  const std::span<const int> local = _s._bodies.local_bodies();
  const auto nl = static_cast<int>(local.size());
  Vectors r(_s._bodies.num_bodies());
#pragma omp parallel for schedule(dynamic) if (nl >= 16)
  for (int i = 0; i < nl; ++i)
  {
    const int b = local[i];
    r[b] = combined_product(_s._A, _s._kbar.mass(b), _s._K[b], vk[b]) +
           h * th * (f_int[b] - _start.f_ext_b[b]) - _start.known[b];
  }
  return r;
}

void NewtonLoop::solve_contacts(const Vectors& vk, const Vectors& r,
                                Vectors& v_new)
{
  // The free velocity v_k - Kbar^-1 r of each body that carries a contact
  // (one solve), read at its contact nodes; after the contact solve the
  // impulses' response Kbar^-1 H R is added (a second solve, whose
  // right-hand side vanishes but at the contact nodes). Reading the free
  // velocity off whole compliance columns instead saved no time and made
  // the columns the largest item of a crowded run's memory.
  auto t0 = clock::now();
  std::vector<double> U_free;
  const Vectors free = free_velocity(vk, r, U_free);
  _report.seconds.solves += seconds_since(t0);
  t0 = clock::now();
  solve_problem(U_free);
  _report.seconds.nlgs += seconds_since(t0);
  t0 = clock::now();
  add_impulse_response(free, v_new);
  _report.seconds.solves += seconds_since(t0);
}

NewtonLoop::Vectors NewtonLoop::free_velocity(const Vectors& vk,
                                              const Vectors& r,
                                              std::vector<double>& U_free)
{
  const std::span<const int> local = _s._bodies.local_bodies();
  const auto nl = static_cast<int>(local.size());
  std::vector<double>& v_contact = _s._v_contact;
  std::fill(v_contact.begin(), v_contact.end(), 0.0);
  Vectors free(_s._bodies.num_bodies());
#pragma omp parallel for schedule(dynamic) if (nl >= 16)
  for (int i = 0; i < nl; ++i)
  {
    const int b = local[i];
    if (_sc.contact_nodes[b].empty())
      continue;
    const bool rigid = _s._rigid.rigid(b);
    if (!rigid)
      free[b] = vk[b] - _s._kbar.solve(b, r[b]);
    const bodies::Body& body = _s._bodies.body(b);
    const int d = _s.dim();
    for (const std::int32_t node : _sc.contact_nodes[b])
    {
      if (rigid)
      {
        const Eigen::VectorXd v_free = _s._rigid.free_velocity(b, node);
        for (int c = 0; c < d; ++c)
          v_contact[d * body.nodes[node] + c] = v_free[c];
      }
      else
        for (int c = 0; c < d; ++c)
          v_contact[d * body.nodes[node] + c] = free[b][d * node + c];
    }
  }
  _s._exchange.share_contact_nodes(_s._bodies, _sc.contact_nodes, v_contact);
  U_free = _sc.H.relative_velocity(_s._bodies, v_contact);
  return free;
}

void NewtonLoop::solve_problem(const std::vector<double>& U_free)
{
  const int d = _s.dim();
  std::vector<double>& q = _problem.q(d);
  for (std::size_t i = 0; i < U_free.size(); ++i)
    q[i] = U_free[i] + _sc.shift[i];
  std::vector<double> U(U_free.size()), start = _s._R;
  contact::NlgsOptions options = _s._nlgs;
  options.tolerance = _tolerance.current();
  if (d == 3 and _s._condense) // (whole on every process)
  {
    std::optional<contact::FrictionlessCondensation<3>>& c = _s._condensation;
    if (!c)
      c.emplace(_problem.three);
    report_nlgs(c->solve(_problem.three, _s._R, U, options).nlgs,
                std::move(start));
    return;
  }
  if (d == 3) // (whole on every process: ContactExchange::delassus)
  {
    std::optional<contact::SweepPlan3D>& plan = _s._sweep_plan3;
    if (!plan && contact::renumbers(_problem.three, _s._nlgs))
      plan.emplace(_problem.three, _s._nlgs);
    report_nlgs(contact::solve_nlgs(_problem.three, _s._R, U, options, nullptr,
                                    plan ? &*plan : nullptr),
                std::move(start));
    return;
  }
  const contact::SweepDomain* domain = _s._exchange.domain();
  std::optional<contact::SweepPlan>& plan = _s._sweep_plan;
  if (!domain && !plan && contact::renumbers(_problem.two, _s._nlgs))
    plan.emplace(_problem.two, _s._nlgs);
  const contact::NlgsResult nlgs = contact::solve_nlgs(
      _problem.two, _s._R, U, options, domain, plan ? &*plan : nullptr);
  _s._exchange.count_sweeps(nlgs.iterations);
  report_nlgs(nlgs, std::move(start));
}

void NewtonLoop::report_nlgs(const contact::NlgsResult& nlgs,
                             std::vector<double> start)
{
  _report.nlgs_iterations += nlgs.iterations;
  _report.nlgs_error = nlgs.error;
  _report.nlgs_converged = _tolerance.after_solve(nlgs);
  if (!_report.nlgs_converged)
  {
    ++_report.unsolved_contact_solves;
    // Kept for replay; the solver itself writes nothing. A 3D problem is
    // whole on every process (ContactExchange::delassus).
    if (_s.dim() == 3)
      _report.unsolved_problem_3d =
          std::make_shared<const contact::FrictionContactProblem3D>(
              _problem.three);
    else
      _report.unsolved_problem =
          std::make_shared<const contact::FrictionContactProblem2D>(
              _s._exchange.whole_problem(_problem.two));
    _report.unsolved_start = std::move(start);
  }
}

void NewtonLoop::add_impulse_response(const Vectors& free, Vectors& v_new)
{
  const int nb = _s._bodies.num_bodies();
  // Of the bodies that carry a contact, those moved here: the local ones
  // and every rigid one (a vector per body of the whole model would grow
  // with it in every process).
  Vectors impulse(nb);
  for (int b = 0; b < nb; ++b)
    if (!_sc.contact_nodes[b].empty() &&
        (_s._bodies.is_local(b) || _s._rigid.rigid(b)))
      impulse[b] = Eigen::VectorXd::Zero(_s._bodies.body(b).num_dofs());
  _sc.H.add_impulses(_s._R, impulse);
  // Every process moves every rigid body (three numbers each): they stay
  // replicated.
  for (int b = 0; b < nb; ++b)
    if (!_sc.contact_nodes[b].empty() && _s._rigid.rigid(b))
      _s._rigid.add_impulse(b, impulse[b]);
#pragma omp parallel for schedule(dynamic) if (nb >= 16)
  for (int b = 0; b < nb; ++b)
    if (free[b].size() > 0)
      v_new[b] = free[b] + _s._kbar.solve(b, impulse[b]);
}

double NewtonLoop::iteration(int k, std::vector<double>& vk)
{
  const int nb = _s._bodies.num_bodies();
  auto t0 = clock::now();
  _s.set_displacement(_start.u_old, _start.v_old, vk);
  std::vector<double> f_int(vk.size());
  _s._bodies.internal_force(f_int);
  _s._rigid.zero(f_int);
  _report.seconds.assembly += seconds_since(t0);
  if (k > 0 && _s._options.time.full_newton)
    _s.refactorize(_sc, _problem, _report);

  t0 = clock::now();
  const Vectors vk_b = _s.gather(vk);
  Vectors r = residual(vk_b, _s.gather(f_int));
  _report.seconds.solves += seconds_since(t0);
  _s._rigid.reset_to_free();
  Vectors v_new(nb); // filled by the contact solve for contact bodies
  if (_sc.size() > 0)
    solve_contacts(vk_b, r, v_new);
  // v_{k+1} = v_k - Kbar^-1 r on the others, one solve per body
  t0 = clock::now();
  const std::span<const int> local = _s._bodies.local_bodies();
  const auto nl = static_cast<int>(local.size());
#pragma omp parallel for schedule(dynamic) if (nl >= 16)
  for (int i = 0; i < nl; ++i)
  {
    const int b = local[i];
    if (_s._rigid.rigid(b))
      v_new[b] = _s._rigid.velocity_field(b);
    else if (v_new[b].size() == 0)
      v_new[b] = vk_b[b] - _s._kbar.solve(b, r[b]);
  }
  // Only the local bodies' entries: no other body is read within the
  // iterations (the contact nodes' free velocities are shared apart), so
  // the whole velocity is shared once, when the iterations end (run).
  double change = 0;
  for (int b = 0; b < nb; ++b)
    if (v_new[b].size() > 0)
    {
      const double c = (v_new[b] - vk_b[b]).lpNorm<Eigen::Infinity>();
      // A NaN would pass std::max unseen, and the step with it
      change = std::isfinite(c) ? std::max(change, c)
                                : std::numeric_limits<double>::infinity();
    }
  std::fill(vk.begin(), vk.end(), 0.0);
  _s.scatter(v_new, vk);
  _report.seconds.solves += seconds_since(t0);
  return change;
}

void NewtonLoop::run()
{
  const MoreauJeanOptions& o = _s._options;
  std::vector<double> vk = _start.v_old;
  double previous_change = 0;
  for (int k = 0;; ++k)
  {
    // The largest change and velocity over every process's bodies (vk
    // holds the local bodies' entries only)
    double largest[2] = {iteration(k, vk), max_abs(vk)};
    _s.dist().comm().max(largest);
    const double change = largest[0];
    _report.newton_iterations = k + 1;
    if (!std::isfinite(change) || !std::isfinite(largest[1]))
    {
      _report.newton_diverged = true;
      break;
    }
    // The iterations contract at the rate rho = change / previous change;
    // the distance of vk to the converged velocity is then at most
    // change * rho / (1 - rho) (Banach), which is what the tolerance bounds.
    const double rho = k > 0 ? change / previous_change : 1.0;
    const double error = rho < slow_rate ? change * rho / (1 - rho) : change;
    previous_change = change;
    // In a periodic cell the velocities' size depends on which image
    // represents each body (a body and its image differ by dh/dt k): the
    // cell's edge speed alone scales the test there
    const double scale =
        _s._cell ? o.velocity_scale : std::max(largest[1], o.velocity_scale);
    if (error <= o.time.newton_tolerance * scale)
    {
      _report.newton_converged = true;
      break;
    }
    if (k + 1 >= o.time.newton_max_iterations)
      break;
    _tolerance.after_iteration(k, rho);
  }
  // The boundaries (what every process reads between outputs); the
  // interiors stay where they are local (io::OutputGather gathers them).
  _s.dist().scatterer().share_boundaries(vk);
  _s._v = std::move(vk);
}

} // namespace softpack::dynamics
