#pragma once

#include <array>
#include <bodies/BodySet.h>
#include <cstdint>
#include <span>
#include <vector>
#include <walls/periodic_cell.h>
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
  /// In a periodic cell: the antagonist is the image of antagonist_body
  /// shifted by h k, k = image (docs/periodic_cell.md); {0, 0} otherwise
  ImageShift image = {0, 0};
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
/// @param[in] cell A periodic cell (nullptr: none): every body is also
/// compared with the images of the others (near_image_pairs), each contact
/// recording its antagonist's image
/// @return The local bodies' share of the contacts
/// (BodySet::local_bodies; every body's until set_local): the pairs whose
/// first (lower) body is local and the wall contacts of the local bodies.
/// The shares of a partition of the bodies, put together and ordered by
/// contact_order_key, are the whole list in its order.
std::vector<Contact> detect_contacts(const bodies::BodySet& bodies,
                                     std::span<const double> x,
                                     const std::vector<Wall>& walls,
                                     const DetectionOptions& options,
                                     const PeriodicCell* cell = nullptr);

/// The position of a contact's group in detect_contacts' order: the body
/// pairs (a < b) in increasing order, then each wall's contacts by body.
/// The contacts of one key come from one detection share, in their order.
std::int64_t contact_order_key(const Contact& c, int num_bodies);

/// Pairs of bodies whose bounding boxes, inflated by `margin`, overlap
/// (i < j). Exposed for tests and benchmarks.
std::vector<std::array<int, 2>> near_body_pairs(const bodies::BodySet& bodies,
                                                std::span<const double> x,
                                                double margin);

/// A near pair of a periodic cell: body a and the image of body b shifted
/// by h k (a < b).
struct ImagePair
{
  int a, b;
  ImageShift image;
  auto operator<=>(const ImagePair&) const = default;
};

/// Pairs of bodies (a < b) whose bounding boxes, inflated by `margin`,
/// overlap when b is shifted by h k, k in {-1, 0, 1}^2: the images binned
/// on a uniform grid, so the cost grows linearly with the bodies.
/// @throws std::runtime_error if a body is not smaller than half the cell
/// (check_body_fits) or two images of one body are near another
std::vector<ImagePair> near_image_pairs(const bodies::BodySet& bodies,
                                        std::span<const double> x,
                                        double margin,
                                        const PeriodicCell& cell);

} // namespace softpack::dynamics
