#pragma once

#include "effective_stiffness.h"
#include <Eigen/Core>
#include <bodies/BodySet.h>
#include <span>
#include <variant>
#include <vector>

namespace softpack::dynamics
{

/// The rigid bodies of a BodySet of dimension D (their material's `rigid`)
/// within a Moreau–Jean step (docs/materials.md, "Rigid bodies").
///
/// A rigid body keeps its nodes in the global displacement and velocity
/// vectors, so detection, the contact operator H, outputs and the state
/// file see it as any body; its motion is that of N degrees of freedom
/// V = (v, omega) about its mass centre c (N = 3 in 2D, 6 in 3D):
/// \f$v_i = P_i V\f$, \f$P_i = [I, -[r_i]_\times]\f$ (v + omega x r_i),
/// \f$r_i = x_i - c\f$. Its mass matrix \f$M_r = P^T M P\f$ (M the
/// scheme's mass matrix of the body: m, and the inertia about c) is made
/// from the mesh and the density; in 2D it does not change with the
/// rotation and is made once, in 3D it turns with the body and is remade
/// at each step's start.
///
/// In a step: \f$V^-\f$ is read from the node velocities by the exact
/// projection \f$M_r^{-1} P^T M v\f$ (so the state is (u, v) alone), the
/// free velocity is \f$V^- + h M_r^{-1} P^T F_{ext}\f$, the compliance seen
/// by the contacts is \f$P_i M_r^{-1} P_j^T\f$, the impulses give
/// \f$V = V_{free} + M_r^{-1} P^T (H R)\f$, and the nodes move by the exact
/// rigid motion (rotation by \f$h\omega_\theta\f$ about c in 2D; in 3D by
/// Rodrigues' formula of the rotation vector the momenta \f$M_r
/// V_\theta\f$ have on the body turned half way, the midpoint rule of the
/// gyroscopic term; translation by \f$h v_\theta\f$), which keeps their
/// distances to round-off. At the step's end, in 3D, the momenta about c
/// are carried to the turned body: \f$V \leftarrow M_r(x)^{-1} M_r V\f$ (a
/// free body keeps them to round-off; an asymmetric top's orientation and
/// kinetic energy err at second order in h). No internal or damping force
/// acts on a rigid body.
template <int D> class RigidBodySet
{
public:
  /// Degrees of freedom of one body
  static constexpr int N = D == 2 ? 3 : 6;
  using Velocity = Eigen::Matrix<double, N, 1>;
  using Point = Eigen::Matrix<double, D, 1>;
  using Compliance = Eigen::Matrix<double, D, D>;

  /// @param[in] bodies The bodies (BodySet::rigid, masses, reference nodes)
  /// @param[in] kbar The scheme's mass matrices (lumped or consistent)
  RigidBodySet(const bodies::BodySet& bodies, const EffectiveStiffness& kbar);

  bool empty() const { return _rigid.empty(); }
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

  /// P V of body b at the step's start configuration (D per local node)
  Eigen::VectorXd velocity_field(int b) const;

  /// P_i V_free at local node i of body b
  Point free_velocity(int b, std::int32_t node) const;

  /// The compliance block \f$P_i M_r^{-1} P_j^T\f$ of nodes i, j of body b
  Compliance compliance(int b, std::int32_t i, std::int32_t j) const;

  /// Set the rigid nodes of u to the exact rigid motion from the step's
  /// start by h (th V + (1 - th) V-).
  void displace(std::span<double> u, double h, double theta) const;

  /// Set the rigid nodes of v to P(x) V at the configuration x = X + u
  /// (the end of the step: the next step's contacts see these).
  void set_velocities(std::span<const double> u, std::span<double> v) const;

  /// Zero the entries of the rigid nodes of a global vector (forces).
  void zero(std::span<double> f) const;

private:
  using Mass = Eigen::Matrix<double, N, N>;
  using Kinematics = Eigen::Matrix<double, D, N>;
  struct Body
  {
    int body;
    /// The scheme's mass matrix of the body (a copy: the scheme may move)
    bodies::BodyMatrix nodal_mass;
    Mass mass, inverse_mass;
    /// Mass centre and arms r_i = x_i - c at the step's start
    Point centre;
    std::vector<Point> arms;
    /// Velocity at the start, free, and the current iterate
    Velocity v_old, v_free, v;
  };
  /// Mass centre (lumped masses) and arms of body k at x = X + u
  void place(Body& k, std::span<const double> u) const;
  /// M_r = P^T M P at k's arms
  Mass rigid_mass(const Body& k) const;
  Kinematics kinematics(const Body& k, int node) const;

  const bodies::BodySet& _bodies;
  std::vector<int> _index;
  std::vector<Body> _rigid;
};

/// The rigid bodies of a BodySet of either dimension, as the Moreau–Jean
/// step calls them (RigidBodySet<BodySet::dim()>).
class RigidBodies
{
public:
  RigidBodies(const bodies::BodySet& bodies, const EffectiveStiffness& kbar);

  /// Whether there is any rigid body
  bool empty() const
  {
    return std::visit([](const auto& s) { return s.empty(); }, _set);
  }
  /// Whether body b is rigid
  bool rigid(int b) const
  {
    return std::visit([b](const auto& s) { return s.rigid(b); }, _set);
  }
  /// The set of dimension D (the bodies')
  template <int D> const RigidBodySet<D>& of() const
  {
    return std::get<RigidBodySet<D>>(_set);
  }

  void start_step(std::span<const double> u, std::span<double> v,
                  std::span<const double> f_ext, double h)
  {
    std::visit([&](auto& s) { s.start_step(u, v, f_ext, h); }, _set);
  }
  void reset_to_free()
  {
    std::visit([](auto& s) { s.reset_to_free(); }, _set);
  }
  void add_impulse(int b, const Eigen::VectorXd& impulse)
  {
    std::visit([&](auto& s) { s.add_impulse(b, impulse); }, _set);
  }
  Eigen::VectorXd velocity_field(int b) const
  {
    return std::visit([b](const auto& s) { return s.velocity_field(b); }, _set);
  }
  /// P_i V_free at local node i of body b (D components)
  Eigen::VectorXd free_velocity(int b, std::int32_t node) const
  {
    return std::visit([&](const auto& s) -> Eigen::VectorXd
                      { return s.free_velocity(b, node); },
                      _set);
  }
  void displace(std::span<double> u, double h, double theta) const
  {
    std::visit([&](const auto& s) { s.displace(u, h, theta); }, _set);
  }
  void set_velocities(std::span<const double> u, std::span<double> v) const
  {
    std::visit([&](const auto& s) { s.set_velocities(u, v); }, _set);
  }
  void zero(std::span<double> f) const
  {
    std::visit([&](const auto& s) { s.zero(f); }, _set);
  }

private:
  std::variant<RigidBodySet<2>, RigidBodySet<3>> _set;
};

} // namespace softpack::dynamics
