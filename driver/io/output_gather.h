#pragma once

#include <bodies/BodySet.h>
#include <dynamics/moreau_jean.h>
#include <span>
#include <vector>

namespace softpack::io
{

/// Rank 0's global copies of the scheme's node vectors for one output (the
/// fields, the state file): gathered from the processes where each body is
/// local (a collective; copies of the stored vectors when serial), handed
/// to the writers, and freed with this object, since kept they would be
/// the one memory of a process that grows with the whole model.
class OutputGather
{
public:
  /// Gather the displacement, the velocity, the kept tangent's
  /// displacement and the internal variables. Every process calls it at the
  /// same point, after MoreauJean::prepare_output (the state's energies).
  OutputGather(const dynamics::MoreauJean& scheme,
               const bodies::BodySet& bodies);

  /// The global displacement (2 entries per mesh node)
  /// @throws std::logic_error but on rank 0, or after take_state
  std::span<const double> displacement() const;
  /// The scheme's state with its global vectors, handed over (not copied:
  /// three vectors of the whole model's length)
  /// @throws std::logic_error but on rank 0, or when taken already
  dynamics::SchemeState take_state();

private:
  void require(const char* what) const;

  const dynamics::MoreauJean& _scheme;
  bool _root;
  std::vector<double> _u, _v, _u_tangent;
  /// The internal variables, now and of the kept tangent, gathered by
  /// cell when distributed (else the scheme's own copies are whole)
  std::vector<double> _internal, _internal_tangent;
};

} // namespace softpack::io
