#pragma once

#include <array>
#include <string>
#include <utility>
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

/// What drives a wall (schema [walls] control, velocity, pressure, force):
/// a [walls.NAME] table and a stage's walls.NAME give one.
struct WallDrive
{
  /// What drives the wall
  WallControl control = WallControl::velocity;
  /// Velocity: imposed (control velocity) or the current one (servo walls,
  /// always along the normal)
  std::array<double, 2> velocity = {0, 0};
  /// Imposed normal stress (Pa), control pressure: > 0 pushes the wall
  /// towards the particles
  double pressure = 0;
  /// Imposed normal force per unit length (N/m), control force
  double force = 0;

  /// Its normal velocity is an unknown of the step
  bool servo() const { return control != WallControl::velocity; }
};

/// A rigid wall: the half-plane \f$(x - p) \cdot n \ge 0\f$ is free, driven
/// by its WallDrive.
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
struct Wall : WallDrive
{
  Wall() = default;
  /// A velocity-controlled wall
  Wall(std::string name_, std::array<double, 2> point_,
       std::array<double, 2> normal_, std::array<double, 2> velocity_ = {0, 0})
      : WallDrive{WallControl::velocity, velocity_}, name(std::move(name_)),
        point(point_), normal(normal_)
  {
  }

  /// Name used in outputs ("left", "piston", ...)
  std::string name;
  /// A point of the wall line (current position)
  std::array<double, 2> point = {0, 0};
  /// Unit normal pointing into the free side (towards the bodies)
  std::array<double, 2> normal = {0, 1};
  /// Mass per unit length (kg/m) of a servo wall
  double mass = 0;
  /// The two walls between which this wall's length is measured (control
  /// pressure; set by link_walls)
  std::array<int, 2> span = {-1, -1};

  /// Normal velocity V = velocity . normal
  double normal_velocity() const
  {
    return velocity[0] * normal[0] + velocity[1] * normal[1];
  }
};

/// A plane wall of a 3D run: the half-space \f$(x - p) \cdot n \ge 0\f$
/// is free. It translates at its imposed velocity (the time stepper
/// advances `point` by h * velocity at each step), or it is a servo wall as
/// a 2D Wall is (its control, pressure, force and mass; the same law,
/// servo_walls.h), its normal velocity an unknown of the step: a pressure
/// pushes it with pressure x its current area (the product of its two
/// spans, the distances between the two pairs of facing walls
/// perpendicular to it), a force with that force (N), and its mass is in
/// kg. Its friction is its party's in the FrictionTable
/// (FrictionTable::wall_party, the wall's index among the 3D walls).
struct Wall3D
{
  /// Name used in outputs
  std::string name;
  /// A point of the wall plane (current position)
  std::array<double, 3> point = {0, 0, 0};
  /// Unit normal pointing into the free side (towards the bodies)
  std::array<double, 3> normal = {0, 0, 1};
  /// Imposed velocity
  std::array<double, 3> velocity = {0, 0, 0};
  /// The largest tension (N) each contact with this wall holds while it is
  /// closed (|gap| <= wall3d_closed_gap): 0, the default, is the plain
  /// unilateral wall; a large value, on a frictionless wall, a symmetry
  /// plane (the nodes lying on it stay on it and slide freely)
  double tensile_strength = 0;
  /// What drives it (velocity: the imposed velocity above) and, for a
  /// servo wall, its imposed pressure (Pa) or force (N) and its mass (kg)
  WallControl control = WallControl::velocity;
  double pressure = 0, force = 0, mass = 0;
  /// The two pairs of facing walls between which its area is measured
  /// (control pressure; set by link_walls)
  std::array<int, 4> span = {-1, -1, -1, -1};

  /// Its normal velocity is an unknown of the step
  bool servo() const { return control != WallControl::velocity; }
  /// Normal velocity V = velocity . normal
  double normal_velocity() const
  {
    return velocity[0] * normal[0] + velocity[1] * normal[1] +
           velocity[2] * normal[2];
  }
};

/// The gap (m) within which a contact with a Wall3D is closed: held by the
/// wall's tensile_strength
inline constexpr double wall3d_closed_gap = 1e-12;

/// The value key of `drive` that another control than its own sets
/// ("velocity", "pressure" or "force"), or nullptr: a wall is driven by one
/// of velocity, pressure or force, only the value of its control nonzero.
const char* conflicting_drive(const WallDrive& drive);

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

/// link_walls for the plane walls of a 3D run: every pressure-controlled
/// wall's two pairs of facing walls perpendicular to it (its area is the
/// product of their distances).
/// @throws std::invalid_argument as link_walls
void link_walls(std::vector<Wall3D>& walls);

/// Current area of plane wall w: the product of its two spans' distances.
double wall_area(const std::vector<Wall3D>& walls, std::size_t w);

/// Current length of wall w: the distance between its span walls.
double wall_length(const std::vector<Wall>& walls, std::size_t w);

/// Imposed normal force per unit length on a servo wall (N/m, along its
/// normal): pressure x current length, or the force.
double imposed_force(const std::vector<Wall>& walls, std::size_t w);

/// Imposed normal force on a servo plane wall (N, along its normal):
/// pressure x current area, or the force.
double imposed_force(const std::vector<Wall3D>& walls, std::size_t w);

/// Kinetic energy of the servo walls, sum of m V^2 / 2 (J/m).
double walls_kinetic_energy(const std::vector<Wall>& walls);
/// The same for the plane walls of a 3D run (J)
double walls_kinetic_energy(const std::vector<Wall3D>& walls);

} // namespace softpack::dynamics
