#include "damping.h"

namespace softpack::dynamics
{

void combine(RayleighDamping::Combination combination,
             const bodies::BodyMatrix& M, const bodies::BodyMatrix& K,
             bodies::BodyMatrix& out)
{
  const double* m = M.valuePtr();
  const double* k = K.valuePtr();
  double* a = out.valuePtr();
  for (Eigen::Index i = 0; i < out.nonZeros(); ++i)
    a[i] = combination.mass * m[i] + combination.stiffness * k[i];
}

} // namespace softpack::dynamics
