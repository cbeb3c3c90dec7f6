#include "rigid_bodies.h"

#include <Eigen/Geometry>
#include <cmath>

namespace softpack::dynamics
{

RigidBodies::RigidBodies(const bodies::BodySet& bodies,
                         const EffectiveStiffness& kbar)
    : _bodies(bodies), _index(bodies.num_bodies(), -1)
{
  const std::vector<double> zero(bodies.num_dofs(), 0.0);
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    if (!bodies.rigid(b))
      continue;
    Body k{b, kbar.mass(b)};
    place(k, zero);
    // M_r = P^T M P at the reference configuration.
    const int n = static_cast<int>(bodies.body(b).nodes.size());
    Eigen::MatrixXd P(2 * n, 3);
    for (int i = 0; i < n; ++i)
      P.middleRows<2>(2 * i) = kinematics(k, i);
    k.mass = P.transpose() * (k.nodal_mass.selfadjointView<Eigen::Lower>() * P);
    k.inverse_mass = k.mass.inverse();
    _index[b] = static_cast<int>(_rigid.size());
    _rigid.push_back(std::move(k));
  }
}

void RigidBodies::place(Body& k, std::span<const double> u) const
{
  const bodies::Body& body = _bodies.body(k.body);
  const Eigen::VectorXd& m = _bodies.lumped_mass()[k.body];
  const std::span<const double> X = _bodies.reference_coordinates();
  const std::size_t n = body.nodes.size();
  std::vector<Eigen::Vector2d> x(n);
  Eigen::Vector2d moment = Eigen::Vector2d::Zero();
  double total = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::int32_t g = body.nodes[i];
    x[i] = {X[2 * g] + u[2 * g], X[2 * g + 1] + u[2 * g + 1]};
    moment += m[2 * i] * x[i];
    total += m[2 * i];
  }
  k.centre = moment / total;
  k.arms.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    k.arms[i] = x[i] - k.centre;
}

Eigen::Matrix<double, 2, 3> RigidBodies::kinematics(const Body& k,
                                                    int node) const
{
  const Eigen::Vector2d& r = k.arms[node];
  Eigen::Matrix<double, 2, 3> P;
  P << 1, 0, -r.y(), 0, 1, r.x();
  return P;
}

void RigidBodies::start_step(std::span<const double> u, std::span<double> v,
                             std::span<const double> f_ext, double h)
{
  for (Body& k : _rigid)
  {
    place(k, u);
    const bodies::Body& body = _bodies.body(k.body);
    const int n = static_cast<int>(body.nodes.size());
    Eigen::VectorXd vb(2 * n), fb(2 * n);
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < 2; ++c)
      {
        vb[2 * i + c] = v[2 * body.nodes[i] + c];
        fb[2 * i + c] = f_ext[2 * body.nodes[i] + c];
      }
    const Eigen::VectorXd Mv = bodies::symmetric_product(k.nodal_mass, vb);
    Eigen::Vector3d PtMv = Eigen::Vector3d::Zero(),
                    PtF = Eigen::Vector3d::Zero();
    for (int i = 0; i < n; ++i)
    {
      const Eigen::Matrix<double, 2, 3> P = kinematics(k, i);
      PtMv += P.transpose() * Mv.segment<2>(2 * i);
      PtF += P.transpose() * fb.segment<2>(2 * i);
    }
    k.v_old = k.inverse_mass * PtMv;
    k.v_free = k.v_old + h * (k.inverse_mass * PtF);
    k.v = k.v_old;
    const Eigen::VectorXd field = velocity_field(k.body);
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < 2; ++c)
        v[2 * body.nodes[i] + c] = field[2 * i + c];
  }
}

void RigidBodies::reset_to_free()
{
  for (Body& k : _rigid)
    k.v = k.v_free;
}

void RigidBodies::add_impulse(int b, const Eigen::VectorXd& impulse)
{
  Body& k = _rigid[_index[b]];
  Eigen::Vector3d PtI = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < k.arms.size(); ++i)
    PtI += kinematics(k, static_cast<int>(i)).transpose() *
           impulse.segment<2>(2 * i);
  k.v += k.inverse_mass * PtI;
}

Eigen::VectorXd RigidBodies::velocity_field(int b) const
{
  const Body& k = _rigid[_index[b]];
  Eigen::VectorXd field(2 * k.arms.size());
  for (std::size_t i = 0; i < k.arms.size(); ++i)
    field.segment<2>(2 * i) = kinematics(k, static_cast<int>(i)) * k.v;
  return field;
}

Eigen::Vector2d RigidBodies::free_velocity(int b, std::int32_t node) const
{
  const Body& k = _rigid[_index[b]];
  return kinematics(k, node) * k.v_free;
}

Eigen::Matrix2d RigidBodies::compliance(int b, std::int32_t i,
                                        std::int32_t j) const
{
  const Body& k = _rigid[_index[b]];
  return kinematics(k, i) * k.inverse_mass * kinematics(k, j).transpose();
}

void RigidBodies::displace(std::span<double> u, double h, double theta) const
{
  const std::span<const double> X = _bodies.reference_coordinates();
  for (const Body& k : _rigid)
  {
    const Eigen::Vector3d d = h * (theta * k.v + (1 - theta) * k.v_old);
    const Eigen::Rotation2Dd R(d[2]);
    const bodies::Body& body = _bodies.body(k.body);
    for (std::size_t i = 0; i < body.nodes.size(); ++i)
    {
      const std::int32_t g = body.nodes[i];
      const Eigen::Vector2d x = k.centre + d.head<2>() + R * k.arms[i];
      u[2 * g] = x.x() - X[2 * g];
      u[2 * g + 1] = x.y() - X[2 * g + 1];
    }
  }
}

void RigidBodies::set_velocities(std::span<const double> u,
                                 std::span<double> v) const
{
  for (const Body& start : _rigid)
  {
    Body k = start;
    place(k, u);
    const bodies::Body& body = _bodies.body(k.body);
    for (std::size_t i = 0; i < body.nodes.size(); ++i)
    {
      const Eigen::Vector2d vi = kinematics(k, static_cast<int>(i)) * k.v;
      v[2 * body.nodes[i]] = vi.x();
      v[2 * body.nodes[i] + 1] = vi.y();
    }
  }
}

void RigidBodies::zero(std::span<double> f) const
{
  for (const Body& k : _rigid)
    for (const std::int32_t g : _bodies.body(k.body).nodes)
      f[2 * g] = f[2 * g + 1] = 0;
}

} // namespace softpack::dynamics
