#pragma once

#include "walls.h"
#include <compliance/contact_operator.h>
#include <compliance/delassus.h>
#include <detection/detection.h>
#include <detection/detection_3d.h>
#include <energy/energy_balance.h>
#include <span>
#include <vector>

/// The servo (pressure- or force-controlled) walls within a Moreau-Jean
/// step (walls.h): their free velocity, their coupling to the contact
/// problem, their update from the impulses and their energy terms.
namespace softpack::dynamics
{

/// One scalar velocity unknown with a mass over one step: a servo wall's
/// normal velocity, or a stress-controlled cell component's edge rate
/// (servo_cell.h). The one rule both follow: V_free = V- + h F / m, the
/// contacts of its WallCoupling add -(1/m) sum_c g_c . R_c, it moves at
/// th V+ + (1 - th) V-, and its energy terms.
struct ServoStep
{
  /// The wall, or the cell's servo component (PeriodicCell::servo)
  std::size_t index;
  /// Imposed force per unit length (its load), at the step's start
  double force;
  /// Mass per unit length (kg/m)
  double mass;
  /// Velocity: start, free (h F / m added), end, theta-mid
  double v_old, v_free = 0, v_new = 0, v_mid = 0;
  /// Viscous damping c (the force -c V_mid) and the inertia the impulses
  /// meet, m + theta h c (m without damping)
  double damping = 0, inertia = mass;

  /// Start: V_free = V- + h F / m
  static ServoStep start(std::size_t index, double force, double mass,
                         double v_old, double h);
  /// Start of a damped unknown, m (V+ - V-) = h (F - c V_mid) + impulses
  /// with V_mid = theta V+ + (1 - theta) V-: V+ = V_free + impulses / m',
  /// m' = m + theta h c, V_free = V- + h (F - c V-) / m'
  static ServoStep start_damped(std::size_t index, double force, double mass,
                                double damping, double v_old, double h,
                                double theta);
  /// From the converged impulses: V+ = V_free - (1/m) sum_c g_c . R_c and
  /// V_mid (D: the contacts' dimension, 2 or 3; R has D per contact)
  template <int D>
  void finish(const WallCouplingD<D>& coupling, std::span<const double> R,
              double theta);
  /// The work the unknown transmits to its contacts over the step,
  /// V_mid sum_c g_c . R_c (their R . U_wall)
  template <int D>
  double transmitted(const WallCouplingD<D>& coupling,
                     std::span<const double> R) const;
  /// Its energy terms: the work of the imposed force h F V_mid (returned),
  /// (th - 1/2) m (V+ - V-)^2 added to the numerical dissipation and the
  /// damping's h c V_mid^2 to the damping
  double account(EnergyBalance& energy, double h, double theta) const;
};

/// The servo unknowns of a step: the servo walls', then the cell's
/// stress-controlled components; one coupling each, in that order (a 3D
/// run's servo plane walls: couplings_3d, no cell).
struct ServoWalls
{
  std::vector<ServoStep> steps;
  std::vector<ServoStep> cell;
  std::vector<WallCoupling> couplings;
  std::vector<WallCouplingD<3>> couplings_3d;
  /// A stress-controlled cell (servo_cell.h): each body's cell coordinates
  /// s_b = h^-1 c_b at the step's start, and each contact's h^-1 l (l the
  /// branch vector from the antagonist's image centroid to the
  /// candidate's; zero for a wall contact)
  std::vector<std::array<double, 2>> cell_coordinates, cell_branch;
  /// The cell's isotropic mode at the step's start, W = h / sqrt(det h)
  /// (columns: a1's x, y, a2's x, y; isotropic_mode in servo_cell.h)
  std::array<double, 4> cell_mode = {0, 0, 0, 0};
  bool empty() const { return steps.empty() && cell.empty(); }
  /// W h^-1 l of contact a: its branch vector over sqrt(det h)
  std::array<double, 2> mode_branch(std::size_t a) const
  {
    return mode_times(cell_branch[a]);
  }
  /// W s
  std::array<double, 2> mode_times(const std::array<double, 2>& s) const
  {
    return {cell_mode[0] * s[0] + cell_mode[2] * s[1],
            cell_mode[1] * s[0] + cell_mode[3] * s[1]};
  }
  /// The coupling of the cell's k-th component
  const WallCoupling& cell_coupling(std::size_t k) const
  {
    return couplings[steps.size() + k];
  }
};

/// Start a step: every servo wall's free velocity V- + h F / m (the
/// velocity it would reach without contacts), set as its contacts' wall
/// velocity in H (so the solver's free relative velocity has it), and its
/// coupling to W. Nothing is done (or changed) without servo walls.
/// @param[in] walls The walls at the start of the step
/// @param[in] contacts The step's contacts
/// @param[in,out] H The step's contact operator
/// @param[in] h Time step
ServoWalls start_servo_walls(const std::vector<Wall>& walls,
                             const std::vector<Contact>& contacts,
                             ContactOperator& H, double h);
/// The same for the plane walls of a 3D run and their contacts
ServoWalls start_servo_walls(const std::vector<Wall3D>& walls,
                             const std::vector<Contact3D>& contacts,
                             ContactOperator& H, double h);

/// End a step: V+ = V_free - (1/m) sum_c g_c . R_c from the converged
/// impulses, the wall advanced by h (th V+ + (1 - th) V-) along its normal.
/// @param[in,out] servo The step's servo walls (v_new, v_mid set)
/// @param[in,out] walls The walls (points and velocities of servo walls)
/// @param[in] R The step's impulses
/// @param[in] h, theta Time step and theta
void finish_servo_walls(ServoWalls& servo, std::vector<Wall>& walls,
                        std::span<const double> R, double h, double theta);
/// The same for the plane walls of a 3D run
void finish_servo_walls(ServoWalls& servo, std::vector<Wall3D>& walls,
                        std::span<const double> R, double h, double theta);

/// Before the step's contact accounts: the servo walls' contacts move at
/// the walls' mid-step velocity th V+ + (1 - th) V-, the velocity at which
/// the wall moved. Then add the servo walls' own terms: the work of the
/// imposed force h F V_mid to wall_work, and (th - 1/2) m (V+ - V-)^2 to
/// the numerical dissipation (their kinetic energy is in the accounts'
/// kinetic terms, walls_kinetic_energy); the work their contacts transmit
/// is then internal and add_contact_terms leaves it out of wall_work.
/// @param[in] servo The finished step's servo walls
/// @param[in] walls The walls
/// @param[in,out] H The step's contact operator
/// @param[in,out] energy The accounts
/// @param[in] h, theta Time step and theta
void account_servo_walls(const ServoWalls& servo,
                         const std::vector<Wall>& walls, ContactOperator& H,
                         EnergyBalance& energy, double h, double theta);
/// The same for the plane walls of a 3D run
void account_servo_walls(const ServoWalls& servo,
                         const std::vector<Wall3D>& walls, ContactOperator& H,
                         EnergyBalance& energy, double h, double theta);

} // namespace softpack::dynamics
