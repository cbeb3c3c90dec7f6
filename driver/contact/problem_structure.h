#pragma once

#include "problem.h"

#include <cstddef>
#include <vector>

namespace softpack::contact
{

/// What a contact problem's W couples, for choosing a solver strategy
/// (`softpack fclib --describe`): how strong its off-diagonal blocks are
/// and how well conditioned the sets of frictionless contacts that share a
/// body are (a body on a frictionless wall: would solving such a set at once
/// save sweeps?).
struct ProblemStructure
{
  std::size_t contacts = 0;
  std::size_t offdiagonal_blocks = 0;
  /// Off-diagonal blocks with \f$|W_{ab}| \ge \tau \sqrt{|W_{aa}|
  /// |W_{bb}|}\f$ (Frobenius norms), for each \f$\tau\f$ of
  /// `coupling_thresholds`
  std::vector<double> coupling_thresholds;
  std::vector<std::size_t> blocks_at_or_above;
  /// Frictionless contacts (mu = 0, no cohesion)
  std::size_t frictionless = 0;
  /// Their sets connected by W's stored blocks, and the sets' sizes
  std::size_t frictionless_sets = 0;
  std::size_t smallest_set = 0, largest_set = 0;
  /// The extreme eigenvalues over the sets of \f$D^{-1/2} W_{nn}
  /// D^{-1/2}\f$, W's normal block over a set scaled by its diagonal (the
  /// matrix a sweep of the set's normal reactions iterates on: eigenvalues
  /// near 1 mean a few sweeps solve it); sets larger than
  /// `largest_conditioned` are not counted
  double scaled_eigenvalue_min = 0, scaled_eigenvalue_max = 0;
  std::size_t largest_conditioned = 2000;
};

/// The structure of a problem (ProblemStructure), for the thresholds
/// 1e-9, 1e-8, ..., 1e-2
template <int D>
ProblemStructure problem_structure(const FrictionContactProblem<D>& problem);

} // namespace softpack::contact
