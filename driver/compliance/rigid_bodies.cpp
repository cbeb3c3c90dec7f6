#include "rigid_bodies.h"

#include <Eigen/Geometry>
#include <cmath>

namespace softpack::dynamics
{

namespace
{
std::variant<RigidBodySet<2>, RigidBodySet<3>>
rigid_set(const bodies::BodySet& bodies, const EffectiveStiffness& kbar)
{
  if (bodies.dim() == 3)
    return RigidBodySet<3>(bodies, kbar);
  return RigidBodySet<2>(bodies, kbar);
}

/// The rotation of the rigid motion d (its angle in 2D; its rotation
/// vector in 3D, Rodrigues')
Eigen::Rotation2Dd rotation(const Eigen::Vector3d& d)
{
  return Eigen::Rotation2Dd(d[2]);
}

Eigen::Matrix3d rotation(const Eigen::Matrix<double, 6, 1>& d)
{
  const Eigen::Vector3d theta = d.tail<3>();
  const double angle = theta.norm();
  if (angle == 0)
    return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, theta / angle).toRotationMatrix();
}

/// The rotation over a step of a body of mass matrix M (about its centre)
/// whose momenta are M d / h: by the explicit midpoint rule, the rotation
/// vector of the momenta on the body turned by half of d (a body's Mr turns
/// as T Mr T^T, T = diag(R, R)), so that an asymmetric top's orientation
/// errs at second order in h. 2D: d's angle.
Eigen::Rotation2Dd step_rotation(const Eigen::Vector3d& d,
                                 const Eigen::Matrix3d&)
{
  return rotation(d);
}

Eigen::Matrix3d step_rotation(const Eigen::Matrix<double, 6, 1>& d,
                              const Eigen::Matrix<double, 6, 6>& M)
{
  using Matrix6d = Eigen::Matrix<double, 6, 6>;
  const Eigen::Matrix3d half = rotation(Eigen::Matrix<double, 6, 1>(0.5 * d));
  Matrix6d T = Matrix6d::Zero();
  T.topLeftCorner<3, 3>() = half;
  T.bottomRightCorner<3, 3>() = half;
  const Matrix6d M_half = T * M * T.transpose();
  return rotation(Eigen::Matrix<double, 6, 1>(M_half.inverse() * (M * d)));
}
} // namespace

RigidBodies::RigidBodies(const bodies::BodySet& bodies,
                         const EffectiveStiffness& kbar)
    : _set(rigid_set(bodies, kbar))
{
}

template <int D>
RigidBodySet<D>::RigidBodySet(const bodies::BodySet& bodies,
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
    k.mass = rigid_mass(k);
    k.inverse_mass = k.mass.inverse();
    _index[b] = static_cast<int>(_rigid.size());
    _rigid.push_back(std::move(k));
  }
}

template <int D>
void RigidBodySet<D>::place(Body& k, std::span<const double> u) const
{
  const bodies::Body& body = _bodies.body(k.body);
  const Eigen::VectorXd& m = _bodies.lumped_mass()[k.body];
  const std::span<const double> X = _bodies.reference_coordinates();
  const std::size_t n = body.nodes.size();
  std::vector<Point> x(n);
  Point moment = Point::Zero();
  double total = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::int32_t g = body.nodes[i];
    for (int c = 0; c < D; ++c)
      x[i][c] = X[D * g + c] + u[D * g + c];
    moment += m[D * i] * x[i];
    total += m[D * i];
  }
  k.centre = moment / total;
  k.arms.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    k.arms[i] = x[i] - k.centre;
}

template <int D>
typename RigidBodySet<D>::Mass RigidBodySet<D>::rigid_mass(const Body& k) const
{
  const int n = static_cast<int>(k.arms.size());
  Eigen::MatrixXd P(D * n, N);
  for (int i = 0; i < n; ++i)
    P.middleRows<D>(D * i) = kinematics(k, i);
  return P.transpose() *
         (k.nodal_mass.template selfadjointView<Eigen::Lower>() * P);
}

template <int D>
typename RigidBodySet<D>::Kinematics RigidBodySet<D>::kinematics(const Body& k,
                                                                 int node) const
{
  const Point& r = k.arms[node];
  Kinematics P;
  if constexpr (D == 2)
    P << 1, 0, -r.y(), 0, 1, r.x();
  else                              // v + omega x r = v - [r]x omega
    P << 1, 0, 0, 0, r.z(), -r.y(), //
        0, 1, 0, -r.z(), 0, r.x(),  //
        0, 0, 1, r.y(), -r.x(), 0;
  return P;
}

template <int D>
void RigidBodySet<D>::start_step(std::span<const double> u, std::span<double> v,
                                 std::span<const double> f_ext, double h)
{
  for (Body& k : _rigid)
  {
    place(k, u);
    if constexpr (D == 3) // the inertia turned with the body
    {
      k.mass = rigid_mass(k);
      k.inverse_mass = k.mass.inverse();
    }
    const bodies::Body& body = _bodies.body(k.body);
    const int n = static_cast<int>(body.nodes.size());
    Eigen::VectorXd vb(D * n), fb(D * n);
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < D; ++c)
      {
        vb[D * i + c] = v[D * body.nodes[i] + c];
        fb[D * i + c] = f_ext[D * body.nodes[i] + c];
      }
    const Eigen::VectorXd Mv = bodies::symmetric_product(k.nodal_mass, vb);
    Velocity PtMv = Velocity::Zero(), PtF = Velocity::Zero();
    for (int i = 0; i < n; ++i)
    {
      const Kinematics P = kinematics(k, i);
      PtMv += P.transpose() * Mv.template segment<D>(D * i);
      PtF += P.transpose() * fb.template segment<D>(D * i);
    }
    k.v_old = k.inverse_mass * PtMv;
    k.v_free = k.v_old + h * (k.inverse_mass * PtF);
    k.v = k.v_old;
    const Eigen::VectorXd field = velocity_field(k.body);
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < D; ++c)
        v[D * body.nodes[i] + c] = field[D * i + c];
  }
}

template <int D> void RigidBodySet<D>::reset_to_free()
{
  for (Body& k : _rigid)
    k.v = k.v_free;
}

template <int D>
void RigidBodySet<D>::add_impulse(int b, const Eigen::VectorXd& impulse)
{
  Body& k = _rigid[_index[b]];
  Velocity PtI = Velocity::Zero();
  for (std::size_t i = 0; i < k.arms.size(); ++i)
    PtI += kinematics(k, static_cast<int>(i)).transpose() *
           impulse.template segment<D>(D * i);
  k.v += k.inverse_mass * PtI;
}

template <int D> Eigen::VectorXd RigidBodySet<D>::velocity_field(int b) const
{
  const Body& k = _rigid[_index[b]];
  Eigen::VectorXd field(D * k.arms.size());
  for (std::size_t i = 0; i < k.arms.size(); ++i)
    field.template segment<D>(D * i) = kinematics(k, static_cast<int>(i)) * k.v;
  return field;
}

template <int D>
typename RigidBodySet<D>::Point
RigidBodySet<D>::free_velocity(int b, std::int32_t node) const
{
  const Body& k = _rigid[_index[b]];
  return kinematics(k, node) * k.v_free;
}

template <int D>
typename RigidBodySet<D>::Compliance
RigidBodySet<D>::compliance(int b, std::int32_t i, std::int32_t j) const
{
  const Body& k = _rigid[_index[b]];
  return kinematics(k, i) * k.inverse_mass * kinematics(k, j).transpose();
}

template <int D>
void RigidBodySet<D>::displace(std::span<double> u, double h,
                               double theta) const
{
  const std::span<const double> X = _bodies.reference_coordinates();
  for (const Body& k : _rigid)
  {
    const Velocity d = h * (theta * k.v + (1 - theta) * k.v_old);
    const auto R = step_rotation(d, k.mass);
    const bodies::Body& body = _bodies.body(k.body);
    for (std::size_t i = 0; i < body.nodes.size(); ++i)
    {
      const std::int32_t g = body.nodes[i];
      const Point x = k.centre + d.template head<D>() + R * k.arms[i];
      for (int c = 0; c < D; ++c)
        u[D * g + c] = x[c] - X[D * g + c];
    }
  }
}

template <int D>
void RigidBodySet<D>::set_velocities(std::span<const double> u,
                                     std::span<double> v) const
{
  for (const Body& start : _rigid)
  {
    Body k = start;
    place(k, u);
    if constexpr (D == 3) // the momenta of the start, on the turned body
      k.v = rigid_mass(k).inverse() * (start.mass * start.v);
    const bodies::Body& body = _bodies.body(k.body);
    for (std::size_t i = 0; i < body.nodes.size(); ++i)
    {
      const Point vi = kinematics(k, static_cast<int>(i)) * k.v;
      for (int c = 0; c < D; ++c)
        v[D * body.nodes[i] + c] = vi[c];
    }
  }
}

template <int D> void RigidBodySet<D>::zero(std::span<double> f) const
{
  for (const Body& k : _rigid)
    for (const std::int32_t g : _bodies.body(k.body).nodes)
      for (int c = 0; c < D; ++c)
        f[D * g + c] = 0;
}

template class RigidBodySet<2>;
template class RigidBodySet<3>;

} // namespace softpack::dynamics
