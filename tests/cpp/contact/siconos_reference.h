#pragma once

/* The reference: Siconos numerics' own 2D NSGS (Debian
 * libsiconos-numerics-dev 4.4) on a Siconos .dat problem. A C translation
 * unit, because Siconos' headers are C (restrict, ...). */

#ifdef __cplusplus
extern "C"
{
#endif

  /** Outcome of siconos_fc2d_nsgs(). */
  typedef struct
  {
    int info;        /**< fc2d_driver's info: 0 converged */
    int contacts;    /**< number of contacts in the file */
    int iterations;  /**< NSGS sweeps done */
    double error;    /**< fc2d_compute_error at the returned reactions */
    double residual; /**< the solver's own final residual (dparam) */
  } SiconosFc2dResult;

  /** Read a 2D problem from a Siconos .dat file and solve it with fc2d_driver
   * (SICONOS_FRICTION_2D_NSGS, default options but tolerance and iterations),
   * from r = 0. A compressed-sparse W is converted to 2x2 sparse blocks first,
   * since the 4.4 driver accepts dense or sparse-block storage only.
   * @param[in] path The .dat file
   * @param[in] tolerance dparam[SICONOS_DPARAM_TOL]
   * @param[in] max_iter iparam[SICONOS_IPARAM_MAX_ITER]
   * @param[out] r Reactions (capacity doubles)
   * @param[out] u Velocities (capacity doubles)
   * @param[in] capacity Size of r and u, at least 2 * contacts
   * @param[out] result Sweeps, error, ...
   * @return 0 if solved (converged or not), -1 if the file cannot be read or
   *   is not 2D, -2 if capacity is too small */
  int siconos_fc2d_nsgs(const char* path, double tolerance, int max_iter,
                        double* r, double* u, int capacity,
                        SiconosFc2dResult* result);

  /** Siconos' fc2d_compute_error of given reactions for a .dat problem.
   * @param[in] path The .dat file
   * @param[in] r Reactions, 2 per contact
   * @param[in] n Size of r (must be 2 * contacts)
   * @param[out] error The relative natural-map error
   * @return 0 if ok, -1 if the file cannot be read or n is wrong */
  int siconos_fc2d_error(const char* path, const double* r, int n,
                         double* error);

  /** Siconos' fc3d_compute_error of given reactions (3 per contact) for a
   * 3D .dat problem, with its norm argument ||q||: Siconos 4.4 then divides
   * by max(||q||, ||r||, ||u||), softpack's scale (error.h). */
  int siconos_fc3d_error(const char* path, const double* r, int n,
                         double* error);

  /** siconos_fc2d_nsgs() for a 3D .dat problem: fc3d_driver with
   * SICONOS_FRICTION_3D_NSGS (its default local solver), from r = 0. */
  int siconos_fc3d_nsgs(const char* path, double tolerance, int max_iter,
                        double* r, double* u, int capacity,
                        SiconosFc2dResult* result);

#ifdef __cplusplus
}
#endif
