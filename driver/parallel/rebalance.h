#pragma once

#include "distribution.h"
#include <array>
#include <bodies/BodySet.h>
#include <span>
#include <vector>

namespace softpack::parallel
{

/// Centre of each of the given bodies at the node coordinates x
/// (interleaved, BodySet::dim() per node and per centre; the others' stay
/// zero)
std::vector<double> body_centres(const bodies::BodySet& bodies,
                                 std::span<const double> x,
                                 std::span<const int> which);

/// A new split of the bodies, by recursive coordinate bisection of their
/// current centres with the given weights, when the split in force has
/// drifted from it (split_has_drifted: uneven work, or many more contacts
/// cut between ranks); else empty. Every rank decides alike from the same
/// data (the centres are summed over the ranks, each from its owner: x is
/// read at the local bodies' nodes only).
/// @param[in] x Current node coordinates (the storage, interleaved)
/// @param[in] weights Work of each body, > 0
/// @param[in] links The body pairs of the contacts between bodies
/// @param[in] tolerance Relative drift allowed (e.g. 0.1)
/// @return The rank of each body, or empty
std::vector<int>
drifted_split(const Distribution& distribution, const bodies::BodySet& bodies,
              std::span<const double> x, std::span<const double> weights,
              std::span<const std::array<int, 2>> links, double tolerance);

/// Give the bodies to the ranks of a drifted_split (counted as a
/// rebalance): each body that changes rank sends its entries of the
/// displacement, the reference coordinates and the given node vectors
/// (the empty ones skipped), its cell lists (BodySet::cell_lists) and its
/// cells' internal variables (a law that has them), from its old owner to
/// its new one (all-to-alls: its interior, cells and internal variables
/// are its old owner's only); `bodies` keeps the new share
/// (Distribution::assign, BodySet::set_local), and the given vectors are
/// remapped to its storage.
void move_bodies(Distribution& distribution, std::vector<int> split,
                 bodies::BodySet& bodies,
                 std::span<std::vector<double>* const> vectors);

} // namespace softpack::parallel
