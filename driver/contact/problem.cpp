#include "problem.h"

#include <cmath>
#include <stdexcept>
#include <string>

using namespace softpack::contact;

namespace
{
//-----------------------------------------------------------------------------
[[noreturn]] void fail(const std::string& what)
{
  throw std::invalid_argument(what);
}
//-----------------------------------------------------------------------------
template <int D> void validate_sizes(const FrictionContactProblem<D>& p)
{
  const std::size_t nc = p.num_contacts();
  if (!p.W.finalized())
    fail("W is not finalized");
  if (p.W.num_contacts() != nc)
  {
    fail("W has " + std::to_string(p.W.num_contacts()) +
         " block rows but friction has " + std::to_string(nc) + " contacts");
  }
  if (p.q.size() != D * nc)
  {
    fail("q has " + std::to_string(p.q.size()) + " entries, expected " +
         std::to_string(D * nc) + " (" + std::to_string(D) + " per contact)");
  }
  if (!p.cohesion.empty() and p.cohesion.size() != nc)
  {
    fail("cohesion has " + std::to_string(p.cohesion.size()) +
         " entries, expected " + std::to_string(nc) +
         " (1 per contact) or none");
  }
}
//-----------------------------------------------------------------------------
template <int D> void validate_values(const FrictionContactProblem<D>& p)
{
  for (std::size_t k = 0; k < p.q.size(); ++k)
    if (!std::isfinite(p.q[k]))
      fail("q[" + std::to_string(k) + "] is not finite");
  for (std::size_t a = 0; a < p.friction.size(); ++a)
  {
    if (!std::isfinite(p.friction[a]))
      fail("friction[" + std::to_string(a) + "] is not finite");
    if (p.friction[a] < 0)
    {
      fail("friction[" + std::to_string(a) +
           "] = " + std::to_string(p.friction[a]) + " is negative");
    }
  }
  for (std::size_t a = 0; a < p.cohesion.size(); ++a)
    if (!(std::isfinite(p.cohesion[a]) and p.cohesion[a] >= 0))
      fail("cohesion[" + std::to_string(a) + "] = " +
           std::to_string(p.cohesion[a]) + " is not a finite value >= 0");
}
//-----------------------------------------------------------------------------
template <int D> void validate_blocks(const DelassusMatrixD<D>& W)
{
  for (std::size_t a = 0; a < W.num_contacts(); ++a)
  {
    const auto& d = W.diagonal(a);
    if (!d.allFinite())
      fail("W diagonal block of contact " + std::to_string(a) +
           " is not finite");
    if (!(d(0, 0) > 0))
    {
      fail("W diagonal block of contact " + std::to_string(a) +
           " has W_nn = " + std::to_string(d(0, 0)) +
           " (must be > 0: missing or degenerate contact)");
    }
    const auto cols = W.row_columns(a);
    const auto blocks = W.row_blocks(a);
    for (std::size_t k = 0; k < cols.size(); ++k)
      if (!blocks[k].allFinite())
        fail("W block (" + std::to_string(a) + ", " + std::to_string(cols[k]) +
             ") is not finite");
  }
}
//-----------------------------------------------------------------------------
template <int D> void validate_problem(const FrictionContactProblem<D>& problem)
{
  validate_sizes(problem);
  validate_values(problem);
  validate_blocks(problem.W);
}
} // namespace

//-----------------------------------------------------------------------------
void softpack::contact::validate(const FrictionContactProblem2D& problem)
{
  validate_problem(problem);
}
//-----------------------------------------------------------------------------
void softpack::contact::validate(const FrictionContactProblem3D& problem)
{
  validate_problem(problem);
}
//-----------------------------------------------------------------------------
