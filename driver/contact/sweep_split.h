#pragma once

#include "DelassusMatrix.h"

#include <cstdint>
#include <vector>

namespace softpack::contact
{

/// The contacts of a problem in three sets for a Gauss–Seidel sweep on two
/// threads: no Delassus block couples a contact of part[0] to one of
/// part[1], so both parts can be swept at once (each in its own order,
/// reading only its own reactions and the separator's), and the separator,
/// which couples to both, is swept after them.
///
/// The sweep "part[0], part[1], separator" is an ordinary Gauss–Seidel
/// sweep in that order: its result does not depend on how many threads run
/// it.
struct SweepSplit
{
  /// Contact indices of the two independent parts, each ascending
  std::vector<std::int32_t> part[2];
  /// Contacts coupled to both parts, ascending
  std::vector<std::int32_t> separator;
};

/// Split the contacts of W by a level-set separator of its coupling graph:
/// breadth-first levels from a pseudo-peripheral contact of each connected
/// component, laid end to end, cut at the level that best balances the
/// work (one plus the off-diagonal blocks of each contact's row) of the two
/// sides plus the separator level itself. Edges between adjacent levels
/// only: the cut level separates the levels before it from those after.
/// The coupling graph is W's block pattern made symmetric. The contacts of
/// W's rank-one terms (DelassusMatrix::RankOne), each coupled to all the
/// others of its term, are all in the separator, the others split; a local
/// term's contacts are split with the others, and those of part[1] moved
/// to the separator when the term also has some in part[0].
/// @param[in] W A finalized Delassus operator
/// @return The split; with fewer than 3 contacts everything is in part[0]
SweepSplit split_for_two_threads(const DelassusMatrix& W);
SweepSplit split_for_two_threads(const DelassusMatrix3D& W);

} // namespace softpack::contact
