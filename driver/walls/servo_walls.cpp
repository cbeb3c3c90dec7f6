#include "servo_walls.h"

#include <tuple>

namespace softpack::dynamics
{
namespace
{
/// A wall's dimension: 2 (Wall, a line) or 3 (Wall3D, a plane)
template <class W>
constexpr int dim_of = static_cast<int>(std::tuple_size_v<decltype(W::point)>);

/// speed x the wall's normal
template <class W> auto along(const W& wall, double speed)
{
  decltype(wall.normal) v{};
  for (std::size_t i = 0; i < v.size(); ++i)
    v[i] = speed * wall.normal[i];
  return v;
}

/// Contact a's impulse in its frame (D entries of R)
template <int D>
Eigen::Matrix<double, D, 1> impulse_of(std::span<const double> R,
                                       std::int32_t a)
{
  Eigen::Matrix<double, D, 1> r;
  for (int i = 0; i < D; ++i)
    r[i] = R[D * a + i];
  return r;
}

/// The step's couplings of the servo walls of dimension D
template <int D> auto& couplings(ServoWalls& servo)
{
  if constexpr (D == 2)
    return servo.couplings;
  else
    return servo.couplings_3d;
}
template <int D> const auto& couplings(const ServoWalls& servo)
{
  return couplings<D>(const_cast<ServoWalls&>(servo));
}

template <class W, class C>
ServoWalls start_walls(const std::vector<W>& walls,
                       const std::vector<C>& contacts, ContactOperator& H,
                       double h)
{
  constexpr int D = dim_of<W>;
  ServoWalls out;
  for (std::size_t w = 0; w < walls.size(); ++w)
  {
    const W& wall = walls[w];
    if (!wall.servo())
      continue;
    const ServoStep s = ServoStep::start(w, imposed_force(walls, w), wall.mass,
                                         wall.normal_velocity(), h);
    WallCouplingD<D> coupling;
    coupling.inverse_mass = 1 / wall.mass;
    Eigen::Matrix<double, D, 1> n;
    for (int i = 0; i < D; ++i)
      n[i] = wall.normal[i];
    for (std::size_t a = 0; a < contacts.size(); ++a)
      if (contacts[a].wall == static_cast<int>(w))
      {
        coupling.contacts.push_back(static_cast<std::int32_t>(a));
        coupling.g.push_back(H.frame<D>(a).transpose() * n);
        H.set_wall_velocity(a, along(wall, s.v_free));
      }
    out.steps.push_back(s);
    couplings<D>(out).push_back(std::move(coupling));
  }
  return out;
}

template <class W>
void finish_walls(ServoWalls& servo, std::vector<W>& walls,
                  std::span<const double> R, double h, double theta)
{
  constexpr int D = dim_of<W>;
  for (std::size_t k = 0; k < servo.steps.size(); ++k)
  {
    ServoStep& s = servo.steps[k];
    s.finish(couplings<D>(servo)[k], R, theta);
    W& wall = walls[s.index];
    for (int d = 0; d < D; ++d)
      wall.point[d] += h * s.v_mid * wall.normal[d];
    wall.velocity = along(wall, s.v_new);
  }
}

template <class W>
void account_walls(const ServoWalls& servo, const std::vector<W>& walls,
                   ContactOperator& H, EnergyBalance& energy, double h,
                   double theta)
{
  constexpr int D = dim_of<W>;
  for (std::size_t k = 0; k < servo.steps.size(); ++k)
  {
    const ServoStep& s = servo.steps[k];
    const W& wall = walls[s.index];
    for (const std::int32_t a : couplings<D>(servo)[k].contacts)
      H.set_wall_velocity(a, along(wall, s.v_mid));
    energy.wall_work += s.account(energy, h, theta);
  }
}
} // namespace

ServoStep ServoStep::start(std::size_t index, double force, double mass,
                           double v_old, double h)
{
  ServoStep s{index, force, mass, v_old};
  s.v_free = s.v_old + h * s.force / mass;
  return s;
}

ServoStep ServoStep::start_damped(std::size_t index, double force, double mass,
                                  double damping, double v_old, double h,
                                  double theta)
{
  ServoStep s{index, force, mass, v_old};
  s.damping = damping;
  s.inertia = mass + theta * h * damping;
  s.v_free = s.v_old + h * (force - damping * v_old) / s.inertia;
  return s;
}

template <int D>
void ServoStep::finish(const WallCouplingD<D>& c, std::span<const double> R,
                       double theta)
{
  // The unknown receives the opposite of its contacts' impulses.
  double impulse = 0;
  for (std::size_t i = 0; i < c.contacts.size(); ++i)
    impulse -= c.g[i].dot(impulse_of<D>(R, c.contacts[i]));
  v_new = v_free + c.inverse_mass * impulse;
  v_mid = theta * v_new + (1 - theta) * v_old;
}

template <int D>
double ServoStep::transmitted(const WallCouplingD<D>& c,
                              std::span<const double> R) const
{
  double impulse = 0;
  for (std::size_t i = 0; i < c.contacts.size(); ++i)
    impulse += c.g[i].dot(impulse_of<D>(R, c.contacts[i]));
  return v_mid * impulse;
}

template void ServoStep::finish<2>(const WallCouplingD<2>&,
                                   std::span<const double>, double);
template void ServoStep::finish<3>(const WallCouplingD<3>&,
                                   std::span<const double>, double);
template double ServoStep::transmitted<2>(const WallCouplingD<2>&,
                                          std::span<const double>) const;
template double ServoStep::transmitted<3>(const WallCouplingD<3>&,
                                          std::span<const double>) const;

double ServoStep::account(EnergyBalance& energy, double h, double theta) const
{
  const double dv = v_new - v_old;
  energy.numerical += (theta - 0.5) * mass * dv * dv;
  energy.damping += h * damping * v_mid * v_mid;
  return h * force * v_mid;
}

ServoWalls start_servo_walls(const std::vector<Wall>& walls,
                             const std::vector<Contact>& contacts,
                             ContactOperator& H, double h)
{
  return start_walls(walls, contacts, H, h);
}

ServoWalls start_servo_walls(const std::vector<Wall3D>& walls,
                             const std::vector<Contact3D>& contacts,
                             ContactOperator& H, double h)
{
  return start_walls(walls, contacts, H, h);
}

void finish_servo_walls(ServoWalls& servo, std::vector<Wall>& walls,
                        std::span<const double> R, double h, double theta)
{
  finish_walls(servo, walls, R, h, theta);
}

void finish_servo_walls(ServoWalls& servo, std::vector<Wall3D>& walls,
                        std::span<const double> R, double h, double theta)
{
  finish_walls(servo, walls, R, h, theta);
}

void account_servo_walls(const ServoWalls& servo,
                         const std::vector<Wall>& walls, ContactOperator& H,
                         EnergyBalance& energy, double h, double theta)
{
  account_walls(servo, walls, H, energy, h, theta);
}

void account_servo_walls(const ServoWalls& servo,
                         const std::vector<Wall3D>& walls, ContactOperator& H,
                         EnergyBalance& energy, double h, double theta)
{
  account_walls(servo, walls, H, energy, h, theta);
}

} // namespace softpack::dynamics
