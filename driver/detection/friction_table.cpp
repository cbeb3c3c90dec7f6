#include "friction_table.h"

#include "detection.h"

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

void FrictionTable::set(int a, int b, double coefficient)
{
  if (a < 0 || b < 0 || a >= _num_parties || b >= _num_parties)
    throw std::invalid_argument("FrictionTable: party out of range");
  if (!(coefficient >= 0))
    throw std::invalid_argument("FrictionTable: negative coefficient");
  _coefficient[a * _num_parties + b] = coefficient;
  _coefficient[b * _num_parties + a] = coefficient;
}

double FrictionTable::operator()(const Contact& c,
                                 double default_coefficient) const
{
  if (_body_species.empty())
    return default_coefficient;
  const int a = _body_species[c.candidate_body];
  const int b =
      c.wall >= 0 ? wall_party(c.wall) : _body_species[c.antagonist_body];
  const double set = _coefficient[a * _num_parties + b];
  return set == unset ? default_coefficient : set;
}

} // namespace softpack::dynamics
