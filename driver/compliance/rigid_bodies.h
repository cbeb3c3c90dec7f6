#pragma once

#include "effective_stiffness.h"
#include <Eigen/Core>
#include <bodies/BodySet.h>
#include <span>
#include <vector>

namespace softpack::dynamics
{

/// The rigid bodies of a BodySet (their material's `rigid`) within a
/// Moreau–Jean step (docs/materials.md).
///
/// A rigid body keeps its nodes in the global displacement and velocity
/// vectors, so detection, the contact operator H, outputs and the state
/// file see it as any body; its motion is that of three degrees of freedom
/// V = (v_x, v_y, omega) about its mass centre c:
/// \f$v_i = P_i V\f$, \f$P_i = [[1, 0, -r_{iy}], [0, 1, r_{ix}]]\f$,
/// \f$r_i = x_i - c\f$. Its 3x3 mass matrix \f$M_r = P^T M P\f$ (M the
/// scheme's mass matrix of the body: m, and I about c) is computed once
/// from the mesh and the density; it does not change with the rotation.
///
/// In a step: \f$V^-\f$ is read from the node velocities by the exact
/// projection \f$M_r^{-1} P^T M v\f$ (so the state is (u, v) alone), the
/// free velocity is \f$V^- + h M_r^{-1} P^T F_{ext}\f$, the compliance seen
/// by the contacts is \f$P_i M_r^{-1} P_j^T\f$, the impulses give
/// \f$V = V_{free} + M_r^{-1} P^T (H R)\f$, and the nodes move by the exact
/// rigid motion (rotation by \f$h\omega_\theta\f$ about c, translation by
/// \f$h v_\theta\f$), which keeps their distances to round-off. No internal
/// or damping force acts on a rigid body.
class RigidBodies
{
public:
  /// @param[in] bodies The bodies (BodySet::rigid, masses, reference nodes)
  /// @param[in] kbar The scheme's mass matrices (lumped or consistent)
  RigidBodies(const bodies::BodySet& bodies, const EffectiveStiffness& kbar);

  /// Whether there is any rigid body
  bool empty() const { return _rigid.empty(); }
  /// Whether body b is rigid
  bool rigid(int b) const { return _index[b] >= 0; }

  /// Start a step at the bodies' displacement u: mass centres and arms,
  /// V- projected from v (whose rigid nodes are then set to P V-, exactly
  /// rigid), the free velocity from the external force; the iterate V is
  /// V-.
  void start_step(std::span<const double> u, std::span<double> v,
                  std::span<const double> f_ext, double h);

  /// The iterate becomes the free velocity (before this iteration's
  /// impulses).
  void reset_to_free();

  /// V += M_r^-1 P^T impulse for body b (impulse: its local nodal vector).
  void add_impulse(int b, const Eigen::VectorXd& impulse);

  /// P V of body b at the step's start configuration (2 per local node)
  Eigen::VectorXd velocity_field(int b) const;

  /// P_i V_free at local node i of body b
  Eigen::Vector2d free_velocity(int b, std::int32_t node) const;

  /// The compliance block \f$P_i M_r^{-1} P_j^T\f$ of nodes i, j of body b
  Eigen::Matrix2d compliance(int b, std::int32_t i, std::int32_t j) const;

  /// Set the rigid nodes of u to the exact rigid motion from the step's
  /// start by h (th V + (1 - th) V-).
  void displace(std::span<double> u, double h, double theta) const;

  /// Set the rigid nodes of v to P(x) V at the configuration x = X + u
  /// (the end of the step: the next step's contacts see these).
  void set_velocities(std::span<const double> u, std::span<double> v) const;

  /// Zero the entries of the rigid nodes of a global vector (forces).
  void zero(std::span<double> f) const;

private:
  struct Body
  {
    int body;
    /// The scheme's mass matrix of the body (a copy: the scheme may move)
    bodies::BodyMatrix nodal_mass;
    Eigen::Matrix3d mass, inverse_mass;
    /// Mass centre and arms r_i = x_i - c at the step's start
    Eigen::Vector2d centre;
    std::vector<Eigen::Vector2d> arms;
    /// Velocity at the start, free, and the current iterate
    Eigen::Vector3d v_old, v_free, v;
  };
  /// Mass centre (lumped masses) and arms of body k at x = X + u
  void place(Body& k, std::span<const double> u) const;
  Eigen::Matrix<double, 2, 3> kinematics(const Body& k, int node) const;

  const bodies::BodySet& _bodies;
  std::vector<int> _index;
  std::vector<Body> _rigid;
};

} // namespace softpack::dynamics
