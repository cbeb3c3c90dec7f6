#pragma once

// The pieces of the FCLIB readers (fclib_io.h) that the local and the
// global layouts share: CSparse matrices as entries, D x D blocks.

#include "problem.h"

#include <hdf5.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace softpack::contact::fclib
{

/// One scalar entry of a sparse matrix.
struct Entry
{
  std::int64_t row, col;
  double value;
};

/// A CSparse matrix of an FCLIB file as its entries (duplicates kept: they
/// add up).
struct SparseEntries
{
  std::int64_t rows = 0, cols = 0;
  std::vector<Entry> entries;
};

/// The integer dataset `path` holding one value.
/// @throws FclibError (fclib_io.h) otherwise
std::int64_t read_scalar(hid_t file, const std::string& path);

/// Read the CSparse matrix stored in the group `group` of an FCLIB file
/// (`{m,n,nz,nzmax,p,i,x}`; nz = -2 compressed rows, nz = -1 compressed
/// columns, nz >= 0 triplets with row i and column p), checking its
/// pointers and indices; the values are checked finite.
/// @param[in] group e.g. "/fclib_local/W"
/// @param[in] name The matrix's name in messages ("W", "M", "H")
/// @param[in] check_size Called with its m and n before its entries are
///   read (to refuse a wrong size first)
/// @throws FclibError naming the dataset and what is wrong
SparseEntries read_csparse(
    hid_t file, const std::string& group, const std::string& name,
    const std::function<void(std::int64_t, std::int64_t)>& check_size = {});

/// Refuse a W that is not (D nc) x (D nc)
/// @throws FclibError
void check_delassus_size(std::int64_t rows, std::int64_t cols, int D,
                         std::size_t nc);

/// The D x D blocks of a (D nc) x (D nc) matrix given by its entries
/// (fclib_io.cpp)
/// @throws FclibError if its size is not D nc x D nc
template <int D>
DelassusMatrixD<D> blocks_of(const SparseEntries& W, std::size_t nc);

/// The problem of an `/fclib_global` group condensed to the local form
/// (fclib_global.cpp): W = H^T M^-1 H, q = H^T M^-1 f + w
/// @throws FclibError for sizes that do not match or an M that is not
///   symmetric positive definite
template <int D> FrictionContactProblem<D> read_global_problem(hid_t file);

} // namespace softpack::contact::fclib
