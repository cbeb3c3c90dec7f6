#pragma once

#include "problem.h"

#include <filesystem>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace softpack::contact
{

/// A file that is not a valid FCLIB problem (or Siconos text problem) of
/// the dimension asked for; the message names the file and what is wrong
/// (missing dataset, wrong sizes, dimension, ...).
class FclibError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// Content of an FCLIB file beyond the problem itself (FclibLocalFile: 2D,
/// FclibFile3D: 3D).
template <int D> struct FclibFile
{
  /// The problem, validated (a global one condensed: read_fclib_file())
  FrictionContactProblem<D> problem;

  /// /fclib_local/info/title, if present
  std::string title;

  /// /solution/r, if present (a reference answer)
  std::optional<std::vector<double>> solution_r;

  /// /solution/u, if present (velocities of the reference answer)
  std::optional<std::vector<double>> solution_u;

  /// /guesses/1/r, if present (e.g. the start of a failed solve)
  std::optional<std::vector<double>> guess_r;
};

using FclibLocalFile = FclibFile<2>;
using FclibFile3D = FclibFile<3>;

/// Read a 2D problem stored in the FCLIB HDF5 local layout `/fclib_local`:
/// `spacedim` (= 2), `W/{m,n,nz,nzmax,p,i,x}` a CSparse matrix (nz = -2
/// compressed rows, nz = -1 compressed columns, nz >= 0 triplets),
/// `vectors/q` (2 per contact, (n, t)), `vectors/mu` (one per contact),
/// and softpack's own `vectors/cohesion` (one per contact) when present:
/// a cohesive problem dumped by dump_problem().
/// W is converted to its 2x2 block form without forming it dense.
/// @param[in] path The HDF5 file
/// @return The problem and the optional title, solution and guess
/// @throws FclibError if the file is not a valid 2D local problem
FclibLocalFile read_fclib_local_file(const std::filesystem::path& path);

/// As read_fclib_local_file(), the problem only.
/// @param[in] path The HDF5 file
/// @return The validated problem
/// @throws FclibError if the file is not a valid 2D local problem
FrictionContactProblem2D read_fclib_local(const std::filesystem::path& path);

/// Read a problem of D = 2 or 3 dimensions from an FCLIB HDF5 file, local
/// or global:
/// - `/fclib_local`: as read_fclib_local_file(), `spacedim` = D, D
///   entries of q per contact;
/// - `/fclib_global` (M v = H r + f, u = H^T v + w; `M`, `H` CSparse
///   matrices, `vectors/{f,w,mu}`): condensed to the local form
///   $W = H^T M^{-1} H$, $q = H^T M^{-1} f + w$ with a sparse
///   Cholesky (LDL^T) factorization of M (fclib_global.cpp). Its
///   /solution/u and /guesses/1/r are the local ones (u, r); its
///   /solution/v is not kept.
/// @throws FclibError if the file is neither, or not of dimension D, or M
///   is not symmetric positive definite
template <int D>
FclibFile<D> read_fclib_file(const std::filesystem::path& path);
extern template FclibFile<2> read_fclib_file(const std::filesystem::path&);
extern template FclibFile<3> read_fclib_file(const std::filesystem::path&);

/// Write a 2D or 3D problem in the same `/fclib_local` layout (`spacedim`
/// D, W as compressed rows of its stored blocks), so that a failed solve
/// can be replayed (read_fclib_file<D>, `./softpack fclib [--dim 3]`); a
/// problem with a cohesion also gets `vectors/cohesion`.
/// @param[in] problem The problem (finalized W)
/// @param[in] path The HDF5 file, created or truncated
/// @param[in] description Stored as /fclib_local/info/description
/// @param[in] guess If not empty, reactions stored as /guesses/1/r (D per
///   contact)
/// @throws FclibError if the file cannot be written
template <int D>
void dump_problem(const FrictionContactProblem<D>& problem,
                  const std::filesystem::path& path,
                  const std::string& description = "",
                  std::span<const double> guess = {});
extern template void dump_problem(const FrictionContactProblem2D&,
                                  const std::filesystem::path&,
                                  const std::string&, std::span<const double>);
extern template void dump_problem(const FrictionContactProblem3D&,
                                  const std::filesystem::path&,
                                  const std::string&, std::span<const double>);

} // namespace softpack::contact
