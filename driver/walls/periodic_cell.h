#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

/// A periodic cell: the assembly as one cell of a periodic tiling
/// (docs/periodic_cell.md).
namespace softpack::dynamics
{

/// Integer image shift k: the image of a point x is x + h k.
using ImageShift = std::array<int, 2>;

/// A stress-controlled diagonal component of the cell (schema [cell]
/// control_xx, control_yy): the rate of h_ii is an unknown of each step,
/// found so that the imposed stress holds, as a servo wall's velocity is
/// (docs/periodic_cell.md, "A stress-controlled cell").
struct CellServo
{
  /// The isotropic mode's axis: dh/dt += V h / sqrt(det h), held by the
  /// mean stress ([cell] control_mean)
  static constexpr int mean = 2;
  /// The shear component h_xy (the edge a2's x), held by the shear stress
  /// sigma_xy ([cell] control_xy)
  static constexpr int shear_xy = 3;
  /// The component (0: h_xx, the edge a1's x; 1: h_yy, the edge a2's y;
  /// CellServo::mean: the isotropic mode; CellServo::shear_xy: h_xy)
  int axis = 1;
  /// The imposed normal stress sigma_ii, or the mean stress (Pa),
  /// compressive positive as a servo wall's pressure, at ramp_start
  double stress = 0;
  /// The fictitious mass (kg/m) of the degree of freedom
  double mass = 1;
  /// Its viscous damping c (N s/m^2 per unit length along z: the force
  /// -c V), mass / [cell] damping_time; 0: undamped
  double damping = 0;
  /// The isotropic mode's velocity V (m/s; a diagonal component's is its
  /// edge's rate, PeriodicCell::axis_rate)
  double velocity = 0;
  /// The stress's rate of change (Pa/s; [cell] stress_rate): a ramp from
  /// ramp_start (last: the brace initializers give the fields above)
  double stress_rate = 0;
  /// The time the drive started (s): the ramp's origin
  double ramp_start = 0;
  /// The row i and column j of the component h_ij (not for the mode): its
  /// rate's change gives a body at s the velocity change dV e_i s_j
  int row() const { return axis == shear_xy ? 0 : axis; }
  int column() const { return axis == shear_xy ? 1 : axis; }
  /// The imposed stress at time t: the ramp, a compressive one stopping
  /// at zero (the shear stress has either sign)
  double stress_at(double t) const
  {
    const double s = stress + stress_rate * (t - ramp_start);
    return axis == shear_xy ? s : std::max(s, 0.0);
  }
};

/// A cell's drive ([cell] or a stage's cell table): the imposed velocity
/// gradient's rows and the stress-controlled components.
struct CellDrive
{
  std::array<double, 2> gradient_x = {0, 0}, gradient_y = {0, 0};
  std::vector<CellServo> servo;
  /// The same gradient and components (their velocities aside)
  bool same(const CellDrive& o) const
  {
    if (gradient_x != o.gradient_x || gradient_y != o.gradient_y ||
        servo.size() != o.servo.size())
      return false;
    for (std::size_t k = 0; k < servo.size(); ++k)
      if (servo[k].axis != o.servo[k].axis ||
          servo[k].stress != o.servo[k].stress ||
          servo[k].stress_rate != o.servo[k].stress_rate ||
          servo[k].mass != o.servo[k].mass ||
          servo[k].damping != o.servo[k].damping)
        return false;
    return true;
  }
};

/// The cell spanned by the edge vectors a1, a2 (the columns of h), whose
/// edges move at constant velocities \f$\dot h = L h_0\f$: L the imposed
/// velocity gradient at the start, h0 the cell then. The images' velocities
/// relative to their bodies, \f$\dot h k\f$, are then constant, as a body
/// and its images obey the same equations of motion only if the images do
/// not accelerate. A stress-controlled component's rate changes from step
/// to step; every body then receives the change's affine velocity
/// (MoreauJean::affine_kick) so that its images still move with it
/// (docs/periodic_cell.md).
struct PeriodicCell
{
  /// Edge vectors (m): the columns of h
  std::array<double, 2> a1 = {0, 0}, a2 = {0, 0};
  /// Their velocities (m/s): the columns of \f$\dot h\f$; constant but
  /// for the stress-controlled components
  std::array<double, 2> a1_rate = {0, 0}, a2_rate = {0, 0};
  /// The stress-controlled components (none: the whole L imposed)
  std::vector<CellServo> servo;
  /// The lean |h_xy| / h_xx beyond which the cell is remapped (a2 -+ a1,
  /// the same lattice): 1/2 keeps the nearest images in {-1, 0, 1}^2
  double remap_lean = 0.5;

  /// The cell h0 = [a1 a2] moving with the velocity gradient L (rows
  /// [L_xx, L_xy] and [L_yx, L_yy], schema [cell] velocity_gradient_x, _y)
  /// at the start: $\dot h = L h_0$
  static PeriodicCell moving(const std::array<double, 2>& a1,
                             const std::array<double, 2>& a2,
                             const std::array<double, 2>& gradient_x,
                             const std::array<double, 2>& gradient_y);
  /// The translation h k of the image k
  std::array<double, 2> shift(const ImageShift& k) const
  {
    return {k[0] * a1[0] + k[1] * a2[0], k[0] * a1[1] + k[1] * a2[1]};
  }
  /// The image's velocity relative to the body's, \f$\dot h k\f$
  std::array<double, 2> rate(const ImageShift& k) const
  {
    return {k[0] * a1_rate[0] + k[1] * a2_rate[0],
            k[0] * a1_rate[1] + k[1] * a2_rate[1]};
  }
  /// The cell coordinates \f$s = h^{-1} x\f$ of a point
  std::array<double, 2> fractional(const std::array<double, 2>& x) const;
  /// The cell's area det h (m^2)
  double area() const { return a1[0] * a2[1] - a1[1] * a2[0]; }
  /// The cell's widths across its edges: area / |a2| (along a1's
  /// direction across a2) and area / |a1|
  std::array<double, 2> widths() const;
  /// The largest edge speed (m/s)
  double speed() const;
  /// One step of size dt: \f$h^+ = h^- + dt\, \dot h\f$
  void advance(double dt);
  /// The rate of the component h_ii (m/s)
  /// (CellServo::shear_xy: h_xy's, the edge a2's x)
  double& axis_rate(int i)
  {
    return i == 0 ? a1_rate[0] : i == 1 ? a2_rate[1] : a2_rate[0];
  }
  double axis_rate(int i) const
  {
    return i == 0 ? a1_rate[0] : i == 1 ? a2_rate[1] : a2_rate[0];
  }
  /// The imposed force per unit length along z on the component h_ii, its
  /// conjugate: -stress x the cofactor of h_ii (the edge's length across
  /// the axis, h_yy for h_xx and h_xx for h_yy): negative (closing) under
  /// a compressive stress
  /// The isotropic mode's: -2 P sqrt(det h), the work of sigma = -P I on
  /// the change dh = h dV / sqrt(det h)
  /// (the stress at time t, CellServo::stress_at)
  double servo_force(const CellServo& s, double t) const
  {
    const double stress = s.stress_at(t);
    if (s.axis == CellServo::mean)
      return -2 * stress * std::sqrt(area());
    // h_xy's: the work of sigma_yx = stress on dh_xy, det h sigma_yx /
    // h_yy = stress h_xx (a1 along x)
    if (s.axis == CellServo::shear_xy)
      return stress * a1[0];
    return -stress * (s.axis == 0 ? a2[1] : a1[0]);
  }
  /// The velocity of a servo unknown: its component's rate or the
  /// isotropic mode's V
  double servo_velocity(const CellServo& s) const
  {
    return s.axis == CellServo::mean ? s.velocity : axis_rate(s.axis);
  }
  /// Remap a cell leaning more than remap_lean: a2 -> a2 - n a1 (n = the
  /// nearest integer to h_xy / h_xx), the same lattice, and its rate
  /// likewise (dh/dt = L h0 with h0 remapped alike). An image shift k in
  /// the old basis is (k1 + n k2, k2) in the new one.
  /// @return n (0: no remap)
  int remap();
};

/// Refuse a body too large for the cell: a bounding box as wide as half
/// the cell's width across an edge would touch two images of a neighbour.
/// @param[in] cell The cell
/// @param[in] body The body index (named in the message)
/// @param[in] extent The body's bounding-box extent along x and y (m)
/// @throws std::runtime_error naming the sizes
void check_body_fits(const PeriodicCell& cell, int body,
                     const std::array<double, 2>& extent);

} // namespace softpack::dynamics
