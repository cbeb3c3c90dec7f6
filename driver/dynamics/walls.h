#pragma once

#include <array>
#include <string>
#include <vector>

/// Rigid walls: straight lines that bound the assembly.
namespace softpack::dynamics
{

/// How a wall moves.
enum class WallControl
{
  /// Its velocity is imposed (zero for a fixed wall)
  velocity,
  /// An imposed normal stress: the force per unit length along z pushing
  /// the wall towards the particles is pressure x the wall's current length
  pressure,
  /// An imposed normal force per unit length along z (N/m)
  force
};

/// A rigid wall: the half-plane \f$(x - p) \cdot n \ge 0\f$ is free.
///
/// A velocity-controlled wall translates at its imposed velocity; the time
/// stepper advances `point` by h * velocity at each step.
///
/// A servo (pressure- or force-controlled) wall is a rigid body with one
/// translational degree of freedom along its normal, of mass `mass` (a
/// numerical parameter, as in LMGC90: it sets how fast the wall reaches its
/// balance, not the balance itself). Its normal velocity V (stored as
/// velocity = V n) is an unknown of the Moreau-Jean step: the imposed force
/// F enters its momentum balance m (V+ - V-) = h F - sum_c (n . impulse on
/// the particle), and its contacts couple it to the bodies through the
/// contact problem (its compliance 1/m enters W). At rest the contact
/// reactions balance F exactly, with no controller gain to tune.
struct Wall
{
  /// Name used in outputs ("left", "piston", ...)
  std::string name;
  /// A point of the wall line (current position)
  std::array<double, 2> point;
  /// Unit normal pointing into the free side (towards the bodies)
  std::array<double, 2> normal;
  /// Velocity: imposed (control velocity) or the current one (servo walls,
  /// always along the normal)
  std::array<double, 2> velocity = {0, 0};
  /// What drives the wall
  WallControl control = WallControl::velocity;
  /// Imposed normal stress (Pa), control pressure: > 0 pushes the wall
  /// towards the particles
  double pressure = 0;
  /// Imposed normal force per unit length (N/m), control force
  double force = 0;
  /// Mass per unit length (kg/m) of a servo wall
  double mass = 0;
  /// The two walls between which this wall's length is measured (control
  /// pressure; set by link_walls)
  std::array<int, 2> span = {-1, -1};

  /// Its normal velocity is an unknown of the step
  bool servo() const { return control != WallControl::velocity; }
  /// Normal velocity V = velocity . normal
  double normal_velocity() const
  {
    return velocity[0] * normal[0] + velocity[1] * normal[1];
  }
};

/// The four walls of a box [x0, x1] x [y0, y1] facing inward; the wall at
/// x = x1 (named "piston") moves at -piston_speed along x.
std::vector<Wall> box_walls(double x0, double x1, double y0, double y1,
                            double piston_speed);

/// Find the span of every pressure-controlled wall: the two walls whose
/// normals are perpendicular to its own and opposite to each other (a
/// box's neighbours). Its length is then the distance between them, which
/// follows them when they move, so two orthogonal servo walls keep a
/// consistent corner.
/// @throws std::invalid_argument if a servo wall has no valid mass or a
/// pressure-controlled wall no such pair of walls
void link_walls(std::vector<Wall>& walls);

/// Current length of wall w: the distance between its span walls.
double wall_length(const std::vector<Wall>& walls, std::size_t w);

/// Imposed normal force per unit length on a servo wall (N/m, along its
/// normal): pressure x current length, or the force.
double imposed_force(const std::vector<Wall>& walls, std::size_t w);

/// Kinetic energy of the servo walls, sum of m V^2 / 2 (J/m).
double walls_kinetic_energy(const std::vector<Wall>& walls);

} // namespace softpack::dynamics
