// Rigid 3D bodies (six degrees of freedom, dynamics/rigid_bodies.h) in the
// same step as the soft ones. References: Euler's equations of the
// torque-free top (integrated here by RK4 with the mesh's inertia), the
// slide-to-roll transition of a ball on a rough floor (the angular
// momentum about the contact point is conserved), and the momentum and
// energy balances of a rigid ball striking a soft one.
#include "../dynamics/scheme_options.h"
#include "sphere_scenes.h"
#include <Eigen/Geometry>
#include <bodies/body_forces.h>
#include <cmath>
#include <gtest/gtest.h>

using namespace softpack;

namespace
{
/// The bodies of a sphere_meshes.py mesh; rigid[b]: body b is rigid
bodies::BodySet bodies_of(const std::string& name, std::vector<int> rigid)
{
  const std::map<std::string, double> p = {
      {"shear_modulus", test::sphere_mu}, {"lame_lambda", test::sphere_lambda}};
  const forms::MaterialForms& law = forms::find_material("neo_hookean");
  const std::filesystem::path file =
      std::filesystem::path(SOFTPACK_SPHERE_MESHES) / (name + ".xdmf");
  return bodies::BodySet(bodies::read_body_mesh(MPI_COMM_SELF, file),
                         {{&law, p, test::sphere_rho, false, "soft"},
                          {&law, p, test::sphere_rho, true, "rigid"}},
                         std::move(rigid));
}

Eigen::Vector3d node(std::span<const double> x, std::int32_t g)
{
  return {x[3 * g], x[3 * g + 1], x[3 * g + 2]};
}

/// Body b's node positions X + u
std::vector<Eigen::Vector3d> positions(const bodies::BodySet& set, int b)
{
  const auto X = set.reference_coordinates();
  const auto u = set.displacement();
  std::vector<Eigen::Vector3d> x;
  for (const std::int32_t g : set.body(b).nodes)
    x.push_back(node(X, g) + node(u, g));
  return x;
}

/// Body b's mass m, mass centre c (lumped masses) and consistent-mass
/// momenta about the origin: p = sum (M v)_i, L = sum x_i x (M v)_i
struct Momenta
{
  double mass = 0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero(), p = Eigen::Vector3d::Zero(),
                  L = Eigen::Vector3d::Zero();
};
Momenta momenta(const bodies::BodySet& set, int b, std::span<const double> v)
{
  const bodies::Body& body = set.body(b);
  const std::vector<Eigen::Vector3d> x = positions(set, b);
  Eigen::VectorXd vb(body.num_dofs());
  for (std::size_t i = 0; i < x.size(); ++i)
    vb.segment<3>(3 * i) = node(v, body.nodes[i]);
  const Eigen::VectorXd Mv =
      bodies::symmetric_product(set.consistent_mass()[b], vb);
  const Eigen::VectorXd& m = set.lumped_mass()[b];
  Momenta k;
  for (std::size_t i = 0; i < x.size(); ++i)
  {
    k.mass += m[3 * i];
    k.centre += m[3 * i] * x[i];
    k.p += Mv.segment<3>(3 * i);
    k.L += x[i].cross(Mv.segment<3>(3 * i));
  }
  k.centre /= k.mass;
  return k;
}

/// The consistent-mass inertia tensor of body b about its mass centre at
/// the reference configuration: column k is sum_i r_i x (M (e_k x r))_i
Eigen::Matrix3d inertia(const bodies::BodySet& set, int b)
{
  const std::vector<Eigen::Vector3d> x = positions(set, b);
  const Momenta k0 = momenta(set, b, std::vector<double>(set.num_dofs()));
  Eigen::Matrix3d I;
  for (int axis = 0; axis < 3; ++axis)
  {
    Eigen::VectorXd vb(3 * x.size());
    for (std::size_t i = 0; i < x.size(); ++i)
      vb.segment<3>(3 * i) =
          Eigen::Vector3d::Unit(axis).cross(x[i] - k0.centre);
    const Eigen::VectorXd Mv =
        bodies::symmetric_product(set.consistent_mass()[b], vb);
    Eigen::Vector3d L = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < x.size(); ++i)
      L += (x[i] - k0.centre).cross(Mv.segment<3>(3 * i));
    I.col(axis) = L;
  }
  return I;
}

/// Largest relative change of the distances between body b's nodes
double distance_change(const bodies::BodySet& set, int b)
{
  const auto X = set.reference_coordinates();
  const std::vector<Eigen::Vector3d> x = positions(set, b);
  const bodies::Body& body = set.body(b);
  double worst = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = i + 1; j < x.size(); ++j)
    {
      const double d0 =
          (node(X, body.nodes[i]) - node(X, body.nodes[j])).norm();
      worst = std::max(worst, std::abs((x[i] - x[j]).norm() - d0) / d0);
    }
  return worst;
}

dynamics::MoreauJeanOptions options(double h, double speed)
{
  dynamics::MoreauJeanOptions o = test::exact_options(h, speed);
  o.time.mass = "consistent";
  o.time.newton_tolerance = 1e-10;
  o.contact.nlgs_tolerance = 1e-12;
  return o;
}

/// The torque-free top: the rotation R(t) and body-frame omega of Euler's
/// equations I w' = (I w) x w, R' = R [w]x, by RK4 in n steps
Eigen::Matrix3d euler_top(const Eigen::Matrix3d& I, Eigen::Vector3d w, double t,
                          int n)
{
  using State = Eigen::Matrix<double, 12, 1>;
  const Eigen::Matrix3d Iinv = I.inverse();
  auto rate = [&](const State& s)
  {
    const Eigen::Map<const Eigen::Matrix3d> R(s.data());
    const Eigen::Vector3d w = s.tail<3>();
    Eigen::Matrix3d W;
    W << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
    State d;
    Eigen::Map<Eigen::Matrix3d>(d.data()) = R * W;
    d.tail<3>() = Iinv * (I * w).cross(w);
    return d;
  };
  State s;
  Eigen::Map<Eigen::Matrix3d>(s.data()) = Eigen::Matrix3d::Identity();
  s.tail<3>() = w;
  const double dt = t / n;
  for (int k = 0; k < n; ++k)
  {
    const State k1 = rate(s), k2 = rate(s + dt / 2 * k1),
                k3 = rate(s + dt / 2 * k2), k4 = rate(s + dt * k3);
    s += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  return Eigen::Map<const Eigen::Matrix3d>(s.data());
}

struct Top
{
  double momentum = 0, angular = 0, distances = 0, centre = 0;
  double orientation = 0; ///< max |r_i - R_exact r_i0| / max |r_i0|
  double kinetic = 0;     ///< |K / K0 - 1|
};

/// The rigid brick spun about no principal axis for 0.1 s at step h
Top spin_brick(double h)
{
  bodies::BodySet set = bodies_of("brick", {1});
  const Eigen::Vector3d V(0.3, -0.1, 0.2), w(20, 40, 5);
  dynamics::MoreauJean scheme(set, options(h, 1.0),
                              std::vector<dynamics::Wall3D>{});
  const auto X = set.reference_coordinates();
  std::vector<double> v(X.size());
  for (std::size_t n = 0; n < X.size() / 3; ++n)
  {
    const Eigen::Vector3d vn = V + w.cross(node(X, n));
    std::copy(vn.data(), vn.data() + 3, v.begin() + 3 * n);
  }
  scheme.set_initial_velocity(v);
  const Momenta k0 = momenta(set, 0, scheme.velocity());
  const Eigen::Matrix3d I = inertia(set, 0);
  const double kinetic0 = scheme.energy().kinetic;
  const double t = 0.1;
  const int steps = static_cast<int>(std::lround(t / h));
  Top top;
  for (int s = 0; s < steps; ++s)
  {
    EXPECT_TRUE(scheme.step().newton_converged) << "step " << s;
    const Momenta k = momenta(set, 0, scheme.velocity());
    top.momentum = std::max(top.momentum, (k.p - k0.p).norm() / k0.p.norm());
    top.angular = std::max(top.angular, (k.L - k0.L).norm() / k0.L.norm());
  }
  top.distances = distance_change(set, 0);
  const Momenta k = momenta(set, 0, scheme.velocity());
  top.centre = (k.centre - (k0.centre + V * scheme.time())).norm();
  // The body frame is the reference frame: r_i(t) = R(t) r_i(0).
  const Eigen::Matrix3d R = euler_top(I, w, scheme.time(), 20000);
  const std::vector<Eigen::Vector3d> x = positions(set, 0);
  double size = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
  {
    const Eigen::Vector3d r0 = node(X, set.body(0).nodes[i]) - k0.centre;
    size = std::max(size, r0.norm());
    top.orientation =
        std::max(top.orientation, (x[i] - k.centre - R * r0).norm());
  }
  top.orientation /= size;
  top.kinetic = std::abs(scheme.energy().kinetic / kinetic0 - 1);
  return top;
}
} // namespace

TEST(RigidBodies3D, FreeAsymmetricTopKeepsItsMomentaAndFollowsEuler)
{
  const Top a = spin_brick(1e-3), b = spin_brick(5e-4);
  for (const Top& top : {a, b})
  {
    EXPECT_LT(top.momentum, 1e-12);
    EXPECT_LT(top.angular, 1e-12);
    EXPECT_LT(top.distances, 1e-12);
    EXPECT_LT(top.centre, 1e-14);
  }
  std::cout << "orientation error " << a.orientation << " -> " << b.orientation
            << ", kinetic energy drift " << a.kinetic << " -> " << b.kinetic
            << "\n";
  RecordProperty("orientation_h", std::to_string(a.orientation));
  RecordProperty("orientation_h2", std::to_string(b.orientation));
  RecordProperty("kinetic_h", std::to_string(a.kinetic));
  RecordProperty("kinetic_h2", std::to_string(b.kinetic));
  // Second order in h (the rotation's midpoint rule): halving the step
  // divides both errors by 4. Measured 2026-12-05: orientation 1.43e-4 ->
  // 3.57e-5 of the size, kinetic energy 7.8e-6 -> 2.0e-6 (the first-order
  // update of omega alone: 2.8e-2 -> 1.4e-2, 3.6e-3 -> 1.8e-3).
  EXPECT_NEAR(a.orientation / b.orientation, 4.0, 0.4);
  EXPECT_NEAR(a.kinetic / b.kinetic, 4.0, 0.4);
  EXPECT_LT(a.orientation, 3e-4);
  EXPECT_LT(a.kinetic, 2e-5);
}

TEST(RigidBodies3D, BallSlidingOnARoughFloorRollsAtTheSpeedOfItsMomentum)
{
  // The graded sphere (a node at each pole) set on the floor by its south
  // pole, launched at v0 along x without spin, under gravity. Friction
  // slows it and spins it up; the angular momentum about the contact point
  // is kept (friction and the normal reaction act there, the weight along
  // the vertical through it), so it rolls from t* = v0 / (mu g (1 + 1/k))
  // at v0 / (1 + k), k = I_y / (m h^2), h the height of the mass centre.
  // The ball turns by ~v0 t* / (2 h) before t*, moving the pole node ahead
  // of the centre: the weight's moment about it then changes the momentum
  // by ~g (v0 t*)^2 / (2 v0 h^2) (2e-4 of it at v0 = 2 cm/s; v0^2).
  bodies::BodySet set = bodies_of("hertz", {1});
  const auto X = set.reference_coordinates();
  double bottom = 0;
  for (std::size_t n = 0; n < X.size() / 3; ++n)
    bottom = std::min(bottom, X[3 * n + 2]);
  const double v0 = 0.02, mu = 0.5, g = 9.81, h = 2e-5;
  dynamics::MoreauJeanOptions o = options(h, v0);
  o.contact.friction = mu;
  dynamics::MoreauJean scheme(
      set, o, std::vector<dynamics::Wall3D>{{"floor", {0, 0, bottom}}});
  scheme.set_external_force(bodies::weight(set, {0, 0, -g}));
  std::vector<double> v(X.size(), 0.0);
  for (std::size_t n = 0; n < X.size() / 3; ++n)
    v[3 * n] = v0;
  scheme.set_initial_velocity(v);
  const Momenta k0 = momenta(set, 0, v);
  const double height = k0.centre.z() - bottom;
  const Eigen::Matrix3d I = inertia(set, 0);
  const double k = I(1, 1) / (k0.mass * height * height);
  const double t_roll = v0 / (mu * g * (1 + 1 / k)), v_roll = v0 / (1 + k);
  // The first step at which the contact point's slip (the centre's speed
  // less omega_y h) has stopped.
  double t_stick = -1;
  Eigen::Vector3d V_stick;
  for (int s = 0; scheme.time() < 1.5 * t_roll; ++s)
  {
    ASSERT_TRUE(scheme.step().newton_converged) << "step " << s;
    const Momenta m = momenta(set, 0, scheme.velocity());
    const Eigen::Vector3d V = m.p / m.mass;
    // The rotation over the test is small: I about c is the start's.
    const double omega_y = (I.inverse() * (m.L - m.centre.cross(m.p)))(1);
    if (t_stick < 0 && V.x() - omega_y * height < 1e-3 * v0)
    {
      t_stick = scheme.time();
      V_stick = V;
    }
  }
  std::cout << "k " << k << " (2/5 for a ball), rolls at " << V_stick.x()
            << " m/s against " << v_roll << ", from t = " << t_stick
            << " s against " << t_roll << "\n";
  RecordProperty("v_over_v_roll", std::to_string(V_stick.x() / v_roll));
  EXPECT_NEAR(k, 0.4, 0.02);
  EXPECT_NEAR(V_stick.x() / v_roll, 1.0, 1e-3);
  EXPECT_NEAR(t_stick, t_roll, h);
  EXPECT_LT(distance_change(set, 0), 1e-12);
}

TEST(RigidBodies3D, RigidBallStrikingASoftOneKeepsMomentumAndTheBalance)
{
  // The off-axis pair: the left ball rigid, the right one soft, closing at
  // 2 x 0.5 m/s with friction 0.3 (the soft-soft collision of
  // Step3D.OffAxisFrictionalCollisionConservesMomentumAndClosesTheBalance
  // with one body rigid).
  bodies::BodySet set = bodies_of("off_axis", {1, 0});
  const double speed = 0.5;
  dynamics::MoreauJeanOptions o = options(2e-5, speed);
  o.time.newton_tolerance = 1e-9;
  o.contact.nlgs_tolerance = 1e-10;
  o.contact.alert_distance = 2e-4;
  dynamics::MoreauJean scheme(set, o, std::vector<dynamics::Wall3D>{});
  const auto X = set.reference_coordinates();
  std::vector<double> v(X.size(), 0.0);
  for (std::size_t n = 0; n < v.size() / 3; ++n)
    v[3 * n] = X[3 * n] < 0 ? speed : -speed;
  scheme.set_initial_velocity(v);
  const std::array<double, 3> P0 = test::momentum(set, scheme.velocity());
  const double mass = momenta(set, 0, v).mass;
  double momentum = 0, balance = 0;
  int contact_steps = 0;
  for (int s = 0; s < 150; ++s)
  {
    const dynamics::StepReport r = scheme.step();
    ASSERT_TRUE(r.newton_converged && r.nlgs_converged) << "step " << s;
    contact_steps += r.active_contacts > 0;
    const std::array<double, 3> P = test::momentum(set, scheme.velocity());
    for (int i = 0; i < 3; ++i)
      momentum = std::max(momentum, std::abs(P[i] - P0[i]) / (mass * speed));
    const dynamics::EnergyBalance& e = scheme.energy();
    balance = std::max(balance, std::abs(e.residual()) / e.kinetic0);
  }
  const dynamics::EnergyBalance& e = scheme.energy();
  std::cout << "momentum " << momentum << ", balance " << balance
            << ", friction " << e.friction / e.kinetic0 << ", contact steps "
            << contact_steps << "\n";
  RecordProperty("balance", std::to_string(balance));
  EXPECT_GT(contact_steps, 20);
  EXPECT_LT(momentum, 1e-12);
  EXPECT_LT(balance, 1e-4);
  EXPECT_GT(e.friction, 0.0);
  EXPECT_LT(distance_change(set, 0), 1e-12);
  EXPECT_LT(std::abs(set.body_strain_energy()[0]), 1e-10 * e.kinetic0);
}
