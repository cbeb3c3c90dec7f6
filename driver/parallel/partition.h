#pragma once

#include <array>
#include <span>
#include <vector>

/// Distribution of the bodies of a run over MPI ranks.
namespace softpack::parallel
{

/// The rank of each body by recursive coordinate bisection of the body
/// centres: the set is cut across its longest extent at the weighted point
/// that gives each side a share of the weight proportional to its number
/// of ranks, and each side is cut again until one rank is left. Bodies
/// close in space land on one rank, so few contacts cross ranks.
///
/// Deterministic (ties broken by body index): every rank computes the same
/// partition from the same input, with no communication.
/// @param[in] centres Centre of each body, (x, y) or (x, y, z) interleaved
/// @param[in] weights Work of each body (e.g. its DOFs), > 0
/// @param[in] ranks Number of parts, 1 <= ranks <= number of bodies
/// @param[in] dim The centres' dimension (the bodies', 2 or 3)
/// @return The part (rank) of each body; every part has at least one body
/// @throws std::invalid_argument if ranks is out of range or the sizes do
/// not match
std::vector<int> partition_bodies(std::span<const double> centres,
                                  std::span<const double> weights, int ranks,
                                  int dim = 2);

/// Whether a distributed run should move from the split `now` to the
/// split `fresh` (e.g. partition_bodies of the current centres), both into
/// `parts` parts (a part may hold no body: it counts in the mean): the
/// busiest part's work exceeds the mean by more than `tolerance` and
/// `fresh` is more even, or the links (contacts) cut between parts exceed
/// fresh's by more than `tolerance` and by at least 8, and fresh is not
/// uneven beyond `tolerance`.
/// @param[in] weights Work of each body
/// @param[in] links Body pairs in contact
bool split_has_drifted(std::span<const int> now, std::span<const int> fresh,
                       int parts, std::span<const double> weights,
                       std::span<const std::array<int, 2>> links,
                       double tolerance);

} // namespace softpack::parallel
