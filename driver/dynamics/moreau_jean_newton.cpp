// The Newton loop of a Moreau–Jean step: the residual, the contact solve
// of each iteration (free velocity at the contact nodes, NLGS) and the one
// solve per body that updates the velocity.
#include "moreau_jean_step.h"

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

MoreauJean::Vectors MoreauJean::residual(const Vectors& vk,
                                         const Vectors& f_int,
                                         const Vectors& f_ext,
                                         const Vectors& known) const
{
  // r = (M + h th C) v_k + h th (F_int(q_k) - F_ext) - b
  const double h = _h, th = _options.time.theta;
  const std::span<const int> local = _bodies.local_bodies();
  const auto nl = static_cast<int>(local.size());
  Vectors r(_bodies.num_bodies());
#pragma omp parallel for schedule(dynamic) if (nl >= 16)
  for (int i = 0; i < nl; ++i)
  {
    const int b = local[i];
    r[b] = combined_product(_A, _kbar.mass(b), _K[b], vk[b]) +
           h * th * (f_int[b] - f_ext[b]) - known[b];
  }
  return r;
}

void MoreauJean::solve_contacts(const StepContacts& sc, const Vectors& vk,
                                const Vectors& residual,
                                contact::FrictionContactProblem2D& problem,
                                StepReport& report, Vectors& v_new)
{
  // The free velocity v_k - Kbar^-1 r of each body that carries a contact
  // (one solve), read at its contact nodes; after the contact solve the
  // impulses' response Kbar^-1 H R is added (a second solve, whose
  // right-hand side vanishes but at the contact nodes). Reading the free
  // velocity off whole compliance columns instead saved no time and made
  // the columns the largest item of a crowded run's memory.
  const int nb = _bodies.num_bodies();
  const std::span<const int> local = _bodies.local_bodies();
  const auto nl = static_cast<int>(local.size());
  auto t0 = clock::now();
  std::fill(_v_contact.begin(), _v_contact.end(), 0.0);
  Vectors free(nb);
#pragma omp parallel for schedule(dynamic) if (nl >= 16)
  for (int i = 0; i < nl; ++i)
  {
    const int b = local[i];
    if (sc.contact_nodes[b].empty())
      continue;
    const bool rigid = _rigid.rigid(b);
    if (!rigid)
      free[b] = vk[b] - _kbar.solve(b, residual[b]);
    const bodies::Body& body = _bodies.body(b);
    for (const std::int32_t node : sc.contact_nodes[b])
    {
      const Eigen::Vector2d v_free =
          rigid ? _rigid.free_velocity(b, node)
                : Eigen::Vector2d(free[b].segment<2>(2 * node));
      for (int c = 0; c < 2; ++c)
        _v_contact[2 * body.nodes[node] + c] = v_free[c];
    }
  }
  _exchange.share_contact_nodes(_bodies, sc.contact_nodes, _v_contact);
  const std::vector<double> U_free =
      sc.H.relative_velocity(_bodies, _v_contact);
  report.seconds.solves += seconds_since(t0);

  t0 = clock::now();
  for (std::size_t i = 0; i < U_free.size(); ++i)
    problem.q[i] = U_free[i] + sc.shift[i];
  std::vector<double> U(U_free.size()), start = _R;
  const contact::SweepDomain* domain = _exchange.domain();
  if (!domain && !_sweep_plan && contact::renumbers(problem, _nlgs))
    _sweep_plan.emplace(problem, _nlgs);
  const contact::NlgsResult nlgs = contact::solve_nlgs(
      problem, _R, U, _nlgs, domain, _sweep_plan ? &*_sweep_plan : nullptr);
  _exchange.count_sweeps(nlgs.iterations);
  report.nlgs_iterations += nlgs.iterations;
  report.nlgs_error = nlgs.error;
  report.nlgs_converged = nlgs.converged;
  if (!nlgs.converged)
  {
    // Kept for replay; the solver itself writes nothing.
    ++report.unsolved_contact_solves;
    report.unsolved_problem =
        std::make_shared<const contact::FrictionContactProblem2D>(
            _exchange.whole_problem(problem));
    report.unsolved_start = std::move(start);
  }
  report.seconds.nlgs += seconds_since(t0);

  // v = v_free + Kbar^-1 H R on the bodies that carry a contact.
  t0 = clock::now();
  // Of the bodies that carry a contact, those moved here: the local ones
  // and every rigid one (a vector per body of the whole model would grow
  // with it in every process).
  Vectors impulse(nb);
  for (int b = 0; b < nb; ++b)
    if (!sc.contact_nodes[b].empty() &&
        (_bodies.is_local(b) || _rigid.rigid(b)))
      impulse[b] = Eigen::VectorXd::Zero(_bodies.body(b).num_dofs());
  sc.H.add_impulses(_R, impulse);
  // Every process moves every rigid body (three numbers each): they stay
  // replicated.
  for (int b = 0; b < nb; ++b)
    if (!sc.contact_nodes[b].empty() && _rigid.rigid(b))
      _rigid.add_impulse(b, impulse[b]);
#pragma omp parallel for schedule(dynamic) if (nb >= 16)
  for (int b = 0; b < nb; ++b)
    if (free[b].size() > 0)
      v_new[b] = free[b] + _kbar.solve(b, impulse[b]);
  report.seconds.solves += seconds_since(t0);
}

void MoreauJean::set_displacement(const std::vector<double>& u_old,
                                  const std::vector<double>& v_old,
                                  const std::vector<double>& v)
{
  const double h = _h, th = _options.time.theta;
  std::span<double> u = _bodies.displacement();
  for (std::size_t i = 0; i < u.size(); ++i)
    u[i] = u_old[i] + h * (th * v[i] + (1 - th) * v_old[i]);
  // Rigid bodies: the exact rigid motion of their iterate.
  _rigid.displace(u, h, th);
}

double MoreauJean::newton_iteration(int k, const StepContacts& sc,
                                    const StepStart& start,
                                    std::vector<double>& vk,
                                    contact::FrictionContactProblem2D& problem,
                                    StepReport& report)
{
  const int nb = _bodies.num_bodies();
  auto t0 = clock::now();
  set_displacement(start.u_old, start.v_old, vk);
  std::vector<double> f_int(vk.size());
  _bodies.internal_force(f_int);
  _rigid.zero(f_int);
  report.seconds.assembly += seconds_since(t0);
  if (k > 0 && _options.time.full_newton)
    refactorize(sc, problem, report);

  t0 = clock::now();
  const Vectors vk_b = gather(vk);
  Vectors r = residual(vk_b, gather(f_int), start.f_ext_b, start.known);
  report.seconds.solves += seconds_since(t0);
  _rigid.reset_to_free();
  Vectors v_new(nb); // filled by the contact solve for contact bodies
  if (sc.size() > 0)
    solve_contacts(sc, vk_b, r, problem, report, v_new);
  // v_{k+1} = v_k - Kbar^-1 r on the others, one solve per body
  t0 = clock::now();
  const std::span<const int> local = _bodies.local_bodies();
  const auto nl = static_cast<int>(local.size());
#pragma omp parallel for schedule(dynamic) if (nl >= 16)
  for (int i = 0; i < nl; ++i)
  {
    const int b = local[i];
    if (_rigid.rigid(b))
      v_new[b] = _rigid.velocity_field(b);
    else if (v_new[b].size() == 0)
      v_new[b] = vk_b[b] - _kbar.solve(b, r[b]);
  }
  // Only the local bodies' entries: no other body is read within the
  // iterations (the contact nodes' free velocities are shared apart), so
  // the whole velocity is shared once, when the iterations end (newton).
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
  scatter(v_new, vk);
  report.seconds.solves += seconds_since(t0);
  return change;
}

void MoreauJean::newton(const StepContacts& sc, const StepStart& start,
                        contact::FrictionContactProblem2D& problem,
                        StepReport& report)
{
  std::vector<double> vk = start.v_old;
  double previous_change = 0;
  for (int k = 0;; ++k)
  {
    // The largest change and velocity over every process's bodies (vk
    // holds the local bodies' entries only)
    double largest[2] = {newton_iteration(k, sc, start, vk, problem, report),
                         max_abs(vk)};
    dist().comm().max(largest);
    const double change = largest[0];
    report.newton_iterations = k + 1;
    if (!std::isfinite(change) || !std::isfinite(largest[1]))
    {
      report.newton_diverged = true;
      break;
    }
    // The iterations contract at the rate rho = change / previous change;
    // the distance of vk to the converged velocity is then at most
    // change * rho / (1 - rho) (Banach), which is what the tolerance bounds.
    const double rho = k > 0 ? change / previous_change : 1.0;
    const double error = rho < 0.5 ? change * rho / (1 - rho) : change;
    previous_change = change;
    if (error <= _options.time.newton_tolerance *
                     std::max(largest[1], _options.velocity_scale))
    {
      report.newton_converged = true;
      break;
    }
    if (k + 1 >= _options.time.newton_max_iterations)
      break;
  }
  // The boundaries (what every process reads between outputs); the
  // interiors stay where they are local (io::OutputGather gathers them).
  dist().scatterer().share_boundaries(vk);
  _v = std::move(vk);
}

} // namespace softpack::dynamics
