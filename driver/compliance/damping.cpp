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

Eigen::VectorXd combined_product(RayleighDamping::Combination combination,
                                 const bodies::BodyMatrix& M,
                                 const bodies::BodyMatrix& K,
                                 const Eigen::VectorXd& v)
{
  const double* m = M.valuePtr();
  const double* k = K.valuePtr();
  const int* outer = M.outerIndexPtr();
  const int* inner = M.innerIndexPtr();
  Eigen::VectorXd y = Eigen::VectorXd::Zero(M.rows());
  for (Eigen::Index j = 0; j < M.outerSize(); ++j)
  {
    const double vj = v[j];
    for (int p = outer[j]; p < outer[j + 1]; ++p)
    {
      // the lower triangle: (i, j) stands for (j, i) too
      const int i = inner[p];
      const double a = combination.mass * m[p] + combination.stiffness * k[p];
      y[i] += a * vj;
      if (i != j)
        y[j] += a * v[i];
    }
  }
  return y;
}

} // namespace softpack::dynamics
