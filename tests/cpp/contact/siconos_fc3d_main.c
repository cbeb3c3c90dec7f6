/* softpack-siconos-fc3d: Siconos numerics' own fc3d NSGS on Siconos .dat
 * problems, the peer of `softpack-fclib --dim 3` (docs/contact_3d.md).
 *
 *   softpack-siconos-fc3d TOL MAX_ITER FILE...
 *
 * One JSON line per problem: sweeps, Siconos' error at its answer
 * (fc3d_compute_error, divided by max(|q|, |r|, |u|) as softpack's), and
 * that error recomputed from the file, seconds. */
#include "siconos_reference.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char** argv)
{
  if (argc < 4)
  {
    fprintf(stderr, "usage: softpack-siconos-fc3d TOL MAX_ITER FILE...\n");
    return 2;
  }
  const double tolerance = atof(argv[1]);
  const int max_iter = atoi(argv[2]);
  const int capacity = 1 << 20;
  double* r = malloc(capacity * sizeof(double));
  double* u = malloc(capacity * sizeof(double));
  int status = 0;
  for (int k = 3; k < argc; ++k)
  {
    SiconosFc2dResult result;
    memset(&result, 0, sizeof(result));
    const double start = now();
    const int rc = siconos_fc3d_nsgs(argv[k], tolerance, max_iter, r, u,
                                     capacity, &result);
    const double seconds = now() - start;
    double recomputed = -1;
    if (rc == 0)
      siconos_fc3d_error(argv[k], r, 3 * result.contacts, &recomputed);
    printf("{\"file\":\"%s\",\"read\":%d,\"contacts\":%d,\"info\":%d,"
           "\"iterations\":%d,\"siconos_error\":%.3e,\"recomputed_error\":%.3e,"
           "\"seconds\":%.4f}\n",
           argv[k], rc, result.contacts, result.info, result.iterations,
           result.error, recomputed, seconds);
    status |= rc != 0 || result.info != 0;
  }
  free(r);
  free(u);
  return status;
}
