#include "body_forces.h"
#include "BodySet.h"

namespace softpack::bodies
{

std::vector<double> weight(const BodySet& bodies,
                           const std::array<double, 2>& g)
{
  std::vector<double> f(bodies.num_dofs(), 0.0);
  const std::vector<char> kept = bodies.kept_masses();
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    if (!kept[b])
      continue;
    const Body& body = bodies.body(b);
    const Eigen::VectorXd& m = bodies.lumped_mass()[b];
    for (std::size_t k = 0; k < body.nodes.size(); ++k)
      for (int d = 0; d < 2; ++d)
        f[2 * body.nodes[k] + d] = m[2 * k + d] * g[d];
  }
  return f;
}

std::array<double, 2> body_weight(const BodySet& bodies, int b,
                                  const std::array<double, 2>& g)
{
  const double mass = bodies.materials()[bodies.body_material(b)].density *
                      bodies.body(b).reference_area;
  return {mass * g[0], mass * g[1]};
}

} // namespace softpack::bodies
