#pragma once

#include <Eigen/Core>
#include <compliance/contact_operator.h>
#include <cstdint>
#include <detection/detection.h>
#include <span>
#include <vector>

namespace softpack::dynamics
{

/// One vector per body, in the body's local DOF numbering.
using BodyVectors = std::vector<Eigen::VectorXd>;

/// Energy bookkeeping since the start (J per unit length along z).
///
/// Balance: wall_work + external_work + cell_work + rewrap = kinetic +
/// strain (their changes) + damping + contact_dissipation + cohesion + bond
/// + numerical + viscous; residual() is what is left.
struct EnergyBalance
{
  double wall_work = 0;
  double external_work = 0;
  /// Work of a periodic cell: through its image contacts, R . ((dh/dt) k),
  /// and, for a stress-controlled component, the imposed load's work in
  /// place of what its contacts transmit to it (docs/periodic_cell.md)
  double cell_work = 0;
  /// Kinetic energy given to the bodies by changes of their velocities by
  /// the cell's rate: re-wrapped into a deforming cell (-(dh/dt) k), and
  /// the affine change of a stress-controlled rate
  double rewrap = 0;
  double kinetic = 0, kinetic0 = 0;
  double strain = 0, strain0 = 0;
  double damping = 0;
  /// Friction (tangential) part of the contact dissipation
  double friction = 0;
  /// Normal part of the compressive (shifted) reactions: -(R_n + c) U_n
  /// (nonzero only through gap corrections)
  double contact_normal = 0;
  /// Work done against the cohesive reactions, c U_n (docs/contact_laws.md):
  /// stored while a bond holds (given back when it closes again), kept
  /// when it breaks
  double cohesion = 0;
  /// Work of the reactions of the intact bonds, -R . U_th, normal and
  /// tangential (docs/contact_laws.md, law "bonded"): dissipated (the
  /// work of breaking, and the theta scheme's small work while they hold);
  /// not counted in friction, contact_normal or cohesion
  double bond = 0;
  /// Dissipation of the theta scheme, (theta - 1/2) (|v+ - v-|_M^2 +
  /// dq . (F_int(q+) - F_int(q-))), dq = q+ - q-
  double numerical = 0;
  /// Viscous dissipation of the laws with internal variables: the drop of
  /// strain energy as they relax at each step's end
  /// (BodySet::update_internal_variables)
  double viscous = 0;

  /// Energy supplied minus energy stored and dissipated
  double residual() const
  {
    return wall_work + external_work + cell_work + rewrap -
           (kinetic - kinetic0 + strain - strain0 + damping + friction +
            contact_normal + cohesion + bond + numerical + viscous);
  }
};

/// Kinetic energy \f$\sum_b \tfrac12 v_b \cdot (M v)_b\f$ of the given
/// bodies.
/// @param[in] v Velocity of (at least) the given bodies
/// @param[in] Mv Mass times velocity of (at least) the given bodies
/// @param[in] bodies The bodies to count, in increasing order (the local
/// ones, BodySet::local_bodies, whose masses are kept)
double kinetic_energy(const BodyVectors& v, const BodyVectors& Mv,
                      std::span<const int> bodies);

/// Add the stiffness part of the theta scheme's dissipation over a step.
///
/// The scheme's internal-force work, dq . (th F+ + (1 - th) F-), exceeds
/// the change of strain energy by (th - 1/2) dq . (F+ - F-) (up to third
/// order in dq).
/// @param[in,out] energy The accounts
/// @param[in] theta theta of the scheme (nothing is added at 1/2)
/// @param[in] u_old, u_new Global displacement at the start and end
/// @param[in] f_old, f_new Global internal force at the start and end
/// @param[in] local_nodes 1 for the nodes whose terms are wanted
/// (BodySet::local_nodes: the local bodies', whose internal force is
/// computed; empty: all)
void add_stiffness_dissipation(EnergyBalance& energy, double theta,
                               std::span<const double> u_old,
                               std::span<const double> u_new,
                               std::span<const double> f_old,
                               std::span<const double> f_new,
                               std::span<const char> local_nodes = {},
                               int dim = 2);

/// Per-body vectors of one step, at its start (-) and end (+).
struct BodyStep
{
  const BodyVectors& v_old;  ///< v-
  const BodyVectors& v_new;  ///< v+
  const BodyVectors& v_mid;  ///< th v+ + (1 - th) v-
  const BodyVectors& Mv_old; ///< M v-
  const BodyVectors& Mv_new; ///< M v+
  const BodyVectors& Cv_old; ///< C v- (damping force)
  const BodyVectors& Cv_new; ///< C v+
  const BodyVectors& f_ext;  ///< external force
};

/// Add the body terms of one step: the damping work h v_th . (th C v+ +
/// (1 - th) C v-), the kinetic part of the theta scheme's dissipation
/// (th - 1/2) (v+ - v-) . M (v+ - v-), and the external work h v_th . F_ext.
/// @param[in,out] energy The accounts
/// @param[in] h Time step
/// @param[in] theta theta of the scheme
/// @param[in] step The step's vectors
/// @param[in] bodies The bodies to count, in increasing order (the local
/// ones, BodySet::local_bodies, whose C v and M v are computed)
void add_body_terms(EnergyBalance& energy, double h, double theta,
                    const BodyStep& step, std::span<const int> bodies);

/// Add the contact terms of one step: the friction and normal dissipation
/// -R . U_th (the normal one split into contact_normal and cohesion) and the
/// work of the velocity-controlled walls R . U_wall (impulses on the
/// candidates, U_th the relative velocity at th v+ + (1 - th) v-), and the
/// periodic cell's work R . (L h k) through its image contacts. A servo
/// wall's work is that of its imposed force (account_servo_walls in
/// servo_walls.h), not counted here.
/// @param[in,out] energy The accounts
/// @param[in] H The step's contact operator
/// @param[in] contacts The step's contacts
/// @param[in] walls The walls
/// @param[in] R Impulses, 2 per contact (n, t)
/// @param[in] U_mid Relative velocities at v_th, 2 per contact (n, t)
/// @param[in] cohesion Cohesion impulse of each contact (empty: none): its
///   part of -R_n U_n, c U_n, is the `cohesion` account, the rest
///   -(R_n + c) U_n `contact_normal`
/// @param[in] bonds The contacts that are intact bonds (ascending): their
///   whole -R . U_th is the `bond` account
void add_contact_terms(EnergyBalance& energy, const ContactOperator& H,
                       const std::vector<Contact>& contacts,
                       const std::vector<Wall>& walls,
                       std::span<const double> R, std::span<const double> U_mid,
                       std::span<const double> cohesion = {},
                       std::span<const std::int32_t> bonds = {});

/// The contact terms of a 3D step (no cohesion or bond): friction
/// -R_t . U_t (both tangents), normal -R_n U_n, and the velocity-controlled
/// walls' work R . U_wall (ContactOperator::wall_velocity); a servo wall's
/// contacts transmit its work, account_servo_walls counts the imposed
/// force's (as add_contact_terms of 2D)
void add_contact_terms(EnergyBalance& energy, const ContactOperator& H,
                       const std::vector<Contact3D>& contacts,
                       const std::vector<Wall3D>& walls,
                       std::span<const double> R,
                       std::span<const double> U_mid);

} // namespace softpack::dynamics
