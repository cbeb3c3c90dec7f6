#include "friction_table.h"
#include "detection_3d.h"
#include <map>
#include <tuple>

#include "detection.h"

#include <bodies/BodySet.h>
#include <cmath>

#include <stdexcept>

namespace softpack::dynamics
{

namespace
{
/// A pair's coefficient not set
constexpr double unset = -1;
} // namespace

FrictionTable::FrictionTable(std::vector<int> body_species, int num_species,
                             int num_walls)
    : _body_species(std::move(body_species)), _num_species(num_species),
      _num_parties(num_species + num_walls),
      _coefficient(_num_parties * _num_parties, unset)
{
  for (int s : _body_species)
    if (s < 0 || s >= num_species)
      throw std::invalid_argument("FrictionTable: species " +
                                  std::to_string(s) + " out of range");
}

void FrictionTable::set(int a, int b, double coefficient, Cohesion cohesion,
                        Bond bond)
{
  if (a < 0 || b < 0 || a >= _num_parties || b >= _num_parties)
    throw std::invalid_argument("FrictionTable: party out of range");
  if (!(coefficient >= 0))
    throw std::invalid_argument("FrictionTable: negative coefficient");
  if (!(cohesion.traction >= 0 && cohesion.distance >= 0))
    throw std::invalid_argument("FrictionTable: negative cohesion");
  if (!(bond.tensile >= 0 && bond.shear >= 0 && bond.distance >= 0) ||
      (bond.tensile > 0) != (bond.shear > 0))
    throw std::invalid_argument(
        "FrictionTable: a bond needs both strengths > 0");
  if (bond.tensile > 0 && cohesion.traction > 0)
    throw std::invalid_argument("FrictionTable: a bond and a cohesion");
  _coefficient[a * _num_parties + b] = coefficient;
  _coefficient[b * _num_parties + a] = coefficient;
  if (bond.tensile > 0 || !_bond.empty())
  {
    _bond.resize(_coefficient.size());
    _bond[a * _num_parties + b] = bond;
    _bond[b * _num_parties + a] = bond;
  }
  if (cohesion.traction == 0 && _cohesion.empty())
    return; // a table without cohesion stores none
  _cohesion.resize(_coefficient.size());
  _cohesion[a * _num_parties + b] = cohesion;
  _cohesion[b * _num_parties + a] = cohesion;
}

int FrictionTable::pair(int candidate_body, int antagonist_body, int wall) const
{
  const int a = _body_species[candidate_body];
  const int b = wall >= 0 ? wall_party(wall) : _body_species[antagonist_body];
  return a * _num_parties + b;
}

int FrictionTable::pair(const Contact& c) const
{
  return pair(c.candidate_body, c.antagonist_body, c.wall);
}

double FrictionTable::coefficient(int pair, double default_coefficient) const
{
  const double set = _coefficient[pair];
  return set == unset ? default_coefficient : set;
}

double FrictionTable::operator()(const Contact& c,
                                 double default_coefficient) const
{
  if (_body_species.empty())
    return default_coefficient;
  return coefficient(pair(c), default_coefficient);
}

double FrictionTable::operator()(const Contact3D& c,
                                 double default_coefficient) const
{
  if (_body_species.empty())
    return default_coefficient;
  return coefficient(pair(c.candidate_body, c.antagonist_body, c.wall),
                     default_coefficient);
}

Cohesion FrictionTable::cohesion(const Contact& c) const
{
  if (_cohesion.empty())
    return {};
  return _cohesion[pair(c)];
}

Bond FrictionTable::bond(const Contact& c) const
{
  if (_bond.empty())
    return {};
  return _bond[pair(c)];
}

namespace
{
/// Half the reference lengths of the two boundary segments at a body's
/// boundary node (m)
double boundary_share(const bodies::BodySet& bodies, int b, int node)
{
  const bodies::Body& body = bodies.body(b);
  const std::span<const double> X = bodies.reference_coordinates();
  double share = 0;
  for (const std::int32_t s : {body.segment_from[node], body.segment_to[node]})
  {
    if (s < 0)
      continue;
    const auto& [p, q] = body.boundary_segments[s];
    const std::int32_t gp = body.nodes[p], gq = body.nodes[q];
    share +=
        0.5 * std::hypot(X[2 * gq] - X[2 * gp], X[2 * gq + 1] - X[2 * gp + 1]);
  }
  return share;
}
} // namespace

double contact_share(const bodies::BodySet& bodies, const Contact& c)
{
  const double sides = c.wall >= 0 ? 1.0 : 0.5;
  return sides * boundary_share(bodies, c.candidate_body, c.candidate_node);
}

namespace
{
/// Where a node's contact is: its body, node and antagonist (body, wall,
/// image)
using ContactPlace = std::tuple<int, int, int, int, int, int>;

ContactPlace place_of(const Contact& k, int node)
{
  return {k.candidate_body, node,       k.antagonist_body,
          k.wall,           k.image[0], k.image[1]};
}

/// \f$\int_0^1 (1 - s) [g(s) \le g_c] ds\f$ for the gap linear along a
/// boundary segment from the node (gap gi, s = 0) to its neighbour (gj):
/// the node's shape function over the part of the segment within the
/// cohesive distance
double within(double gi, double gj, double gc)
{
  if (gi <= gc && gj <= gc)
    return 0.5;
  if (gi > gc && gj > gc)
    return 0.0;
  const double s = (gc - gi) / (gj - gi); // where the gap crosses gc
  return gi <= gc ? s - 0.5 * s * s : 0.5 * (1 - s) * (1 - s);
}
} // namespace

std::vector<double> cohesion_impulses(const FrictionTable& table,
                                      const bodies::BodySet& bodies,
                                      const std::vector<Contact>& contacts,
                                      double h)
{
  std::vector<double> c(contacts.size(), 0.0);
  std::map<ContactPlace, double> gaps;
  for (const Contact& k : contacts)
    if (table.cohesion(k).traction > 0)
      gaps[place_of(k, k.candidate_node)] = k.gap;
  const std::span<const double> X = bodies.reference_coordinates();
  const std::span<const double> u = bodies.displacement();
  // a node's current coordinate, as current_coordinates() gives it, without
  // copying every node's at each step
  auto x = [&](std::int32_t i) { return X[i] + u[i]; };
  for (std::size_t a = 0; a < contacts.size(); ++a)
  {
    const Contact& k = contacts[a];
    const Cohesion law = table.cohesion(k);
    if (law.traction == 0)
      continue;
    const bodies::Body& body = bodies.body(k.candidate_body);
    const int i = k.candidate_node;
    double share = 0; // the node's shape function within g_c (m)
    for (const std::int32_t s : {body.segment_from[i], body.segment_to[i]})
    {
      if (s < 0)
        continue;
      const auto& [p, q] = body.boundary_segments[s];
      const int j = p == i ? q : p;
      const auto found = gaps.find(place_of(k, j));
      // a neighbour not detected (beyond the alert distance): its gap
      // along this contact's normal, exact against a plane wall
      const std::int32_t gi = body.nodes[i], gj = body.nodes[j];
      const double gap_j = found != gaps.end()
                               ? found->second
                               : k.gap + (x(2 * gj) - x(2 * gi)) * k.n[0] +
                                     (x(2 * gj + 1) - x(2 * gi + 1)) * k.n[1];
      const std::int32_t gp = body.nodes[p], gq = body.nodes[q];
      share += within(k.gap, gap_j, law.distance) *
               std::hypot(X[2 * gq] - X[2 * gp], X[2 * gq + 1] - X[2 * gp + 1]);
    }
    const double sides = k.wall >= 0 ? 1.0 : 0.5;
    c[a] = law.traction * sides * share * h;
  }
  return c;
}

std::vector<std::array<double, 2>>
bond_strengths(const FrictionTable& table, const bodies::BodySet& bodies,
               const std::vector<Contact>& contacts,
               std::span<const std::int32_t> bonded, double h)
{
  std::vector<std::array<double, 2>> out;
  out.reserve(bonded.size());
  for (const std::int32_t a : bonded)
  {
    const Bond law = table.bond(contacts[a]);
    const double share = contact_share(bodies, contacts[a]);
    out.push_back({law.tensile * share * h, law.shear * share * h});
  }
  return out;
}

} // namespace softpack::dynamics
