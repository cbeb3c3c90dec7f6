#include "servo_walls.h"

namespace softpack::dynamics
{
namespace
{
std::array<double, 2> along(const Wall& wall, double speed)
{
  return {speed * wall.normal[0], speed * wall.normal[1]};
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

void ServoStep::finish(const WallCoupling& c, std::span<const double> R,
                       double theta)
{
  // The unknown receives the opposite of its contacts' impulses.
  double impulse = 0;
  for (std::size_t i = 0; i < c.contacts.size(); ++i)
    impulse -= c.g[i].dot(
        Eigen::Vector2d(R[2 * c.contacts[i]], R[2 * c.contacts[i] + 1]));
  v_new = v_free + c.inverse_mass * impulse;
  v_mid = theta * v_new + (1 - theta) * v_old;
}

double ServoStep::transmitted(const WallCoupling& c,
                              std::span<const double> R) const
{
  double impulse = 0;
  for (std::size_t i = 0; i < c.contacts.size(); ++i)
    impulse += c.g[i].dot(
        Eigen::Vector2d(R[2 * c.contacts[i]], R[2 * c.contacts[i] + 1]));
  return v_mid * impulse;
}

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
  ServoWalls out;
  for (std::size_t w = 0; w < walls.size(); ++w)
  {
    const Wall& wall = walls[w];
    if (!wall.servo())
      continue;
    const ServoStep s = ServoStep::start(w, imposed_force(walls, w), wall.mass,
                                         wall.normal_velocity(), h);
    WallCoupling coupling;
    coupling.inverse_mass = 1 / wall.mass;
    const Eigen::Vector2d n(wall.normal[0], wall.normal[1]);
    for (std::size_t a = 0; a < contacts.size(); ++a)
      if (contacts[a].wall == static_cast<int>(w))
      {
        coupling.contacts.push_back(static_cast<std::int32_t>(a));
        coupling.g.push_back(H.frame(a).transpose() * n);
        H.set_wall_velocity(a, along(wall, s.v_free));
      }
    out.steps.push_back(s);
    out.couplings.push_back(std::move(coupling));
  }
  return out;
}

void finish_servo_walls(ServoWalls& servo, std::vector<Wall>& walls,
                        std::span<const double> R, double h, double theta)
{
  for (std::size_t k = 0; k < servo.steps.size(); ++k)
  {
    ServoStep& s = servo.steps[k];
    s.finish(servo.couplings[k], R, theta);
    Wall& wall = walls[s.index];
    for (int d = 0; d < 2; ++d)
      wall.point[d] += h * s.v_mid * wall.normal[d];
    wall.velocity = along(wall, s.v_new);
  }
}

void account_servo_walls(const ServoWalls& servo,
                         const std::vector<Wall>& walls, ContactOperator& H,
                         EnergyBalance& energy, double h, double theta)
{
  for (std::size_t k = 0; k < servo.steps.size(); ++k)
  {
    const ServoStep& s = servo.steps[k];
    const Wall& wall = walls[s.index];
    for (const std::int32_t a : servo.couplings[k].contacts)
      H.set_wall_velocity(a, along(wall, s.v_mid));
    energy.wall_work += s.account(energy, h, theta);
  }
}

} // namespace softpack::dynamics
