#include "general_factor.h"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <cstdlib>
#include <mutex>
#include <omp.h>
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

/// Runs `f` with OpenMP's parallel regions serial. CHOLMOD 3 (SuiteSparse 5)
/// runs loops of each large supernode in OpenMP teams of 4 threads (its
/// compile-time CHOLMOD_OMP_NUM_THREADS, which a num_threads clause sets, so
/// OMP_NUM_THREADS does not bound it): on 2 shared cores, with the driver's
/// threads waiting passively (apps::ensure_passive_waiting), each such
/// region waits for wake-ups and time slices. Measured on a cylinder of
/// 3,186 DOFs: 0.17 s per factorization in those teams, 0.05 s serial
/// (docs/performance_3d.md, "Factors of 3D bodies"). Within the driver's
/// parallel loops over bodies CHOLMOD's regions are nested, hence serial
/// already (max-active-levels 1, OpenMP's default).
template <class F> void without_openmp_teams(F&& f)
{
  if (omp_in_parallel())
  {
    f();
    return;
  }
  const int levels = omp_get_max_active_levels();
  omp_set_max_active_levels(0);
  f();
  omp_set_max_active_levels(levels);
}

/// CHOLMOD's supernodal LL^T, analyzed once (CHOLMOD's default ordering:
/// AMD, METIS when AMD's fill is large). Each factor has its own
/// cholmod_common, so different bodies are factorized and solved on
/// different threads at once.
class CholmodFactor final : public GeneralFactor
{
public:
  void analyze(const bodies::BodyMatrix& pattern) override
  {
    without_openmp_teams([&] { _llt.analyzePattern(pattern); });
  }
  bool factorize(const bodies::BodyMatrix& A) override
  {
    without_openmp_teams([&] { _llt.factorize(A); });
    return _llt.info() == Eigen::Success;
  }
  Eigen::MatrixXd solve(const Eigen::MatrixXd& Y) const override
  {
    Eigen::MatrixXd X;
    without_openmp_teams([&] { X = _llt.solve(Y); });
    return X;
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& y) const override
  {
    Eigen::VectorXd x;
    without_openmp_teams([&] { x = _llt.solve(y); });
    return x;
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
