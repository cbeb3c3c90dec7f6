// The Moreau–Jean step's contact problem: the contacts detected and their
// predicted gaps, cohesion and bonds, the problem handed to the NLGS, and
// the bonds that broke in it.
#include "moreau_jean_step.h"

#include <algorithm>
#include <walls/servo_cell.h>

namespace softpack::dynamics
{

MoreauJean::StepContacts
MoreauJean::prepare_contacts(const std::vector<double>& v_old)
{
  const double h = _h, th = _options.time.theta;
  const int d = dim();
  const PeriodicCell* cell = _cell ? &*_cell : nullptr;
  if (d == 2)
    _contacts = _exchange.detect(_bodies, _bodies.current_coordinates(), _walls,
                                 _detection, cell);
  StepContacts sc{
      d == 2 ? ContactOperator(_contacts, _walls, cell) : detect_3d(), {}};
  const std::vector<double> U_old = sc.H.relative_velocity(_bodies, v_old);
  // Signorini on the predicted gap g~ = g + h((1-th) U_n- + th U_n+):
  // the solver's normal velocity is g~ / (h th).
  sc.shift.assign(d * sc.size(), 0.0);
  for (std::size_t a = 0; a < sc.size(); ++a)
  {
    const double gap = d == 2 ? _contacts[a].gap : _contacts3[a].gap;
    sc.shift[d * a] = (gap + h * (1 - th) * U_old[d * a]) / (h * th);
  }
  if (_options.friction.cohesive())
    sc.cohesion = cohesion_impulses(_options.friction, _bodies, _contacts, h);
  if (_options.friction.bonded())
    prepare_bonds(sc);
  sc.contact_nodes.resize(_bodies.num_bodies());
  for (std::size_t a = 0; a < sc.size(); ++a)
    for (const NodeTerm& term : sc.H.terms(a))
      sc.contact_nodes[term.body].push_back(term.node);
  for (std::vector<std::int32_t>& nodes : sc.contact_nodes)
  {
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  }
  if (d == 3) // (no cell: check_3d)
  {
    sc.cohesion = wall_cohesion_3d();
    // After the shift: U_n- is at the walls' start velocity.
    sc.servo = start_servo_walls(_walls3, _contacts3, sc.H, h);
    _R = _history.warm_start(_contacts3);
    return sc;
  }
  // After the shift: U_n- is at the walls' start velocity.
  sc.servo = start_servo_walls(_walls, _contacts, sc.H, h);
  if (_cell && !_cell->servo.empty())
    start_servo_cell(*_cell, _contacts, body_centroids(), sc.H, h,
                     _options.time.theta, _time, sc.servo);
  _R = _history.warm_start(_contacts);
  return sc;
}

void MoreauJean::prepare_bonds(StepContacts& sc)
{
  const double h = _h, th = _options.time.theta;
  if (!_bonds.formed())
    _bonds.form(_options.friction, _contacts);
  sc.bonds = _bonds.intact(_contacts);
  // An intact bond holds its gap: u_n = (g~ - g_bond) / (h th)
  for (std::size_t k = 0; k < sc.bonds.contacts.size(); ++k)
    sc.shift[2 * sc.bonds.contacts[k]] -= sc.bonds.gap[k] / (h * th);
  for (const auto& [T, S] : bond_strengths(_options.friction, _bodies,
                                           _contacts, sc.bonds.contacts, h))
    sc.bond_strength.push_back({T, S});
}

void MoreauJean::break_bonds(const StepContacts& sc, StepReport& report)
{
  const std::size_t nb = sc.bonds.contacts.size();
  std::vector<char> broken(nb);
  for (std::size_t k = 0; k < nb; ++k)
  {
    const std::size_t a = sc.bonds.contacts[k];
    // (closed, as a cohesive contact: R_n + T > 0; the plain count above
    // has those with R_n > 0)
    if (_R[2 * a] <= 0 && _R[2 * a] + sc.bond_strength[k].tensile > 0)
      ++report.active_contacts;
    broken[k] =
        contact::bond_outcome({_R[2 * a], _R[2 * a + 1]}, sc.bond_strength[k],
                              _options.contact.nlgs_tolerance) !=
        contact::BondOutcome::holds;
  }
  _bonds.keep_intact(_contacts, sc.bonds, broken);
}

MoreauJean::StepProblem MoreauJean::prepare_problem(const StepContacts& sc,
                                                    StepReport& report)
{
  StepProblem problem;
  const int d = dim();
  if (d == 2)
  {
    contact::FrictionContactProblem2D& p = problem.two;
    p.friction.resize(sc.size());
    for (std::size_t a = 0; a < sc.size(); ++a)
      p.friction[a] =
          _options.friction(_contacts[a], _options.contact.friction);
    p.cohesion = sc.cohesion;
    contact::set_bonds(p, sc.bonds.contacts, sc.bond_strength);
  }
  else
  {
    problem.three.friction.resize(sc.size());
    for (std::size_t a = 0; a < sc.size(); ++a)
      problem.three.friction[a] =
          _options.friction(_contacts3[a], _options.contact.friction);
    problem.three.cohesion = sc.cohesion;
  }
  problem.q(d).resize(d * sc.size());
  if (needs_refactorization())
  {
    rebalance(); // every body is refactorized now: a free time to move
    refactorize(sc, problem, report);
  }
  else if (sc.size() > 0)
    set_delassus(sc, problem, report);
  return problem;
}

} // namespace softpack::dynamics
