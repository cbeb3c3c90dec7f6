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
    ServoStep s{w, imposed_force(walls, w), wall.normal_velocity(), 0};
    s.v_free = s.v_old + h * s.force / wall.mass;
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
    const WallCoupling& c = servo.couplings[k];
    // The wall receives the opposite of its contacts' impulses.
    double impulse = 0;
    for (std::size_t i = 0; i < c.contacts.size(); ++i)
      impulse -= c.g[i].dot(
          Eigen::Vector2d(R[2 * c.contacts[i]], R[2 * c.contacts[i] + 1]));
    s.v_new = s.v_free + c.inverse_mass * impulse;
    s.v_mid = theta * s.v_new + (1 - theta) * s.v_old;
    Wall& wall = walls[s.wall];
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
    const Wall& wall = walls[s.wall];
    for (const std::int32_t a : servo.couplings[k].contacts)
      H.set_wall_velocity(a, along(wall, s.v_mid));
    energy.wall_work += h * s.force * s.v_mid;
    const double dv = s.v_new - s.v_old;
    energy.numerical += (theta - 0.5) * wall.mass * dv * dv;
  }
}

} // namespace softpack::dynamics
