#include "threads.h"

#include <cstdio>
#include <cstdlib>
#include <omp.h>
#include <stdexcept>
#include <string>
#include <unistd.h>

namespace softpack::apps
{

void ensure_passive_waiting(char** argv)
{
  if (std::getenv("OMP_WAIT_POLICY") != nullptr)
    return;
  ::setenv("OMP_WAIT_POLICY", "PASSIVE", 1);
  ::execv("/proc/self/exe", argv);
  std::fprintf(stderr, "softpack-simulate: warning: could not restart with "
                       "OMP_WAIT_POLICY=PASSIVE; threads will spin at "
                       "barriers (slow when the cores are shared)\n");
}

void set_thread_count(int threads)
{
  if (threads < 0)
    throw std::invalid_argument("--threads " + std::to_string(threads) +
                                ": must be >= 0 (0: one per available core)");
  if (threads > 0)
    omp_set_num_threads(threads);
}

} // namespace softpack::apps
