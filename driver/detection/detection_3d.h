#pragma once

#include "detection.h"
#include <array>
#include <cstdint>
#include <span>
#include <vector>

/// Contact detection in 3D: boundary nodes against the boundary triangles
/// of other bodies and against plane walls (docs/contact_3d.md, "3D
/// detection"). The broad phase is the 2D one's (box_grid.h) for D = 3.
namespace softpack::dynamics
{

/// A body's boundary surface as the detection reads it: triangles of local
/// node indices oriented counter-clockwise seen from outside, so that
/// (b - a) x (c - a) is the outward normal, and the adjacency the edge and
/// vertex normals need.
class BoundarySurface
{
public:
  /// @param[in] nodes Storage index of each local node (x holds 3
  /// coordinates per storage index), as bodies::Body::nodes
  /// @param[in] triangles Boundary triangles, local node indices, outward
  /// @throws std::invalid_argument if the triangles do not make a closed,
  /// consistently oriented surface (each edge in exactly two triangles,
  /// once each way), a triangle repeats a node or names a node out of range
  BoundarySurface(std::vector<std::int32_t> nodes,
                  std::vector<std::array<std::int32_t, 3>> triangles);

  /// Storage index of each local node
  const std::vector<std::int32_t>& nodes() const { return _nodes; }
  /// Local indices of the nodes on the triangles (sorted): the candidates
  const std::vector<std::int32_t>& boundary_nodes() const
  {
    return _boundary_nodes;
  }
  const std::vector<std::array<std::int32_t, 3>>& triangles() const
  {
    return _triangles;
  }
  /// Triangle across edge k (vertices k, k + 1 mod 3) of triangle t
  std::int32_t neighbour(std::int32_t t, int k) const
  {
    return _neighbours[t][k];
  }
  /// Triangles around local node v
  std::span<const std::int32_t> triangles_around(std::int32_t v) const
  {
    return std::span(_around).subspan(
        _around_offsets[v], _around_offsets[v + 1] - _around_offsets[v]);
  }

private:
  std::vector<std::int32_t> _nodes, _boundary_nodes;
  std::vector<std::array<std::int32_t, 3>> _triangles, _neighbours;
  std::vector<std::int32_t> _around_offsets, _around;
};

/// Where on a triangle the point nearest to a node lies.
enum class Feature : std::int8_t
{
  face,
  edge,
  vertex
};

/// The point of triangle (a, b, c) nearest to p: its barycentric weights
/// (the point is w0 a + w1 b + w2 c, weights >= 0 summing to 1), the
/// feature it lies on, the edge (vertices k, k + 1 mod 3) or vertex k, and
/// the squared distance.
struct TrianglePoint
{
  std::array<double, 3> weights;
  Feature feature;
  int k;
  double distance2;
};

/// Nearest point of triangle (a, b, c) to p, by the Voronoi regions of its
/// vertices, edges and face.
TrianglePoint nearest_on_triangle(const double* p, const double* a,
                                  const double* b, const double* c);

/// An orthonormal right-handed frame (n, t1, t2) from the unit normal n:
/// t1 = e x n / |e x n| with e the coordinate axis least aligned with n
/// (the first of equals), t2 = n x t1. Deterministic and continuous while
/// that axis does not change.
std::array<std::array<double, 3>, 3>
contact_frame(const std::array<double, 3>& n);

/// One 3D node-to-face (or node-to-wall) contact.
///
/// The candidate is a boundary node; the antagonist a boundary triangle of
/// another body, or a wall. n points from the antagonist to the candidate;
/// the gap is g = (x_cand - q) . n with q = sum_i weights[i] x_triangle[i]
/// the antagonist's nearest point. The reaction R = R_n n + R_t1 t1 +
/// R_t2 t2 acts on the candidate and -weights[i] R on the triangle's node
/// i (the 3D form of the 2D segment's (1 - xi, xi)).
struct Contact3D
{
  /// Candidate body and its local node
  int candidate_body, candidate_node;
  /// Antagonist body (or -1 if a wall)
  int antagonist_body;
  /// Wall index (or -1 if a body)
  int wall;
  /// Antagonist triangle (local nodes of antagonist_body; -1 for a wall),
  /// the feature q lies on and q's barycentric weights
  std::array<std::int32_t, 3> triangle;
  Feature feature;
  std::array<double, 3> weights;
  /// Normal, then the two tangents (docs/contact_3d.md's order)
  std::array<double, 3> n, t1, t2;
  /// Gap at detection
  double gap;
};

/// A plane wall: the half-space (x - point) . normal >= 0 is free.
struct PlaneWall
{
  std::array<double, 3> point, normal;
};

/// The contact of boundary node `node` of body `cand` with the boundary of
/// body `ant` among the triangles `candidates` (all of them: pass every
/// index), by the rule of detect_contacts_3d; false if there is none.
/// @throws std::runtime_error if the feature's normal is undefined (a
/// triangle of zero area)
bool node_to_surface(std::span<const BoundarySurface> surfaces,
                     std::span<const double> x, int cand, std::int32_t node,
                     int ant, std::span<const std::int32_t> candidates,
                     const DetectionOptions& options, Contact3D& contact);

/// Find all 3D contacts in the current configuration x (3 coordinates per
/// storage index).
///
/// Broad phase: the bodies' boundary boxes, inflated by the search
/// distance r = max(alert_distance, max_penetration), on a uniform grid
/// (the 2D code's overlapping_pairs for D = 3); the triangles of each body
/// of a near pair binned once on a second grid, and each candidate node
/// (within r of the antagonist's box) compared with the antagonist's
/// triangles of the 27 cells around it: the cost grows linearly with the
/// triangles and nodes. Narrow phase: the antagonist's point nearest to the
/// node, if within r (ties: the lowest triangle index); n is the triangle's
/// normal on a face, the normalised sum of the two faces' normals on an
/// edge and the angle-weighted sum of the faces' normals around a vertex
/// (the 2D vertex's bisector; the sign of the gap is then right inside
/// and outside, Baerentzen and Aanaes 2005). A contact is kept when
/// -max_penetration <= gap <= alert_distance. When two nodes face each
/// other (each the node of weight >= 3/4 of the other's contact) both ways,
/// only the first contact is kept, as in 2D. Every boundary node against
/// every wall. Order: pairs (a < b) increasing, a's nodes on b then b's
/// nodes on a, then each wall's contacts by body and node.
/// @throws std::runtime_error if a node's nearest triangle (or one whose
/// normal its feature needs) has collapsed to zero area
/// @throws std::invalid_argument if a wall's normal is not a unit vector
std::vector<Contact3D> detect_contacts_3d(
    std::span<const BoundarySurface> surfaces, std::span<const double> x,
    const std::vector<PlaneWall>& walls, const DetectionOptions& options);

/// The local bodies' share of detect_contacts_3d (BodySet::local_bodies;
/// every body's until set_local), as detect_contacts' in 2D: the pairs
/// whose first (lower) body is local and the wall contacts of the local
/// bodies, each in its place in the whole list's order. The shares of a
/// partition of the bodies, put together and ordered by contact_order_key,
/// are the whole list in its order.
/// @param[in] surfaces Every body's boundary surface (of its storage
/// indices), in body order
/// @throws std::invalid_argument if there is not a surface per body
std::vector<Contact3D> detect_contacts_3d(
    const bodies::BodySet& bodies, std::span<const BoundarySurface> surfaces,
    std::span<const double> x, const std::vector<PlaneWall>& walls,
    const DetectionOptions& options);

/// The position of a 3D contact's group in detect_contacts_3d's order: the
/// body pairs (a < b) in increasing order, then each wall's contacts by
/// body (contact_order_key's numbers for 2D contacts)
std::int64_t contact_order_key(const Contact3D& c, int num_bodies);

/// Pairs (a < b) of surfaces whose boundary boxes, inflated by margin,
/// overlap (the broad phase of detect_contacts_3d)
std::vector<std::array<int, 2>>
near_surface_pairs(std::span<const BoundarySurface> surfaces,
                   std::span<const double> x, double margin);

} // namespace softpack::dynamics
