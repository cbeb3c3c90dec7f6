#include "energy_balance.h"

namespace softpack::dynamics
{

double kinetic_energy(const BodyVectors& v, const BodyVectors& Mv,
                      std::span<const int> bodies)
{
  double e = 0;
  for (const int b : bodies)
    e += 0.5 * v[b].dot(Mv[b]);
  return e;
}

void add_stiffness_dissipation(EnergyBalance& energy, double theta,
                               std::span<const double> u_old,
                               std::span<const double> u_new,
                               std::span<const double> f_old,
                               std::span<const double> f_new,
                               std::span<const char> local_nodes, int dim)
{
  if (theta == 0.5)
    return;
  double excess = 0;
  for (std::size_t i = 0; i < u_new.size(); ++i)
    if (local_nodes.empty() || local_nodes[i / dim])
      excess += (u_new[i] - u_old[i]) * (f_new[i] - f_old[i]);
  energy.numerical += (theta - 0.5) * excess;
}

void add_body_terms(EnergyBalance& energy, double h, double theta,
                    const BodyStep& s, std::span<const int> bodies)
{
  const double th = theta;
  for (const int b : bodies)
  {
    energy.damping +=
        h * s.v_mid[b].dot(th * s.Cv_new[b] + (1 - th) * s.Cv_old[b]);
    energy.numerical +=
        (th - 0.5) * (s.v_new[b] - s.v_old[b]).dot(s.Mv_new[b] - s.Mv_old[b]);
    energy.external_work += h * s.v_mid[b].dot(s.f_ext[b]);
  }
}

namespace
{
/// The work on contact a of a velocity-controlled wall, or of the cell's
/// motion on a particle contact: R . U_wall (the antagonist's velocity
/// from the cell's motion is the contact operator's wall velocity)
void add_wall_work(EnergyBalance& energy, const ContactOperator& H,
                   const std::vector<Contact>& contacts,
                   const std::vector<Wall>& walls, std::span<const double> R,
                   std::size_t a)
{
  const double work =
      R[2 * a] * H.wall_velocity(a)[0] + R[2 * a + 1] * H.wall_velocity(a)[1];
  if (contacts[a].wall >= 0 && !walls[contacts[a].wall].servo())
    energy.wall_work += work;
  else if (contacts[a].antagonist_body >= 0)
    // (zero without a cell; in a cell the image's rate, and the affine
    // change of a stress-controlled one, servo_cell.h)
    energy.cell_work += work;
}
} // namespace

void add_contact_terms(EnergyBalance& energy, const ContactOperator& H,
                       const std::vector<Contact>& contacts,
                       const std::vector<Wall>& walls,
                       std::span<const double> R, std::span<const double> U_mid,
                       std::span<const double> cohesion,
                       std::span<const std::int32_t> bonds)
{
  std::size_t next_bond = 0; // bonds are ascending
  for (std::size_t a = 0; a < contacts.size(); ++a)
  {
    if (next_bond < bonds.size() &&
        static_cast<std::size_t>(bonds[next_bond]) == a)
    {
      ++next_bond;
      energy.bond -= R[2 * a] * U_mid[2 * a] + R[2 * a + 1] * U_mid[2 * a + 1];
      add_wall_work(energy, H, contacts, walls, R, a);
      continue;
    }
    energy.friction -= R[2 * a + 1] * U_mid[2 * a + 1];
    const double c = cohesion.empty() ? 0.0 : cohesion[a];
    if (c == 0)
      energy.contact_normal -= R[2 * a] * U_mid[2 * a];
    else
    {
      energy.contact_normal -= (R[2 * a] + c) * U_mid[2 * a];
      energy.cohesion += c * U_mid[2 * a];
    }
    add_wall_work(energy, H, contacts, walls, R, a);
  }
}

void add_contact_terms(EnergyBalance& energy, const ContactOperator& H,
                       const std::vector<Contact3D>& contacts,
                       const std::vector<Wall3D>& walls,
                       std::span<const double> R, std::span<const double> U_mid)
{
  for (std::size_t a = 0; a < contacts.size(); ++a)
  {
    const double* r = &R[3 * a];
    const double* u = &U_mid[3 * a];
    energy.friction -= r[1] * u[1] + r[2] * u[2];
    energy.contact_normal -= r[0] * u[0];
    // (a servo wall's contacts transmit its own work: account_servo_walls)
    if (contacts[a].wall >= 0 && !walls[contacts[a].wall].servo())
    {
      const Eigen::Vector3d w = H.wall_velocity<3>(a);
      energy.wall_work += r[0] * w[0] + r[1] * w[1] + r[2] * w[2];
    }
  }
}

} // namespace softpack::dynamics
