#pragma once

#include <string>
#include <vector>

namespace softpack::dynamics
{
struct Contact;

/// The Coulomb friction coefficient of every pair of parties in contact:
/// the species of the bodies, and the walls (docs/materials.md).
///
/// Party p < num_species is species p; party num_species + w is wall w.
/// The table is symmetric and holds the pairs set ([[friction]]); every
/// other pair, and every contact of an empty table (no species), has the
/// default coefficient the caller passes ([contact] friction, stored there
/// only).
class FrictionTable
{
public:
  FrictionTable() = default;

  /// @param[in] body_species Species of each body
  /// @param[in] num_species Number of species
  /// @param[in] num_walls Number of walls
  FrictionTable(std::vector<int> body_species, int num_species, int num_walls);

  /// Set the coefficient of a pair (both orders).
  void set(int party_a, int party_b, double coefficient);

  /// The party of species s and of wall w
  int species_party(int s) const { return s; }
  int wall_party(int w) const { return _num_species + w; }

  /// The coefficient of a contact: that set for its candidate body's
  /// species against its antagonist's (body's species or wall), else
  /// `default_coefficient`.
  double operator()(const Contact& c, double default_coefficient) const;

private:
  std::vector<int> _body_species;
  int _num_species = 0, _num_parties = 0;
  /// Per pair of parties: the coefficient set, or < 0 (not set)
  std::vector<double> _coefficient;
};

} // namespace softpack::dynamics
