#pragma once

#include "walls.h"
#include <compliance/contact_operator.h>
#include <compliance/delassus.h>
#include <detection/detection.h>
#include <energy/energy_balance.h>
#include <span>
#include <vector>

/// The servo (pressure- or force-controlled) walls within a Moreau-Jean
/// step (walls.h): their free velocity, their coupling to the contact
/// problem, their update from the impulses and their energy terms.
namespace softpack::dynamics
{

/// One servo wall over one step.
struct ServoStep
{
  std::size_t wall;
  /// Imposed force per unit length along the normal, at the step's start
  double force;
  /// Normal velocity: start, free (h F / m added), end, theta-mid
  double v_old, v_free, v_new = 0, v_mid = 0;
};

/// The servo walls of a step: one ServoStep and one coupling each.
struct ServoWalls
{
  std::vector<ServoStep> steps;
  std::vector<WallCoupling> couplings;
  bool empty() const { return steps.empty(); }
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

/// End a step: V+ = V_free - (1/m) sum_c g_c . R_c from the converged
/// impulses, the wall advanced by h (th V+ + (1 - th) V-) along its normal.
/// @param[in,out] servo The step's servo walls (v_new, v_mid set)
/// @param[in,out] walls The walls (points and velocities of servo walls)
/// @param[in] R The step's impulses
/// @param[in] h, theta Time step and theta
void finish_servo_walls(ServoWalls& servo, std::vector<Wall>& walls,
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

} // namespace softpack::dynamics
