#include "siconos_reference.h"

#include <siconos/numerics/FrictionContactProblem.h>
#include <siconos/numerics/Friction_cst.h>
#include <siconos/numerics/NonSmoothDrivers.h>
#include <siconos/numerics/NumericsMatrix.h>
#include <siconos/numerics/SolverOptions.h>
#include <siconos/numerics/SparseBlockMatrix.h>
#include <siconos/numerics/fc2d_compute_error.h>
#include <siconos/numerics/fc3d_compute_error.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* Replace a compressed-sparse W by the same matrix in 2x2 sparse blocks. */
static int to_sparse_block(FrictionContactProblem* problem)
{
  NumericsMatrix* A = problem->M;
  NumericsMatrix* B = NM_new();
  B->storageType = NM_SPARSE_BLOCK;
  B->size0 = A->size0;
  B->size1 = A->size1;
  B->matrix1 = SBM_new();
  if (SBM_from_csparse(2, NM_csc(A), B->matrix1) != 0)
  {
    NM_clear(B);
    free(B);
    return -1;
  }
  NM_clear(A);
  free(A);
  problem->M = B;
  return 0;
}

/* Read a .dat problem of the given dimension, NULL if that fails. */
static FrictionContactProblem* read_problem_of(const char* path, int dim)
{
  FILE* file = fopen(path, "r");
  if (!file)
    return NULL;
  FrictionContactProblem* problem = frictionContact_newFromFile(file);
  fclose(file);
  if (problem && problem->dimension != dim)
  {
    frictionContactProblem_free(problem);
    return NULL;
  }
  return problem;
}

static FrictionContactProblem* read_problem(const char* path)
{
  return read_problem_of(path, 2);
}

static double norm2(const double* v, int n)
{
  double s = 0;
  for (int k = 0; k < n; ++k)
    s += v[k] * v[k];
  return sqrt(s);
}

int siconos_fc2d_error(const char* path, const double* r, int n, double* error)
{
  FrictionContactProblem* problem = read_problem(path);
  if (!problem)
    return -1;
  if (n != 2 * problem->numberOfContacts)
  {
    frictionContactProblem_free(problem);
    return -1;
  }
  double* z = malloc(n * sizeof(double));
  double* w = malloc(n * sizeof(double));
  for (int k = 0; k < n; ++k)
    z[k] = r[k];
  fc2d_compute_error(problem, z, w, 0.0, norm2(problem->q, n), error);
  free(z);
  free(w);
  frictionContactProblem_free(problem);
  return 0;
}

int siconos_fc2d_nsgs(const char* path, double tolerance, int max_iter,
                      double* r, double* u, int capacity,
                      SiconosFc2dResult* result)
{
  FrictionContactProblem* problem = read_problem(path);
  if (!problem)
    return -1;
  const int n = 2 * problem->numberOfContacts;
  result->contacts = problem->numberOfContacts;
  if (n > capacity)
  {
    frictionContactProblem_free(problem);
    return -2;
  }
  if (problem->M->storageType == NM_SPARSE && to_sparse_block(problem) != 0)
  {
    frictionContactProblem_free(problem);
    return -1;
  }
  for (int k = 0; k < n; ++k)
    r[k] = u[k] = 0.0;

  SolverOptions* options = solver_options_create(SICONOS_FRICTION_2D_NSGS);
  options->iparam[SICONOS_IPARAM_MAX_ITER] = max_iter;
  options->dparam[SICONOS_DPARAM_TOL] = tolerance;
  result->info = fc2d_driver(problem, r, u, options);
  result->iterations = options->iparam[SICONOS_IPARAM_ITER_DONE];
  result->residual = options->dparam[SICONOS_DPARAM_RESIDU];
  solver_options_delete(options);

  fc2d_compute_error(problem, r, u, tolerance, norm2(problem->q, n),
                     &result->error);
  frictionContactProblem_free(problem);
  return 0;
}

int siconos_fc3d_error(const char* path, const double* r, int n, double* error)
{
  FrictionContactProblem* problem = read_problem_of(path, 3);
  if (!problem)
    return -1;
  if (n != 3 * problem->numberOfContacts)
  {
    frictionContactProblem_free(problem);
    return -1;
  }
  double* z = malloc(n * sizeof(double));
  double* w = malloc(n * sizeof(double));
  for (int k = 0; k < n; ++k)
    z[k] = r[k];
  /* Siconos 4.4 divides by max(norm, |r|, |u|): with norm = |q| it is
   * softpack's error (error.h) */
  fc3d_compute_error(problem, z, w, 0.0, NULL, norm2(problem->q, n), error);
  free(z);
  free(w);
  frictionContactProblem_free(problem);
  return 0;
}

int siconos_fc3d_nsgs(const char* path, double tolerance, int max_iter,
                      double* r, double* u, int capacity,
                      SiconosFc2dResult* result)
{
  FrictionContactProblem* problem = read_problem_of(path, 3);
  if (!problem)
    return -1;
  const int n = 3 * problem->numberOfContacts;
  result->contacts = problem->numberOfContacts;
  if (n > capacity)
  {
    frictionContactProblem_free(problem);
    return -2;
  }
  for (int k = 0; k < n; ++k)
    r[k] = u[k] = 0.0;
  SolverOptions* options = solver_options_create(SICONOS_FRICTION_3D_NSGS);
  options->iparam[SICONOS_IPARAM_MAX_ITER] = max_iter;
  options->dparam[SICONOS_DPARAM_TOL] = tolerance;
  result->info = fc3d_driver(problem, r, u, options);
  result->iterations = options->iparam[SICONOS_IPARAM_ITER_DONE];
  result->residual = options->dparam[SICONOS_DPARAM_RESIDU];
  solver_options_delete(options);
  fc3d_compute_error(problem, r, u, tolerance, NULL, norm2(problem->q, n),
                     &result->error);
  frictionContactProblem_free(problem);
  return 0;
}
