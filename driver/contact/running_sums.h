#pragma once

#include "DelassusMatrix.h"

#include <vector>

namespace softpack::contact
{

/// The running sums of W's rank-one terms (DelassusMatrix::RankOne) over a
/// solve: made again from r at the start of every sweep (and after a
/// domain's exchange), so that their rounding does not pile up over the
/// sweeps, and updated after every local solve.
template <int D> class RunningSums
{
public:
  explicit RunningSums(const DelassusMatrixD<D>& W)
      : _W(W), _sums(W.rank_one_terms().size())
  {
  }
  /// The sums, null when W has no rank-one term
  double* data() { return _sums.empty() ? nullptr : _sums.data(); }
  /// Made again from r
  void reset(const double* r)
  {
    if (!_sums.empty())
      _W.rank_one_sums(r, _sums.data());
  }

private:
  const DelassusMatrixD<D>& _W;
  std::vector<double> _sums;
};

} // namespace softpack::contact
