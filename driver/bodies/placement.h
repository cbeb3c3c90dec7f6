#pragma once

#include "BodySet.h"
#include <vector>

/// Where each body is: its area centroid and its rotation from the
/// reference configuration, from its boundary polygon (the nodes every rank
/// holds, as for the current areas).
namespace softpack::bodies
{

/// A body's placement in the plane.
struct Placement
{
  /// Area centroid of the deformed boundary polygon (m)
  double x = 0, y = 0;
  /// Rotation from the reference configuration (rad, counter-clockwise,
  /// in (-pi, pi]): the angle of the rotation that best maps the reference
  /// boundary nodes about their centroid onto the current ones (least
  /// squares, the 2D Procrustes angle); a rigid body's own rotation
  double rotation = 0;
};

/// Each body's placement at the current displacement.
std::vector<Placement> placements(const BodySet& bodies);

/// Each 3D body's volume centroid at the current displacement, from its
/// closed boundary surface (the divergence theorem over its outward
/// boundary faces).
/// @throws std::invalid_argument if the bodies are not 3D
std::vector<std::array<double, 3>> centroids_3d(const BodySet& bodies);

} // namespace softpack::bodies
