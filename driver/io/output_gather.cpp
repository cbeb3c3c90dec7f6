#include "output_gather.h"

#include <stdexcept>
#include <string>
#include <utility>

namespace softpack::io
{

OutputGather::OutputGather(const dynamics::MoreauJean& scheme,
                           const bodies::BodySet& bodies)
    : _scheme(scheme)
{
  const parallel::Distribution& dist = scheme.distribution();
  const parallel::Scatterer& scatter = dist.scatterer();
  _root = dist.comm().rank() == 0;
  _u = scatter.gather_to_root(bodies, bodies.displacement());
  _v = scatter.gather_to_root(bodies, scheme.velocity());
  if (scheme.matrix_age() >= 0)
    _u_tangent = scatter.gather_to_root(bodies, scheme.tangent_displacement());
  // Each cell's internal variables are current on its body's owner only
  if (const int stride = bodies.internal_stride();
      stride > 0 && dist.distributed())
  {
    _internal = scatter.gather_cells_to_root(
        bodies, bodies.internal_variables(), stride);
    if (scheme.matrix_age() >= 0)
      _internal_tangent = scatter.gather_cells_to_root(
          bodies, scheme.tangent_internal(), stride);
  }
}

void OutputGather::require(const char* what) const
{
  if (!_root || _u.empty())
    throw std::logic_error(std::string("OutputGather::") + what +
                           ": the global vectors are rank 0's, until the "
                           "state takes them");
}

std::span<const double> OutputGather::displacement() const
{
  require("displacement");
  return _u;
}

dynamics::SchemeState OutputGather::take_state()
{
  require("take_state");
  dynamics::SchemeState s = _scheme.scalar_state();
  s.u = std::exchange(_u, {});
  s.v = std::exchange(_v, {});
  std::vector<double> u_tangent = std::exchange(_u_tangent, {});
  if (s.matrix_age >= 0)
    s.u_tangent = std::move(u_tangent);
  if (!_internal.empty())
  {
    s.internal = std::exchange(_internal, {});
    if (s.matrix_age >= 0)
      s.internal_tangent = std::exchange(_internal_tangent, {});
  }
  return s;
}

} // namespace softpack::io
