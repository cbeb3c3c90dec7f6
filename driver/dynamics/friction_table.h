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
/// The table is symmetric; pairs not set keep the default coefficient
/// ([contact] friction). An empty table (no species) gives the default to
/// every contact.
class FrictionTable
{
public:
  FrictionTable() = default;

  /// @param[in] default_coefficient Every pair's coefficient until set
  /// @param[in] body_species Species of each body
  /// @param[in] num_species Number of species
  /// @param[in] num_walls Number of walls
  FrictionTable(double default_coefficient, std::vector<int> body_species,
                int num_species, int num_walls);

  /// Set the coefficient of a pair (both orders).
  void set(int party_a, int party_b, double coefficient);

  /// The party of species s and of wall w
  int species_party(int s) const { return s; }
  int wall_party(int w) const { return _num_species + w; }

  /// The coefficient of a contact: its candidate body's species against
  /// its antagonist's (body's species or wall).
  double operator()(const Contact& c) const;

  /// The default coefficient
  double default_coefficient() const { return _default; }

  /// Whether the table holds the species of the bodies (else every contact
  /// has the default)
  bool empty() const { return _body_species.empty(); }

private:
  double _default = 0;
  std::vector<int> _body_species;
  int _num_species = 0, _num_parties = 0;
  std::vector<double> _coefficient;
};

} // namespace softpack::dynamics
