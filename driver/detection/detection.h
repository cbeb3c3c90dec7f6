#pragma once

#include <array>
#include <bodies/BodySet.h>
#include <cstdint>
#include <span>
#include <vector>
#include <walls/walls.h>

/// Contact detection between deformable bodies and rigid walls.
namespace softpack::dynamics
{

/// One node-to-segment (or node-to-wall) contact.
///
/// The candidate is a boundary node; the antagonist is a boundary segment
/// of another body, or a wall. The local frame (n, t) has n pointing from
/// the antagonist to the candidate (the antagonist's outward normal) and
/// \f$t = (-n_y, n_x)\f$. The gap is \f$g = (x_{cand} - x_{ant}) \cdot n\f$.
/// The reaction acts as \f$+R_n n + R_t t\f$ on the candidate and its
/// opposite on the antagonist.
struct Contact
{
  /// Candidate body and its local node
  int candidate_body, candidate_node;
  /// Antagonist body (or -1 if a wall)
  int antagonist_body;
  /// Wall index (or -1 if a body)
  int wall;
  /// Antagonist segment (local nodes of antagonist_body) and the position
  /// \f$\xi \in [0, 1]\f$ of the projection on it
  std::array<std::int32_t, 2> segment;
  double xi;
  /// Unit normal and tangent
  std::array<double, 2> n, t;
  /// Gap at detection
  double gap;
  /// The antagonist feature is a vertex (segment[0]), not a face
  bool vertex = false;
};

/// Options of the detection.
struct DetectionOptions
{
  /// Pairs closer than this are kept (they may close during the step)
  double alert_distance = 1e-4;
  /// Penetrations deeper than this are taken as a detection on the wrong
  /// side (e.g. the far face of a thin body) and ignored
  double max_penetration = 1e-3;
};

/// Find all contacts in the current configuration x = X + u.
///
/// Broad phase: body bounding boxes on a uniform grid (cell = largest body
/// box), so the cost grows linearly with the number of bodies. Narrow
/// phase: every boundary node of one body of a near pair against the
/// boundary of the other, in both directions; one contact per (node,
/// antagonist body), with the nearest face or vertex. When two nodes face
/// each other (each within a quarter segment of the other) in both
/// directions, the two contacts are nearly the same constraint and only the
/// first is kept (redundant constraints make the contact problem
/// degenerate). Every boundary node against every wall.
/// @param[in] bodies The bodies (reference configuration and boundaries)
/// @param[in] x Current node coordinates (global, interleaved)
/// @param[in] walls Walls
/// @param[in] options Alert distance
/// @return The local bodies' share of the contacts
/// (BodySet::local_bodies; every body's until set_local): the pairs whose
/// first (lower) body is local and the wall contacts of the local bodies.
/// The shares of a partition of the bodies, put together and ordered by
/// contact_order_key, are the whole list in its order.
std::vector<Contact> detect_contacts(const bodies::BodySet& bodies,
                                     std::span<const double> x,
                                     const std::vector<Wall>& walls,
                                     const DetectionOptions& options);

/// The position of a contact's group in detect_contacts' order: the body
/// pairs (a < b) in increasing order, then each wall's contacts by body.
/// The contacts of one key come from one detection share, in their order.
std::int64_t contact_order_key(const Contact& c, int num_bodies);

/// Pairs of bodies whose bounding boxes, inflated by `margin`, overlap
/// (i < j). Exposed for tests and benchmarks.
std::vector<std::array<int, 2>> near_body_pairs(const bodies::BodySet& bodies,
                                                std::span<const double> x,
                                                double margin);

} // namespace softpack::dynamics
