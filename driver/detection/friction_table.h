#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace softpack::bodies
{
class BodySet;
}

namespace softpack::dynamics
{
struct Contact;
struct Contact3D;

/// The cohesive law of a pair of parties (docs/contact_laws.md)
struct Cohesion
{
  /// Largest tensile traction (Pa: N per m of boundary per m of
  /// thickness); 0: plain Signorini–Coulomb
  double traction = 0;
  /// The cohesion acts on a contact whose gap at the start of the step is
  /// at most this (m)
  double distance = 0;
};

/// The bonded law of a pair of parties (docs/contact_laws.md, law
/// "bonded"): strengths as tractions, turned into impulses per contact by
/// bond_strengths()
struct Bond
{
  /// Tensile strength sigma_t (Pa); 0: the pair is not bonded
  double tensile = 0;
  /// Shear strength tau_s (Pa)
  double shear = 0;
  /// A contact is bonded when its gap is at most this where bonds form (m)
  double distance = 0;
};

/// The contact law of every pair of parties in contact: the species of the
/// bodies, and the walls (docs/materials.md, docs/contact_laws.md): its
/// Coulomb friction coefficient, its cohesion and its bond.
///
/// Party p < num_species is species p; party num_species + w is wall w.
/// The table is symmetric and holds the pairs set ([[friction]]); every
/// other pair, and every contact of an empty table (no species), has the
/// default coefficient the caller passes ([contact] friction, stored there
/// only) and no cohesion.
class FrictionTable
{
public:
  FrictionTable() = default;

  /// @param[in] body_species Species of each body
  /// @param[in] num_species Number of species
  /// @param[in] num_walls Number of walls
  FrictionTable(std::vector<int> body_species, int num_species, int num_walls);

  /// Set the coefficient, the cohesion and the bond of a pair (both
  /// orders); a pair has at most one of a cohesion and a bond.
  void set(int party_a, int party_b, double coefficient, Cohesion cohesion = {},
           Bond bond = {});

  /// The party of species s and of wall w
  int species_party(int s) const { return s; }
  int wall_party(int w) const { return _num_species + w; }

  /// The coefficient of a contact: that set for its candidate body's
  /// species against its antagonist's (body's species or wall), else
  /// `default_coefficient`.
  double operator()(const Contact& c, double default_coefficient) const;
  /// The same for a 3D contact (its wall: an index among the 3D walls)
  double operator()(const Contact3D& c, double default_coefficient) const;

  /// true when a pair has a cohesion (else every contact's is 0)
  bool cohesive() const { return !_cohesion.empty(); }

  /// The cohesion of a contact's pair (none when not set)
  Cohesion cohesion(const Contact& c) const;

  /// true when a pair is bonded
  bool bonded() const { return !_bond.empty(); }

  /// The bond of a contact's pair (none when not set: tensile 0)
  Bond bond(const Contact& c) const;

private:
  /// The index of a contact's pair in the tables
  int pair(const Contact& c) const;
  /// The index of the pair (candidate body, antagonist body or wall)
  int pair(int candidate_body, int antagonist_body, int wall) const;
  /// The coefficient of a pair index, or the default
  double coefficient(int pair, double default_coefficient) const;
  std::vector<int> _body_species;
  int _num_species = 0, _num_parties = 0;
  /// Per pair of parties: the coefficient set, or < 0 (not set)
  std::vector<double> _coefficient;
  /// Per pair of parties: the cohesion (empty while no pair has one)
  std::vector<Cohesion> _cohesion;
  /// Per pair of parties: the bond (empty while no pair is bonded)
  std::vector<Bond> _bond;
};

/// A contact's share of the boundary, \f$s_a \ell_k\f$ (m): the candidate
/// node's share of its body's boundary (half its two boundary segments,
/// reference lengths) times \f$s_a = 1\f$ against a wall and 1/2 against a
/// body (the nodes of both bodies are candidates on their interface). A
/// traction of the pair times it is a force per unit thickness.
double contact_share(const bodies::BodySet& bodies, const Contact& c);

/// The cohesion impulse of each contact of a step (docs/contact_laws.md):
/// \f$c_a = \sigma_c \, s_a \, \ell_k \, h\f$ when the contact's gap at
/// the start of the step is at most its pair's cohesive distance, else 0;
/// \f$\sigma_c\f$ the pair's traction, \f$\ell_k\f$ the candidate node's
/// share of its body's boundary (half its two boundary segments, reference
/// lengths), \f$s_a = 1\f$ against a wall and 1/2 against a body (the
/// nodes of both bodies are candidates on their interface).
/// @param[in] table The pairs' laws (cohesive())
/// @param[in] bodies The bodies (boundaries and reference coordinates)
/// @param[in] contacts The step's contacts
/// @param[in] h Time step
/// @return One impulse per contact (N s per m of thickness)
std::vector<double> cohesion_impulses(const FrictionTable& table,
                                      const bodies::BodySet& bodies,
                                      const std::vector<Contact>& contacts,
                                      double h);

/// The impulse bounds of bonded contacts (docs/contact_laws.md):
/// \f$T_a = \sigma_t s_a \ell_k h\f$, \f$S_a = \tau_s s_a \ell_k h\f$
/// (contact_share()), the pair's strengths.
/// @param[in] bonded Indices of the contacts of bonded pairs
/// @return (T_a, S_a) per listed contact (N s per m of thickness)
std::vector<std::array<double, 2>>
bond_strengths(const FrictionTable& table, const bodies::BodySet& bodies,
               const std::vector<Contact>& contacts,
               std::span<const std::int32_t> bonded, double h);

} // namespace softpack::dynamics
