#pragma once

#include "problem.h"

#include <filesystem>

namespace softpack::contact
{

/// Read a local problem from Siconos numerics' text format (what
/// `frictionContact_printInFile` writes and `frictionContact_newFromFile`
/// reads; the `.dat` files of Siconos' test data):
///
///     dimension  number_of_contacts
///     W: storage size0 size1, then
///        storage 0 (dense): size0 size1, the values column by column;
///        storage 1 (sparse blocks): nbblocks, block rows, block columns,
///          the cumulative block sizes of the rows and of the columns,
///          filled1, filled2, the block-row pointers, the block columns,
///          then per block its number and its values column by column
///     q: dimension x number_of_contacts values
///     mu: number_of_contacts values
///
/// Anything after mu is ignored. Storage 2 (a CSparse matrix printed with
/// 6 significant digits) is refused: those problems are read from their
/// HDF5 copies (fclib_io.h).
/// @tparam D 2 or 3: the dimension the file must have
/// @return The validated problem
/// @throws FclibError (fclib_io.h) naming the file and what is wrong
template <int D>
FrictionContactProblem<D> read_siconos_dat(const std::filesystem::path& path);
extern template FrictionContactProblem<2>
read_siconos_dat(const std::filesystem::path&);
extern template FrictionContactProblem<3>
read_siconos_dat(const std::filesystem::path&);

} // namespace softpack::contact
