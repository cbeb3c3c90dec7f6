#include "body_forces.h"
#include "BodySet.h"

namespace softpack::bodies
{

std::vector<double> weight(const BodySet& bodies, const Acceleration& g)
{
  std::vector<double> f(bodies.num_dofs(), 0.0);
  const std::vector<char> kept = bodies.kept_masses();
  const int D = bodies.dim();
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    if (!kept[b])
      continue;
    const Body& body = bodies.body(b);
    const Eigen::VectorXd& m = bodies.lumped_mass()[b];
    for (std::size_t k = 0; k < body.nodes.size(); ++k)
      for (int d = 0; d < D; ++d)
        f[D * body.nodes[k] + d] = m[D * k + d] * g[d];
  }
  return f;
}

Acceleration body_weight(const BodySet& bodies, int b, const Acceleration& g)
{
  const double mass = bodies.materials()[bodies.body_material(b)].density *
                      bodies.body(b).reference_area;
  return {mass * g[0], mass * g[1], bodies.dim() == 3 ? mass * g[2] : 0.0};
}

} // namespace softpack::bodies
