#include "moreau_jean.h"

#include "delassus.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace softpack::dynamics
{
namespace
{
std::tuple<int, int, int> contact_key(const Contact& c)
{
  return {c.candidate_body, c.candidate_node,
          c.antagonist_body >= 0 ? c.antagonist_body : -1 - c.wall};
}

double max_abs(const std::vector<double>& v)
{
  double m = 0;
  for (double x : v)
    m = std::max(m, std::abs(x));
  return m;
}
} // namespace

MoreauJean::MoreauJean(bodies::BodySet& bodies, std::vector<Wall> walls,
                       MoreauJeanOptions options)
    : _bodies(bodies), _walls(std::move(walls)), _options(options),
      _kbar(bodies, options.lumped_mass), _K(bodies.create_matrices()),
      _v(bodies.num_dofs(), 0.0), _f_ext(bodies.num_dofs(), 0.0),
      _f_int(bodies.num_dofs(), 0.0)
{
  if (!(options.time_step > 0))
    throw std::invalid_argument("time step must be positive");
  if (options.theta < 0.5 || options.theta > 1)
    throw std::invalid_argument("theta must be in [0.5, 1]");
  _bodies.internal_force(_f_int);
  _energy.strain = _energy.strain0 = _bodies.strain_energy();
}

void MoreauJean::set_external_force(std::vector<double> f)
{
  if (f.size() != _bodies.num_dofs())
    throw std::invalid_argument("external force: wrong size");
  _f_ext = std::move(f);
}

MoreauJean::Vectors MoreauJean::gather(std::span<const double> global) const
{
  Vectors out(_bodies.num_bodies());
  for (int b = 0; b < _bodies.num_bodies(); ++b)
  {
    const bodies::Body& body = _bodies.body(b);
    out[b].resize(body.num_dofs());
    for (std::size_t k = 0; k < body.nodes.size(); ++k)
      for (int c = 0; c < 2; ++c)
        out[b][2 * k + c] = global[2 * body.nodes[k] + c];
  }
  return out;
}

void MoreauJean::scatter(const Vectors& per_body,
                         std::span<double> global) const
{
  for (int b = 0; b < _bodies.num_bodies(); ++b)
  {
    const bodies::Body& body = _bodies.body(b);
    for (std::size_t k = 0; k < body.nodes.size(); ++k)
      for (int c = 0; c < 2; ++c)
        global[2 * body.nodes[k] + c] = per_body[b][2 * k + c];
  }
}

MoreauJean::Vectors MoreauJean::solve(const Vectors& rhs) const
{
  Vectors x(rhs.size());
  for (std::size_t b = 0; b < rhs.size(); ++b)
    x[b] = _kbar.solve(static_cast<int>(b), rhs[b]);
  return x;
}

std::vector<double> MoreauJean::warm_start() const
{
  std::vector<double> R(2 * _contacts.size(), 0.0);
  for (std::size_t a = 0; a < _contacts.size(); ++a)
    if (auto it = _previous.find(contact_key(_contacts[a]));
        it != _previous.end())
    {
      R[2 * a] = it->second[0];
      R[2 * a + 1] = it->second[1];
    }
  return R;
}

double MoreauJean::kinetic_energy(std::span<const double> v) const
{
  const Vectors vb = gather(v);
  double e = 0;
  for (int b = 0; b < _bodies.num_bodies(); ++b)
    e += 0.5 * vb[b].dot(_kbar.mass(b) * vb[b]);
  return e;
}

StepReport MoreauJean::step()
{
  if (!_started)
  {
    // Initial velocities are set between construction and the first step.
    _energy.kinetic = _energy.kinetic0 = kinetic_energy(_v);
    _started = true;
  }
  const double h = _options.time_step, th = _options.theta;
  const double alpha = _options.alpha, beta = _options.beta;
  const int nb = _bodies.num_bodies();
  std::span<double> u = _bodies.displacement();
  const std::vector<double> u_old(u.begin(), u.end()), v_old = _v;

  // Detection and contact frames at the start of the step.
  std::vector<double> x(_bodies.reference_coordinates().begin(),
                        _bodies.reference_coordinates().end());
  for (std::size_t i = 0; i < x.size(); ++i)
    x[i] += u_old[i];
  _contacts = detect_contacts(_bodies, x, _walls, _options.detection);
  const ContactOperator H(_contacts, _walls);
  const std::size_t nc = _contacts.size();
  const std::vector<double> U_old = H.relative_velocity(_bodies, v_old);
  // Signorini on the predicted gap g~ = g + h((1-th) U_n- + th U_n+):
  // the solver's normal velocity is g~ / (h th).
  std::vector<double> shift(2 * nc, 0.0);
  for (std::size_t a = 0; a < nc; ++a)
    shift[2 * a] = (_contacts[a].gap + h * (1 - th) * U_old[2 * a]) / (h * th);
  _R = warm_start();

  contact::FrictionContactProblem2D problem;
  problem.mu.assign(nc, _options.friction);
  problem.q.resize(2 * nc);
  std::vector<double> U(2 * nc);

  const Vectors v_old_b = gather(v_old), f_ext_b = gather(_f_ext);
  Vectors damping_old(nb), f_old(nb), f_int_b;
  auto damping_force = [&](int b, const Eigen::VectorXd& v)
  { return Eigen::VectorXd(alpha * (_kbar.mass(b) * v) + beta * (_K[b] * v)); };

  contact::NlgsOptions nlgs_options = _options.nlgs;
  if (!_options.failed_problem_directory.empty())
  {
    char name[32];
    std::snprintf(name, sizeof(name), "step_%08ld.hdf5", _steps);
    std::filesystem::create_directories(_options.failed_problem_directory);
    nlgs_options.dump_on_failure = _options.failed_problem_directory / name;
  }

  StepReport report;
  report.contacts = static_cast<int>(nc);
  std::vector<double> vk = v_old, f_int(u.size());
  for (int k = 0;; ++k)
  {
    for (std::size_t i = 0; i < u.size(); ++i)
      u[i] = u_old[i] + h * (th * vk[i] + (1 - th) * v_old[i]);
    _bodies.internal_force(f_int);
    if (k == 0 || _options.full_newton)
    {
      _bodies.tangent(_K);
      _kbar.factorize(_K, 1 + h * th * alpha, h * th * beta + h * h * th * th);
      if (nc > 0)
        problem.W = build_delassus(_bodies, H, _kbar);
    }
    if (k == 0)
    {
      const Vectors f_int_old = gather(_f_int);
      for (int b = 0; b < nb; ++b)
      {
        damping_old[b] = damping_force(b, v_old_b[b]);
        f_old[b] = f_ext_b[b] - f_int_old[b] - damping_old[b];
      }
    }

    // Free velocity: one (quasi-)Newton correction without contact.
    const Vectors vk_b = gather(vk);
    f_int_b = gather(f_int);
    Vectors residual(nb);
    for (int b = 0; b < nb; ++b)
      residual[b] =
          _kbar.mass(b) * (vk_b[b] - v_old_b[b]) +
          h * th * (f_int_b[b] + damping_force(b, vk_b[b]) - f_ext_b[b]) -
          h * (1 - th) * f_old[b];
    const Vectors correction = solve(residual);
    Vectors v_new(nb);
    for (int b = 0; b < nb; ++b)
      v_new[b] = vk_b[b] - correction[b];

    if (nc > 0)
    {
      std::vector<double> v_free(u.size());
      scatter(v_new, v_free);
      const std::vector<double> U_free = H.relative_velocity(_bodies, v_free);
      for (std::size_t i = 0; i < 2 * nc; ++i)
        problem.q[i] = U_free[i] + shift[i];
      const contact::NlgsResult nlgs =
          contact::solve_nlgs(problem, _R, U, nlgs_options);
      report.nlgs_iterations += nlgs.iterations;
      report.nlgs_error = nlgs.error;
      report.nlgs_converged = nlgs.converged;
      Vectors impulse(nb);
      for (int b = 0; b < nb; ++b)
        impulse[b] = Eigen::VectorXd::Zero(_bodies.body(b).num_dofs());
      H.add_impulses(_R, impulse);
      const Vectors dv = solve(impulse);
      for (int b = 0; b < nb; ++b)
        v_new[b] += dv[b];
    }

    std::vector<double> v_next(u.size());
    scatter(v_new, v_next);
    double change = 0;
    for (std::size_t i = 0; i < vk.size(); ++i)
      change = std::max(change, std::abs(v_next[i] - vk[i]));
    vk = std::move(v_next);
    report.newton_iterations = k + 1;
    if (change <= _options.newton_tolerance *
                      std::max(max_abs(vk), _options.velocity_scale))
    {
      report.newton_converged = true;
      break;
    }
    if (k + 1 >= _options.max_newton_iterations)
      break;
  }

  _v = vk;
  for (std::size_t i = 0; i < u.size(); ++i)
    u[i] = u_old[i] + h * (th * _v[i] + (1 - th) * v_old[i]);
  _bodies.internal_force(_f_int);
  _time += h;
  ++_steps;
  for (Wall& wall : _walls)
    for (int d = 0; d < 2; ++d)
      wall.point[d] += h * wall.velocity[d];

  // Energy bookkeeping with the scheme's own quantities.
  std::vector<double> v_mid(u.size());
  for (std::size_t i = 0; i < u.size(); ++i)
    v_mid[i] = th * _v[i] + (1 - th) * v_old[i];
  const Vectors v_new_b = gather(_v), v_mid_b = gather(v_mid);
  for (int b = 0; b < nb; ++b)
  {
    const Eigen::VectorXd dv = v_new_b[b] - v_old_b[b];
    _energy.damping += h * v_mid_b[b].dot(th * damping_force(b, v_new_b[b]) +
                                          (1 - th) * damping_old[b]);
    _energy.numerical += (th - 0.5) * dv.dot(_kbar.mass(b) * dv);
    _energy.external_work += h * v_mid_b[b].dot(f_ext_b[b]);
  }
  const std::vector<double> U_mid = H.relative_velocity(_bodies, v_mid);
  _previous.clear();
  for (std::size_t a = 0; a < nc; ++a)
  {
    _energy.friction -= _R[2 * a + 1] * U_mid[2 * a + 1];
    _energy.contact_normal -= _R[2 * a] * U_mid[2 * a];
    if (_contacts[a].wall >= 0)
      _energy.wall_work += _R[2 * a] * H.wall_velocity(a)[0] +
                           _R[2 * a + 1] * H.wall_velocity(a)[1];
    const double gap = _contacts[a].gap + h * U_mid[2 * a];
    report.max_penetration = std::max(report.max_penetration, -gap);
    if (_R[2 * a] > 0)
      ++report.active_contacts;
    _previous[contact_key(_contacts[a])] = {_R[2 * a], _R[2 * a + 1]};
  }
  _energy.kinetic = kinetic_energy(_v);
  _energy.strain = _bodies.strain_energy();
  return report;
}

std::vector<std::array<double, 2>> MoreauJean::wall_forces() const
{
  std::vector<std::array<double, 2>> force(_walls.size(), {0, 0});
  const double h = _options.time_step;
  for (std::size_t a = 0; a < _contacts.size(); ++a)
  {
    const Contact& c = _contacts[a];
    if (c.wall < 0)
      continue;
    // The wall receives the opposite of the candidate's impulse.
    force[c.wall][0] -= (_R[2 * a] * c.n[0] + _R[2 * a + 1] * c.t[0]) / h;
    force[c.wall][1] -= (_R[2 * a] * c.n[1] + _R[2 * a + 1] * c.t[1]) / h;
  }
  return force;
}

} // namespace softpack::dynamics
