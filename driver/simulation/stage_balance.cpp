// The equilibrium criterion of a stage (stages.h): the unbalanced force
// ratio of the particles and servo walls, for either dimension's contacts
// and walls.
#include "stages.h"
#include <walls/wall_vectors.h>

#include <algorithm>
#include <bodies/body_forces.h>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

namespace softpack::simulation
{
using dynamics::dot;

namespace
{
double norm(const std::array<double, 2>& f)
{
  return std::hypot(f[0], f[1]);
}
double norm(const std::array<double, 3>& f)
{
  return std::hypot(f[0], f[1], f[2]);
}
} // namespace

namespace
{
/// The largest servo wall's residual: its imposed force against the normal
/// contact force it received, relative to the imposed force (a servo wall
/// is a body too)
template <class W, class F>
double servo_wall_ratio(const std::vector<W>& walls,
                        const std::vector<F>& received)
{
  // Measured against its own load: a wall carries the contacts of a whole
  // side of the box (tens of pair forces), so measured against one mean
  // pair force its residual breathing would keep a 100-disk stage from
  // ever ending (seen at 40 kPa: 0.5 % of its load).
  double ratio = 0;
  for (std::size_t w = 0; w < walls.size(); ++w)
  {
    const double imposed = dynamics::imposed_force(walls, w);
    if (walls[w].servo() && imposed != 0)
      ratio = std::max(ratio,
                       std::abs(imposed + dot(received[w], walls[w].normal)) /
                           std::abs(imposed));
  }
  return ratio;
}

/// Contact a's impulse on its candidate in world components
std::array<double, 2> impulse_on(const dynamics::Contact& c,
                                 const std::vector<double>& R, std::size_t a)
{
  return {R[2 * a] * c.n[0] + R[2 * a + 1] * c.t[0],
          R[2 * a] * c.n[1] + R[2 * a + 1] * c.t[1]};
}
std::array<double, 3> impulse_on(const dynamics::Contact3D& c,
                                 const std::vector<double>& R, std::size_t a)
{
  std::array<double, 3> f;
  for (int i = 0; i < 3; ++i)
    f[i] = R[3 * a] * c.n[i] + R[3 * a + 1] * c.t1[i] + R[3 * a + 2] * c.t2[i];
  return f;
}

/// max_p |f_p| / <|f_c|> over contacts of either dimension (without the
/// servo walls' ratio); `resultant` starts at each body's weight x h.
/// Without a contact force: inf if a body is pulled, else 0, and `none`
template <class C, class F>
double particle_ratio(bool& none, const std::vector<C>& contacts,
                      const std::vector<double>& R, std::vector<F> resultant)
{
  constexpr std::size_t D = std::tuple_size_v<F>;
  // A pair: (candidate, antagonist body) or (candidate, -1 - wall).
  std::map<std::pair<int, int>, F> pairs;
  for (std::size_t a = 0; a < contacts.size(); ++a)
  {
    const C& c = contacts[a];
    const F f = impulse_on(c, R, a);
    for (std::size_t d = 0; d < D; ++d)
    {
      resultant[c.candidate_body][d] += f[d];
      if (c.antagonist_body >= 0)
        resultant[c.antagonist_body][d] -= f[d];
    }
    // One pair whichever body is the candidate.
    const int other = c.antagonist_body >= 0 ? c.antagonist_body : -1 - c.wall;
    const std::pair<int, int> key =
        other >= 0 ? std::make_pair(std::min(c.candidate_body, other),
                                    std::max(c.candidate_body, other))
                   : std::make_pair(c.candidate_body, other);
    F& p = pairs[key];
    // Forces on the lower-numbered body of the pair.
    const double s = (other >= 0 && c.candidate_body != key.first) ? -1 : 1;
    for (std::size_t d = 0; d < D; ++d)
      p[d] += s * f[d];
  }
  double sum = 0;
  int n = 0;
  for (const auto& [key, f] : pairs)
    if (norm(f) > 0)
    {
      sum += norm(f);
      ++n;
    }
  double largest = 0;
  for (const auto& f : resultant)
    largest = std::max(largest, norm(f));
  // No contact force: at rest, unless a weight pulls a body in flight
  none = n == 0;
  if (n == 0)
    return largest > 0 ? std::numeric_limits<double>::infinity() : 0;
  return largest / (sum / n);
}

/// Each particle's weight times the time step (zeros without gravity): the
/// impulse its resultant starts from.
template <std::size_t D>
std::vector<std::array<double, D>>
weight_impulses(const dynamics::MoreauJean& scheme,
                const bodies::BodySet& bodies,
                const bodies::Acceleration& gravity)
{
  std::vector<std::array<double, D>> out(bodies.num_bodies());
  for (auto& f : out)
    f.fill(0);
  if (gravity == bodies::Acceleration{0, 0, 0})
    return out;
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    const bodies::Acceleration w = bodies::body_weight(bodies, b, gravity);
    for (std::size_t d = 0; d < D; ++d)
      out[b][d] = w[d] * scheme.time_step();
  }
  return out;
}
} // namespace

double unbalanced_force_ratio(const dynamics::MoreauJean& scheme,
                              const bodies::BodySet& bodies,
                              const bodies::Acceleration& gravity)
{
  // The particles' ratio is taken on impulses (forces x h), as the
  // contacts give them; the walls' on forces.
  bool none = false;
  const double particles =
      scheme.dimension() == 3
          ? particle_ratio(none, scheme.contacts_3d(), scheme.impulses(),
                           weight_impulses<3>(scheme, bodies, gravity))
          : particle_ratio(none, scheme.contacts(), scheme.impulses(),
                           weight_impulses<2>(scheme, bodies, gravity));
  if (none)
    return particles;
  return std::max(
      particles,
      scheme.dimension() == 3
          ? servo_wall_ratio(scheme.walls_3d(), scheme.wall_forces_3d())
          : servo_wall_ratio(scheme.walls(), scheme.wall_forces()));
}

} // namespace softpack::simulation
