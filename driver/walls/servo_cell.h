#pragma once

#include "periodic_cell.h"
#include "servo_walls.h"

/// A stress-controlled periodic cell within a Moreau-Jean step
/// (docs/periodic_cell.md, "A stress-controlled cell"). Each controlled
/// component h_ii is a servo unknown V (ServoStep), its load the imposed
/// stress times the edge across it. Its change over the step, V+ - V-,
/// gives every body the affine velocity change (V+ - V-) e_i s_{b,i}
/// (s_b = h^-1 c_b, c_b its centroid), which keeps a body and its images
/// on the same motion (the isotropic mode's, held by the mean stress:
/// (V+ - V-) W s_b, W = h / sqrt(det h)); a contact's relative velocity then
/// gains (V+ - V-) frame^T e_i (h^-1 l)_i, l its branch vector: the rank-one
/// coupling of the unknown to every particle contact, g_c = -(h^-1 l)_i
/// frame_c^T e_i.
namespace softpack::dynamics
{

/// Start a step: each stress-controlled component's free rate (ServoStep),
/// its coupling to every particle contact, and the contacts' known
/// velocity of the antagonist in H at the free rates:
/// (dh/dt)- k - sum_i (V_free - V-) e_i (h^-1 l)_i. Appended to `servo`
/// (after the walls' couplings), with the bodies' cell coordinates and the
/// contacts' h^-1 l.
/// @param[in] cell The cell at the start of the step
/// @param[in] contacts The step's contacts
/// @param[in] centroids Each body's centroid at the start of the step
/// @param[in,out] H The step's contact operator
/// @param[in] h Time step
/// @param[in] theta The scheme's theta (a damped component's V_mid)
/// @param[in] time The step's start time (the imposed stresses' ramps are
/// read at mid-step)
/// @param[in,out] servo The step's servo unknowns
void start_servo_cell(const PeriodicCell& cell,
                      const std::vector<Contact>& contacts,
                      const std::vector<std::array<double, 2>>& centroids,
                      ContactOperator& H, double h, double theta, double time,
                      ServoWalls& servo);

/// End a step: every component's V+ and V_mid from the impulses (the cell
/// itself is advanced, and the bodies given the affine change, by
/// MoreauJean::finish_cell_step).
void finish_servo_cell(ServoWalls& servo, std::span<const double> R,
                       double theta);

/// Before the step's contact accounts: the contacts' antagonist velocity at
/// the mid-step rates; then the components' terms: the imposed load's work
/// h F V_mid in cell_work, in place of the work the contacts transmit to
/// the component (internal, taken out of the cell_work that
/// add_contact_terms books), and the theta scheme's (th - 1/2) m dV^2.
void account_servo_cell(const ServoWalls& servo, const PeriodicCell& cell,
                        const std::vector<Contact>& contacts,
                        ContactOperator& H, std::span<const double> R,
                        EnergyBalance& energy, double h, double theta);

/// The stress-controlled components' kinetic energy, sum m V^2 / 2 (J/m)
double cell_kinetic_energy(const PeriodicCell& cell);

/// The isotropic mode's change of dh/dt per unit V, h / sqrt(det h): the
/// columns (x, y of a1's, then of a2's)
std::array<double, 4> isotropic_mode(const PeriodicCell& cell);

} // namespace softpack::dynamics
