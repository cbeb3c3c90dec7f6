#pragma once

#include "DelassusMatrix.h"
#include <cstdint>
#include <span>
#include <vector>

namespace softpack::contact
{

/// How one domain of a distributed contact problem takes part in a sweep
/// of the domain-wise NLGS (docs/mpi_design.md), from the rows of W of its
/// own contacts (the only rows a domain holds) and the graph of which
/// domains neighbour which.
///
/// A domain's contacts are split into its *interior* (no Delassus block
/// with another domain's contact, either way) and its *interface*. The
/// domains are coloured so that two domains linked by a block have
/// different colours (greedy, in domain order). A sweep is then:
/// - stage 0: every domain sweeps its interior, all at once (they are
///   independent);
/// - stage 1 + c: the domains of colour c sweep their interface (same
///   colour: not linked), then send the new reactions to the neighbours
///   that read them.
/// The contacts of one of W's rank-one terms (DelassusMatrix::RankOne)
/// read one another as if each pair had a block: those of a term held by
/// several domains are interface contacts, sent to every domain holding
/// some of its contacts.
/// This is the serial Gauss–Seidel sweep in one global order (interiors,
/// then the interfaces colour by colour), so it converges as the serial
/// NLGS does. The block-Jacobi alternative (every domain at once with its
/// neighbours' reactions of the previous sweep) diverged on the FCLIB
/// 2020-contact granular problem split in three (tests/cpp/contact/
/// test_nlgs_domains.cpp).
struct DomainPlan
{
  /// The domain this plan is for, and the colour of every domain
  int domain = 0;
  std::vector<int> colour;
  /// Number of colours (the same on every domain)
  int colours = 0;
  /// This domain's contacts by stage (1 + colours stages; the interface
  /// in stage 1 + its colour, nothing in the other interface stages)
  std::vector<std::vector<std::int32_t>> stages;
  /// A neighbouring domain: the contacts of this one it reads (received
  /// after its stage), and those of this one it reads (sent after ours),
  /// both in increasing order
  struct Link
  {
    int domain;
    std::vector<std::int32_t> send, receive;
  };
  std::vector<Link> links;

  /// Interface contacts sent per sweep (counted once per reader)
  std::size_t sent_per_sweep() const;
};

/// The domains that domain `me`'s rows of W read (contact a owned by
/// owner[a]), in increasing order: with W's pattern symmetric, also those
/// that read `me`'s contacts.
std::vector<int> neighbour_domains(const DelassusMatrix& W,
                                   std::span<const int> owner, int me);

/// The plan of domain `me`, contact a owned by owner[a].
/// @param[in] W The rows of `me`'s contacts (others may be empty); its
/// pattern must be symmetric (W_ab stored iff W_ba is, as
/// dynamics::delassus_blocks keeps them), so that what `me` sends follows
/// from what it reads
/// @param[in] graph Every domain's neighbour_domains, the same on every
/// domain (the colours must agree)
DomainPlan plan_domain(const DelassusMatrix& W, std::span<const int> owner,
                       int me, const std::vector<std::vector<int>>& graph);

} // namespace softpack::contact
