#include "bond.h"

#include <cmath>
#include <stdexcept>

using namespace softpack::contact;

//-----------------------------------------------------------------------------
ShiftedCone softpack::contact::bond_cone(const BondStrength& s)
{
  if (!(s.tensile > 0 and std::isfinite(s.tensile) and s.shear > 0 and
        std::isfinite(s.shear)))
    throw std::invalid_argument(
        "bond_cone: the tensile and shear strengths must be > 0 and finite");
  return {s.shear / s.tensile, s.tensile};
}
//-----------------------------------------------------------------------------
LocalSolution softpack::contact::solve_bond(const Eigen::Matrix2d& W,
                                            const Eigen::Vector2d& q,
                                            const BondStrength& s)
{
  const ShiftedCone cone = bond_cone(s);
  return solve_local(W, q, cone.coefficient, cone.cohesion);
}
//-----------------------------------------------------------------------------
void softpack::contact::set_bonds(FrictionContactProblem2D& problem,
                                  std::span<const std::int32_t> contacts,
                                  std::span<const BondStrength> strengths)
{
  if (contacts.size() != strengths.size())
    throw std::invalid_argument("set_bonds: one strength per bonded contact");
  if (contacts.empty())
    return;
  const std::size_t n = problem.num_contacts();
  if (problem.cohesion.empty())
    problem.cohesion.assign(n, 0.0);
  for (std::size_t k = 0; k < contacts.size(); ++k)
  {
    const std::int32_t a = contacts[k];
    if (a < 0 or static_cast<std::size_t>(a) >= n)
      throw std::invalid_argument("set_bonds: contact out of range");
    const ShiftedCone cone = bond_cone(strengths[k]);
    problem.friction[a] = cone.coefficient;
    problem.cohesion[a] = cone.cohesion;
  }
}
//-----------------------------------------------------------------------------
BondOutcome softpack::contact::bond_outcome(const Eigen::Vector2d& r,
                                            const BondStrength& s, double eta)
{
  if (!(eta >= 0 and eta < 1))
    throw std::invalid_argument("bond_outcome: eta must be in [0, 1)");
  bond_cone(s); // the strengths' conditions
  const double rn_shifted = r[0] + s.tensile;
  if (rn_shifted <= eta * s.tensile)
    return BondOutcome::tension;
  if (std::abs(r[1]) * s.tensile >= (1 - eta) * s.shear * rn_shifted)
    return BondOutcome::shear;
  return BondOutcome::holds;
}
//-----------------------------------------------------------------------------
