#include "servo_cell.h"

#include <cmath>

namespace softpack::dynamics
{
namespace
{
/// Each contact's antagonist velocity with every controlled component's
/// rate changed from V- by `change` of its step: the cell's rate at the
/// image, (dh/dt)- k, less the affine change at the branch vector
void set_antagonist_velocities(const ServoWalls& servo,
                               const PeriodicCell& cell,
                               const std::vector<Contact>& contacts,
                               ContactOperator& H, double ServoStep::*rate)
{
  for (std::size_t a = 0; a < contacts.size(); ++a)
  {
    if (contacts[a].antagonist_body < 0)
      continue;
    std::array<double, 2> w = cell.rate(contacts[a].image);
    for (const ServoStep& s : servo.cell)
    {
      const int i = cell.servo[s.index].axis;
      if (i == CellServo::mean)
      {
        const std::array<double, 2> l = servo.mode_branch(a);
        for (int d = 0; d < 2; ++d)
          w[d] -= (s.*rate - s.v_old) * l[d];
      }
      else
        w[cell.servo[s.index].row()] -=
            (s.*rate - s.v_old) *
            servo.cell_branch[a][cell.servo[s.index].column()];
    }
    H.set_wall_velocity(a, w);
  }
}
} // namespace

void start_servo_cell(const PeriodicCell& cell,
                      const std::vector<Contact>& contacts,
                      const std::vector<std::array<double, 2>>& centroids,
                      ContactOperator& H, double h, double theta, double time,
                      ServoWalls& servo)
{
  if (cell.servo.empty())
    return;
  for (const std::array<double, 2>& c : centroids)
    servo.cell_coordinates.push_back(cell.fractional(c));
  servo.cell_branch.assign(contacts.size(), {0, 0});
  for (std::size_t a = 0; a < contacts.size(); ++a)
  {
    const Contact& c = contacts[a];
    if (c.antagonist_body < 0)
      continue;
    // h^-1 l = s_candidate - s_antagonist - k
    for (int d = 0; d < 2; ++d)
      servo.cell_branch[a][d] = servo.cell_coordinates[c.candidate_body][d] -
                                servo.cell_coordinates[c.antagonist_body][d] -
                                c.image[d];
  }
  servo.cell_mode = isotropic_mode(cell);
  for (std::size_t k = 0; k < cell.servo.size(); ++k)
  {
    const CellServo& c = cell.servo[k];
    servo.cell.push_back(
        ServoStep::start_damped(k, cell.servo_force(c, time + h / 2), c.mass,
                                c.damping, cell.servo_velocity(c), h, theta));
    WallCoupling coupling;
    coupling.inverse_mass = 1 / servo.cell.back().inertia;
    for (std::size_t a = 0; a < contacts.size(); ++a)
      if (contacts[a].antagonist_body >= 0)
      {
        coupling.contacts.push_back(static_cast<std::int32_t>(a));
        if (c.axis == CellServo::mean)
        {
          // frame^T (h / sqrt(det h)) h^-1 l = frame^T l / sqrt(det h)
          const std::array<double, 2> l = servo.mode_branch(a);
          coupling.g.push_back(-(l[0] * H.frame(a).row(0).transpose() +
                                 l[1] * H.frame(a).row(1).transpose()));
        }
        else
          coupling.g.push_back(-servo.cell_branch[a][c.column()] *
                               H.frame(a).row(c.row()).transpose());
      }
    servo.couplings.push_back(std::move(coupling));
  }
  set_antagonist_velocities(servo, cell, contacts, H, &ServoStep::v_free);
}

void finish_servo_cell(ServoWalls& servo, std::span<const double> R,
                       double theta)
{
  for (std::size_t k = 0; k < servo.cell.size(); ++k)
    servo.cell[k].finish(servo.cell_coupling(k), R, theta);
}

void account_servo_cell(const ServoWalls& servo, const PeriodicCell& cell,
                        const std::vector<Contact>& contacts,
                        ContactOperator& H, std::span<const double> R,
                        EnergyBalance& energy, double h, double theta)
{
  if (servo.cell.empty())
    return;
  set_antagonist_velocities(servo, cell, contacts, H, &ServoStep::v_mid);
  for (std::size_t k = 0; k < servo.cell.size(); ++k)
  {
    const ServoStep& s = servo.cell[k];
    energy.cell_work +=
        s.account(energy, h, theta) - s.transmitted(servo.cell_coupling(k), R);
  }
}

double cell_kinetic_energy(const PeriodicCell& cell)
{
  double e = 0;
  for (const CellServo& s : cell.servo)
    e += 0.5 * s.mass * cell.servo_velocity(s) * cell.servo_velocity(s);
  return e;
}

std::array<double, 4> isotropic_mode(const PeriodicCell& cell)
{
  const double scale = 1 / std::sqrt(cell.area());
  return {cell.a1[0] * scale, cell.a1[1] * scale, cell.a2[0] * scale,
          cell.a2[1] * scale};
}

} // namespace softpack::dynamics
