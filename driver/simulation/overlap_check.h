#pragma once

#include <array>
#include <bodies/BodySet.h>
#include <vector>
#include <walls/periodic_cell.h>
#include <walls/walls.h>

/// An overlap check independent of the contact detection (issue 16, item 5):
/// a detection that misses contacts (a too small contact.max_penetration,
/// a bug) lets bodies interpenetrate while reporting no penetration, so the
/// run measures the overlap again from the deformed boundaries alone.
namespace softpack::simulation
{

/// A boundary segment (ax, ay, bx, by), counter-clockwise around its body.
using Segment = std::array<double, 4>;

/// Each body's deformed boundary: its boundary segments at the current
/// displacement.
std::vector<std::vector<Segment>> deformed_boundaries(bodies::BodySet& bodies);

/// The largest depth of a boundary node inside another body or behind a
/// wall, m (0 when nothing overlaps).
///
/// A node of body A is inside body B when a ray from it crosses B's
/// boundary an odd number of times (valid for non-convex and deformed
/// polygons, unlike convex clipping); its depth is then its distance to B's
/// boundary. Only pairs whose bounding boxes intersect are tested. Behind a
/// wall, the depth is the node's distance to the wall line. In a periodic
/// cell, B's images shifted by h k, k in {-1, 0, 1}^2, are B's too (and A's
/// own images other than A).
double max_overlap_depth(const std::vector<std::vector<Segment>>& boundaries,
                         const std::vector<dynamics::Wall>& walls,
                         const dynamics::PeriodicCell* cell = nullptr);

} // namespace softpack::simulation
