#include "general_factor.h"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <cstdlib>
#include <mutex>
#include <stdexcept>

// OpenBLAS (CHOLMOD's BLAS here) exports this; weak, so that another BLAS
// links too.
extern "C" void openblas_set_num_threads(int) __attribute__((weak));

namespace softpack::dynamics
{

namespace
{
/// Eigen's SimplicialLDLT with its AMD ordering, analyzed once
class SimplicialFactor final : public GeneralFactor
{
public:
  void analyze(const bodies::BodyMatrix& pattern) override
  {
    _ldlt.analyzePattern(pattern);
  }
  bool factorize(const bodies::BodyMatrix& A) override
  {
    _ldlt.factorize(A);
    return _ldlt.info() == Eigen::Success &&
           (_ldlt.vectorD().array() > 0).all();
  }
  Eigen::MatrixXd solve(const Eigen::MatrixXd& Y) const override
  {
    return _ldlt.solve(Y);
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& y) const override
  {
    return _ldlt.solve(y);
  }

private:
  Eigen::SimplicialLDLT<bodies::BodyMatrix> _ldlt;
};

/// CHOLMOD's supernodal LL^T, analyzed once (CHOLMOD's default ordering:
/// AMD, METIS when AMD's fill is large). Each factor has its own
/// cholmod_common, so different bodies are factorized and solved on
/// different threads at once.
class CholmodFactor final : public GeneralFactor
{
public:
  void analyze(const bodies::BodyMatrix& pattern) override
  {
    _llt.analyzePattern(pattern);
  }
  bool factorize(const bodies::BodyMatrix& A) override
  {
    _llt.factorize(A);
    return _llt.info() == Eigen::Success;
  }
  Eigen::MatrixXd solve(const Eigen::MatrixXd& Y) const override
  {
    return _llt.solve(Y);
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& y) const override
  {
    return _llt.solve(y);
  }

private:
  Eigen::CholmodSupernodalLLT<bodies::BodyMatrix, Eigen::Lower> _llt;
};

/// One BLAS thread: the driver's OpenMP threads already share the cores out
/// body by body, and OpenBLAS's own threads on top of them oversubscribe
/// them (docs/performance_3d.md). OPENBLAS_NUM_THREADS, when set, wins.
void single_blas_thread()
{
  static std::once_flag once;
  std::call_once(once,
                 []
                 {
                   if (openblas_set_num_threads &&
                       std::getenv("OPENBLAS_NUM_THREADS") == nullptr)
                     openblas_set_num_threads(1);
                 });
}
} // namespace

std::string general_factor_kind()
{
  const char* kind = std::getenv("SOFTPACK_3D_FACTORS");
  if (kind == nullptr || *kind == '\0')
    return "cholmod";
  const std::string k(kind);
  if (k != "cholmod" && k != "simplicial")
    throw std::invalid_argument("SOFTPACK_3D_FACTORS=" + k +
                                ": expected cholmod or simplicial");
  return k;
}

std::unique_ptr<GeneralFactor> make_general_factor(const std::string& kind)
{
  if (kind == "simplicial")
    return std::make_unique<SimplicialFactor>();
  if (kind != "cholmod")
    throw std::invalid_argument("make_general_factor: unknown kind " + kind);
  single_blas_thread();
  return std::make_unique<CholmodFactor>();
}

} // namespace softpack::dynamics
