// The parts of a Moreau–Jean step that differ when the bodies are spread
// over MPI ranks (docs/mpi_design.md) besides its contact problem
// (parallel::ContactExchange): the rebalance, the strain energies of an
// output, and the body terms of the energy accounts summed over the ranks.
#include "moreau_jean.h"
#include "moreau_jean_step.h"

#include <parallel/rebalance.h>

namespace softpack::dynamics
{
namespace
{
/// Each contact's candidate body weighs `weight` more; the body pairs of
/// the contacts between bodies (Contact or Contact3D)
template <typename C>
std::vector<std::array<int, 2>> add_contacts(const std::vector<C>& contacts,
                                             double weight,
                                             std::vector<double>& weights)
{
  std::vector<std::array<int, 2>> links;
  for (const C& c : contacts)
  {
    weights[c.candidate_body] += weight;
    if (c.antagonist_body >= 0)
      links.push_back({c.candidate_body, c.antagonist_body});
  }
  return links;
}
} // namespace

void MoreauJean::rebalance()
{
  if (!dist().distributed())
    return;
  // A body's work: its DOFs (assembly, factorization, solves) and its
  // contacts as candidate (Delassus blocks, its rank's NLGS share), one
  // contact costing as much as 35 DOFs: the paper case over Phi 0.80 ->
  // 0.82 on one rank spent 0.82 us per DOF and 29 us per contact and step
  // (docs/mpi_design.md).
  constexpr double contact_weight = 35;
  const int nb = _bodies.num_bodies();
  std::vector<double> weights(nb);
  for (int b = 0; b < nb; ++b)
    weights[b] = _bodies.body(b).num_dofs();
  const std::vector<std::array<int, 2>> links =
      dim() == 2 ? add_contacts(_contacts, contact_weight, weights)
                 : add_contacts(_contacts3, contact_weight, weights);
  std::vector<int> split = parallel::drifted_split(
      dist(), _bodies, _bodies.current_coordinates(), weights, links,
      _options.parallel.rebalance_tolerance);
  if (split.empty())
    return;
  // Every node vector follows the new storage; the arriving bodies'
  // entries come from their old owners (the retry's copies are empty when
  // no retry is possible; the kept tangent is assembled again right after).
  std::vector<double>* const vectors[] = {
      &_v, &_f_ext, &_f_int, &_v_contact, &_u_tangent, &_retry_u, &_retry_v};
  parallel::move_bodies(_exchange.distribution(), std::move(split), _bodies,
                        vectors);
  _surfaces.clear(); // (a 3D run's: their nodes' storage indices changed)
  _kbar.set_local(_bodies);
  _K = _bodies.create_matrices();
  _products_valid = false;
  // The arriving bodies' internal force, at the displacement their former
  // owner computed it at (the step's start): the same bits.
  _bodies.internal_force(_f_int);
  _rigid.zero(_f_int);
}

void MoreauJean::prepare_output()
{
  if (!dist().distributed() || _strain_shared)
    return;
  _body_strain = _bodies.body_strain_energy();
  dist().scatterer().share_by_body(_body_strain, 1);
  _strain_shared = true;
}

void MoreauJean::add_local_body_terms(const BodyStep& step,
                                      double stiffness_numerical)
{
  const double h = _h, th = _options.time.theta;
  const std::span<const int> local = _bodies.local_bodies();
  if (!dist().distributed())
  {
    // Added in place: the serial sums keep their order of operations.
    _energy.numerical += stiffness_numerical;
    add_body_terms(_energy, h, th, step, local);
    _body_kinetic = kinetic_energy(step.v_new, step.Mv_new, local);
    return;
  }
  EnergyBalance mine;
  mine.numerical = stiffness_numerical;
  add_body_terms(mine, h, th, step, local);
  double sums[4] = {mine.damping, mine.numerical, mine.external_work,
                    kinetic_energy(step.v_new, step.Mv_new, local)};
  dist().comm().sum(sums);
  _energy.damping += sums[0];
  _energy.numerical += sums[1];
  _energy.external_work += sums[2];
  _body_kinetic = sums[3];
}

} // namespace softpack::dynamics
