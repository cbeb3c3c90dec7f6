#pragma once

#include <array>
#include <string>
#include <vector>

/// Rigid walls: straight lines that bound the assembly.
namespace softpack::dynamics
{

/// A rigid wall: the half-plane \f$(x - p) \cdot n \ge 0\f$ is free. A
/// wall translates at its imposed velocity (zero for a fixed wall); the
/// time stepper advances `point` by h * velocity at each step.
struct Wall
{
  /// Name used in outputs ("left", "piston", ...)
  std::string name;
  /// A point of the wall line (current position)
  std::array<double, 2> point;
  /// Unit normal pointing into the free side (towards the bodies)
  std::array<double, 2> normal;
  /// Imposed velocity
  std::array<double, 2> velocity = {0, 0};
};

/// The four walls of a box [x0, x1] x [y0, y1] facing inward; the wall at
/// x = x1 (named "piston") moves at -piston_speed along x.
std::vector<Wall> box_walls(double x0, double x1, double y0, double y1,
                            double piston_speed);

} // namespace softpack::dynamics
