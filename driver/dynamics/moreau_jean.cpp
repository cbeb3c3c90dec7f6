// The Moreau–Jean step: the refactor decision, the known part, the attempts
// of a step, and the end-of-step update and accounts (the step's contact
// problem is moreau_jean_contacts.cpp, the Newton loop newton_loop.h).
#include "moreau_jean_step.h"
#include "newton_loop.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <compliance/delassus.h>
#include <numeric>
#include <omp.h>
#include <stdexcept>
#include <walls/servo_cell.h>

namespace softpack::dynamics
{
MoreauJean::MoreauJean(bodies::BodySet& bodies, std::vector<Wall> walls,
                       MoreauJeanOptions options,
                       parallel::Distribution distribution)
    : _bodies(bodies), _exchange(std::move(distribution)),
      _walls(std::move(walls)), _options(checked(options)),
      _detection(detection_options(options.contact)),
      _nlgs(nlgs_options(options.contact)), _damping{options.damping.alpha,
                                                     options.damping.beta},
      _kbar(bodies, options.time.mass == "lumped"), _rigid(bodies, _kbar),
      _K(bodies.create_matrices()), _v(bodies.num_dofs(), 0.0),
      _f_ext(bodies.num_dofs(), 0.0), _f_int(bodies.num_dofs(), 0.0),
      _v_contact(bodies.num_dofs(), 0.0),
      _step_size(options.time.time_step,
                 options.time.time_step * options.time.max_step_factor,
                 options.time.refactor_above_iterations),
      _h(options.time.time_step)
{
  // The local bodies' internal force only: no other is read.
  _bodies.internal_force(_f_int);
  _rigid.zero(_f_int);
  // Each body's where it is local (its interior is stored there only)
  _body_strain = _bodies.body_strain_energy();
  dist().scatterer().share_by_body(_body_strain, 1);
  // (serial: energy() computes it when asked, from the bodies as they are)
  _strain_shared = dist().distributed();
  _energy.strain0 =
      std::accumulate(_body_strain.begin(), _body_strain.end(), 0.0);
  link_walls(_walls);
  _condense = contact::condenses(options.contact.nlgs_condensation, dim());
  if (dim() == 3)
    check_3d();
}

void MoreauJean::set_initial_velocity(std::vector<double> v)
{
  if (_started)
    throw std::logic_error("set_initial_velocity: after the first step");
  if (v.size() != _bodies.num_global_dofs())
    throw std::invalid_argument("initial velocity: wrong size");
  _v = _bodies.from_global(v);
  _body_kinetic = body_kinetic_energy();
  _energy_stale = true;
  _strain_shared = false;
}

double MoreauJean::body_kinetic_energy() const
{
  const Vectors v = gather(_v);
  double e = kinetic_energy(v, mass_products(v), _bodies.local_bodies());
  dist().comm().sum(std::span<double>(&e, 1));
  return e;
}

void MoreauJean::set_external_force(std::vector<double> f)
{
  if (f.size() != _bodies.num_global_dofs())
    throw std::invalid_argument("external force: wrong size");
  _f_ext = _bodies.from_global(f);
}

MoreauJean::Vectors MoreauJean::gather(std::span<const double> global) const
{
  Vectors out(_bodies.num_bodies());
  for (const int b : _bodies.local_bodies())
  {
    const bodies::Body& body = _bodies.body(b);
    out[b].resize(body.num_dofs());
    const int d = dim();
    for (std::size_t k = 0; k < body.nodes.size(); ++k)
      for (int c = 0; c < d; ++c)
        out[b][d * k + c] = global[d * body.nodes[k] + c];
  }
  return out;
}

void MoreauJean::scatter(const Vectors& per_body,
                         std::span<double> global) const
{
  for (int b = 0; b < _bodies.num_bodies(); ++b)
  {
    const bodies::Body& body = _bodies.body(b);
    if (per_body[b].size() == 0) // not a local body
      continue;
    const int d = dim();
    for (std::size_t k = 0; k < body.nodes.size(); ++k)
      for (int c = 0; c < d; ++c)
        global[d * body.nodes[k] + c] = per_body[b][d * k + c];
  }
}

bool MoreauJean::needs_refactorization() const
{
  return _matrix_age < 0 || _options.time.full_newton ||
         _matrix_age >= _options.time.tangent_reuse_steps ||
         _last_iterations > _options.time.refactor_above_iterations;
}

void MoreauJean::factorize_tangent(StepReport* report)
{
  const double h = _h, th = _options.time.theta;
  auto t0 = clock::now();
  _bodies.tangent(_K);
  const std::span<const double> u = _bodies.displacement();
  _u_tangent.assign(u.begin(), u.end());
  const std::span<const double> internal = _bodies.internal_variables();
  _internal_tangent.assign(internal.begin(), internal.end());
  // Only the local bodies' entries are current here (within a full Newton
  // method's iterations, or between outputs); the state file, which alone
  // reads the others', gathers it (io::OutputGather).
  if (report)
    report->seconds.assembly += seconds_since(t0);
  t0 = clock::now();
  // Kbar = M + h th C + h^2 th^2 K; A = M + h th C multiplies v_k in the
  // residual (with the same K and h until the next factorization).
  _A = _damping.mass_plus(h * th);
  _kbar.factorize(_K, _A.mass, _A.stiffness + h * h * th * th);
  _products_valid = false;
  if (report)
    report->seconds.factorization += seconds_since(t0);
}

void MoreauJean::set_delassus(const StepContacts& sc, StepProblem& problem,
                              StepReport& report)
{
  const auto t0 = clock::now();
  if (dim() == 3)
  {
    problem.three.W = _exchange.delassus(
        sc.size(),
        delassus_blocks<3>(_bodies, sc.H, _kbar,
                           _options.contact.delassus_drop_tolerance, &_rigid),
        std::span<const WallCouplingD<3>>(sc.servo.couplings_3d));
    _sweep_plan3.reset();
    _condensation.reset();
    report.seconds.delassus += seconds_since(t0);
    return;
  }
  problem.two.W = _exchange.delassus(
      _contacts,
      delassus_blocks(_bodies, sc.H, _kbar,
                      _options.contact.delassus_drop_tolerance, &_rigid),
      sc.servo.couplings);
  _sweep_plan.reset();
  report.seconds.delassus += seconds_since(t0);
}

void MoreauJean::refactorize(const StepContacts& sc, StepProblem& problem,
                             StepReport& report)
{
  factorize_tangent(&report);
  _matrix_age = 0;
  report.refactorized = true;
  if (sc.size() > 0)
    set_delassus(sc, problem, report);
}

MoreauJean::StepStart MoreauJean::start_step(std::vector<double> u_old,
                                             std::vector<double> v_old)
{
  const double h = _h, th = _options.time.theta;
  const int nb = _bodies.num_bodies();
  StepStart s{std::move(u_old), std::move(v_old)};
  s.v_old_b = gather(s.v_old);
  s.f_ext_b = gather(_f_ext);
  const Vectors f_int_old = gather(_f_int);
  update_products(s.v_old_b);
  s.Mv_old = _Mv;
  s.Cv_old.resize(nb);
  s.known.resize(nb);
  s.affine_drag = affine_drag();
  for (const int b : _bodies.local_bodies())
  {
    // No damping acts on a rigid body.
    s.Cv_old[b] = _rigid.rigid(b)
                      ? Eigen::VectorXd(Eigen::VectorXd::Zero(_Mv[b].size()))
                      : _damping.force(_Mv[b], _Kv[b]);
    if (!s.affine_drag.empty())
      s.Cv_old[b] -= s.affine_drag[b];
    s.known[b] =
        _Mv[b] + h * (1 - th) * (s.f_ext_b[b] - f_int_old[b] - s.Cv_old[b]);
    // The pull is the same at both ends of the step: its theta part
    // joins the known one (the residual's (M + h th C) v has the rest)
    if (!s.affine_drag.empty())
      s.known[b] += h * th * s.affine_drag[b];
  }
  return s;
}

StepReport MoreauJean::step()
{
  if (!_started)
  {
    // Initial velocities are set between construction and the first step
    // (set_initial_velocity), a wall's velocity too.
    _energy.kinetic0 = _body_kinetic + walls_kinetic_energy(_walls) +
                       walls_kinetic_energy(_walls3) +
                       (_cell ? cell_kinetic_energy(*_cell) : 0.0);
    _started = true;
  }
  // The step's start, for a retry: kept only when one is possible (two
  // node vectors, at fixed steps never read).
  if (_step_size.can_retry())
  {
    const std::span<const double> u = _bodies.displacement();
    _retry_u.assign(u.begin(), u.end());
    _retry_v = _v;
  }
  StepTimings abandoned;
  for (int retries = 0;; ++retries)
  {
    _h = _step_size.current();
    Attempt a = attempt();
    StepReport& report = a.report;
    const bool solved =
        report.newton_converged && report.unsolved_contact_solves == 0;
    if (solved || !_step_size.retry())
    {
      if (report.newton_diverged) // nothing to take: the state is not finite
        throw std::runtime_error(
            "step " + std::to_string(_steps + 1) +
            " (t = " + std::to_string(_time + _h) +
            " s): a Newton iterate of the " + "velocity is not finite after " +
            std::to_string(report.newton_iterations) +
            " iterations (an element inverted, or the time step too large "
            "for the loading); the step is not taken");
      finish_step(a.sc, a.start, report);
      std::vector<double>().swap(_retry_u); // freed: whole vectors
      std::vector<double>().swap(_retry_v);
      report.time_step = _h;
      report.retries = retries;
      report.seconds += abandoned;
      // A new step size changes the iteration matrix: the next step
      // refactors.
      if (_step_size.update(report, window_energy(report)))
        _matrix_age = -1;
      return report;
    }
    // Not solved at h: the step starts again at h / 2 (the iteration
    // matrix with it). Nothing of the attempt was kept but its time.
    abandoned += report.seconds;
    return_to_step_start();
  }
}

std::optional<StepSize::WindowEnergy>
MoreauJean::window_energy(const StepReport& report)
{
  if (!_step_size.needs_energy(report))
    return std::nullopt;
  // A collective where distributed: every rank's StepSize sees the same
  // reports, so all of them ask at the same step.
  prepare_output();
  const EnergyBalance& e = energy();
  return StepSize::WindowEnergy{e.residual(), e.wall_work + e.external_work +
                                                  e.cell_work + e.rewrap};
}

void MoreauJean::return_to_step_start()
{
  // (retry() succeeds only above the base step, where can_retry() held at
  // the step's start too: h only falls within a step.)
  // (a rebalance in the attempt changed the storage: u is fetched anew)
  const std::span<double> u = _bodies.displacement();
  if (_retry_u.size() != u.size())
    throw std::logic_error("MoreauJean::step: a retry without the step's "
                           "start (StepSize::retry against can_retry)");
  std::copy(_retry_u.begin(), _retry_u.end(), u.begin());
  _v = _retry_v;
  _matrix_age = -1;
}

MoreauJean::Attempt MoreauJean::attempt()
{
  StepReport report;
  auto t0 = clock::now();
  // Rigid bodies: V- from the node velocities, which become exactly rigid.
  _rigid.start_step(_bodies.displacement(), _v, _f_ext, _h);
  StepContacts sc = prepare_contacts(_v);
  report.contacts = static_cast<int>(sc.size());
  report.seconds.detection = seconds_since(t0);
  StepProblem problem = prepare_problem(sc, report);

  t0 = clock::now();
  // The step's start after prepare_problem: a rebalance there gives the
  // arriving bodies' interiors and a new storage (u and v are not changed
  // otherwise).
  const std::span<const double> u = _bodies.displacement();
  StepStart start = start_step(std::vector<double>(u.begin(), u.end()), _v);
  report.seconds.solves += seconds_since(t0);
  NewtonLoop(*this, sc, start, problem, report).run();
  return {std::move(report), std::move(sc), std::move(start)};
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

void MoreauJean::finish_step(StepContacts& sc, const StepStart& start,
                             StepReport& report)
{
  const double h = _h;
  auto t0 = clock::now();
  set_displacement(start.u_old, start.v_old, _v);
  const std::vector<double> f_int_before = _f_int;
  _bodies.internal_force(_f_int);
  _rigid.zero(_f_int);
  report.seconds.assembly += seconds_since(t0);
  // Over the local bodies (the others' internal forces are zero here):
  // summed over the processes with the body terms.
  EnergyBalance stiffness;
  add_stiffness_dissipation(stiffness, _options.time.theta, start.u_old,
                            _bodies.displacement(), f_int_before, _f_int,
                            _bodies.local_nodes(), dim());
  if (_bodies.internal_stride() > 0)
  {
    // The internal variables relax at the converged configuration, once
    // per accepted step; the next step starts from their internal force
    // (the relaxed bodies' entries of _f_int, in the same pass).
    t0 = clock::now();
    double viscous = _bodies.update_internal_variables(h, _f_int);
    dist().comm().sum(std::span<double>(&viscous, 1)); // the local bodies'
    _energy.viscous += viscous;
    _rigid.zero(_f_int);
    report.seconds.assembly += seconds_since(t0);
  }
  _time += h;
  ++_steps;
  ++_matrix_age;
  _last_iterations = report.newton_iterations;
  for (Wall& wall : _walls)
    if (!wall.servo())
      for (int d = 0; d < 2; ++d)
        wall.point[d] += h * wall.velocity[d];
  for (Wall3D& wall : _walls3)
    if (!wall.servo())
      for (int d = 0; d < 3; ++d)
        wall.point[d] += h * wall.velocity[d];
  if (dim() == 3)
    finish_servo_walls(sc.servo, _walls3, _R, h, _options.time.theta);
  else
    finish_servo_walls(sc.servo, _walls, _R, h, _options.time.theta);
  finish_servo_cell(sc.servo, _R, _options.time.theta);
  t0 = clock::now();
  account_step(sc, start, report, stiffness.numerical);
  if (_cell)
    finish_cell_step(h, sc.servo);
  if (!_rigid.empty())
  {
    // The next step's contacts see the rigid bodies' velocity field at
    // their new positions (the accounts used the step's start ones).
    _rigid.set_velocities(_bodies.displacement(), _v);
    _products_valid = false;
  }
  report.seconds.solves += seconds_since(t0);
}

void MoreauJean::account_step(StepContacts& sc, const StepStart& start,
                              StepReport& report, double stiffness_numerical)
{
  const double h = _h, th = _options.time.theta;
  const Vectors v_new_b = gather(_v);
  _products_valid = false;
  update_products(v_new_b);
  // The contact terms read every contact's velocity: v_th is made from the
  // whole vectors, then split for the local bodies' terms.
  std::vector<double> v_mid(_v.size());
  for (std::size_t i = 0; i < v_mid.size(); ++i)
    v_mid[i] = th * _v[i] + (1 - th) * start.v_old[i];
  const Vectors v_mid_b = gather(v_mid);
  const std::size_t nb = v_new_b.size();
  Vectors Cv_new(nb);
  for (const int b : _bodies.local_bodies())
    Cv_new[b] = _rigid.rigid(b)
                    ? Eigen::VectorXd(Eigen::VectorXd::Zero(_Mv[b].size()))
                    : _damping.force(_Mv[b], _Kv[b]);
  if (!start.affine_drag.empty())
    for (const int b : _bodies.local_bodies())
      Cv_new[b] -= start.affine_drag[b];
  add_local_body_terms({.v_old = start.v_old_b,
                        .v_new = v_new_b,
                        .v_mid = v_mid_b,
                        .Mv_old = start.Mv_old,
                        .Mv_new = _Mv,
                        .Cv_old = start.Cv_old,
                        .Cv_new = Cv_new,
                        .f_ext = start.f_ext_b},
                       stiffness_numerical);
  if (dim() == 3)
    account_servo_walls(sc.servo, _walls3, sc.H, _energy, h, th);
  else
    account_servo_walls(sc.servo, _walls, sc.H, _energy, h, th);
  if (_cell)
    account_servo_cell(sc.servo, *_cell, _contacts, sc.H, _R, _energy, h, th);
  const std::vector<double> U_mid = sc.H.relative_velocity(_bodies, v_mid);
  const int d = dim();
  if (d == 2)
    add_contact_terms(_energy, sc.H, _contacts, _walls, _R, U_mid, sc.cohesion,
                      sc.bonds.contacts);
  else
    add_contact_terms(_energy, sc.H, _contacts3, _walls3, _R, U_mid);
  for (std::size_t a = 0; a < sc.size(); ++a)
  {
    const double gap =
        (d == 2 ? _contacts[a].gap : _contacts3[a].gap) + h * U_mid[d * a];
    report.max_penetration = std::max(report.max_penetration, -gap);
    // (closed: the reaction in its cone's variable, r + c, is positive)
    const double c = sc.cohesion.empty() ? 0.0 : sc.cohesion[a];
    if (_R[d * a] + c > 0)
      ++report.active_contacts;
  }
  if (d == 2)
    _history.record(_contacts, _R);
  else
    _history.record(_contacts3, _R);
  if (_options.friction.bonded())
    break_bonds(sc, report);
  _energy_stale = true;
  _strain_shared = false;
}

void MoreauJean::update_products(const Vectors& v)
{
  if (_products_valid)
    return;
  const std::span<const int> local = _bodies.local_bodies();
  const auto nl = static_cast<int>(local.size());
  _Mv = mass_products(v);
  _Kv.resize(_bodies.num_bodies());
#pragma omp parallel for schedule(static) if (nl >= 16)
  for (int i = 0; i < nl; ++i)
    _Kv[local[i]] = bodies::symmetric_product(_K[local[i]], v[local[i]]);
  _products_valid = true;
}

MoreauJean::Vectors MoreauJean::mass_products(const Vectors& v) const
{
  const std::span<const int> local = _bodies.local_bodies();
  const auto nl = static_cast<int>(local.size());
  Vectors Mv(_bodies.num_bodies());
#pragma omp parallel for schedule(static) if (nl >= 16)
  for (int i = 0; i < nl; ++i)
    Mv[local[i]] = bodies::symmetric_product(_kbar.mass(local[i]), v[local[i]]);
  return Mv;
}

} // namespace softpack::dynamics
