#pragma once

#include "contact_domains.h"
#include "distribution.h"
#include <bodies/BodySet.h>
#include <compliance/delassus.h>
#include <contact/problem.h>
#include <cstdint>
#include <detection/detection.h>
#include <detection/detection_3d.h>
#include <optional>
#include <span>
#include <vector>

namespace softpack::parallel
{

/// The parts of a step's contact problem that differ when the bodies are
/// spread over MPI ranks (docs/mpi_design.md): the detection by shares put
/// together in the serial order, W's rows of a rank's contacts from every
/// rank's blocks and the plan of its share of the contact solves, the free
/// velocities at the contact nodes, and the whole problem of an unsolved
/// solve. Serial, each is the plain computation, with no exchange.
class ContactExchange
{
public:
  explicit ContactExchange(Distribution distribution);
  // The contact solves' domains count into this object.
  ContactExchange(const ContactExchange&) = delete;
  ContactExchange& operator=(const ContactExchange&) = delete;

  /// The bodies over the ranks (writable: a rebalance moves bodies)
  const Distribution& distribution() const { return _dist; }
  Distribution& distribution() { return _dist; }
  /// What the domain-wise contact solves have sent so far (distributed)
  const ContactTraffic& traffic() const { return _traffic; }

  /// The contacts at the node coordinates x: each rank detects its local
  /// bodies' share (dynamics::detect_contacts) and the shares are put
  /// together in the serial order (dynamics::contact_order_key); with a
  /// periodic cell, against the images too
  std::vector<dynamics::Contact>
  detect(const bodies::BodySet& bodies, std::span<const double> x,
         const std::vector<dynamics::Wall>& walls,
         const dynamics::DetectionOptions& options,
         const dynamics::PeriodicCell* cell = nullptr) const;
  /// The contacts of a 3D run, as detect's: the local bodies' share
  /// (dynamics::detect_contacts_3d) put together in the serial order
  std::vector<dynamics::Contact3D>
  detect(const bodies::BodySet& bodies,
         std::span<const dynamics::BoundarySurface> surfaces,
         std::span<const double> x,
         const std::vector<dynamics::PlaneWall>& walls,
         const dynamics::DetectionOptions& options) const;
  /// W from the local bodies' blocks (dynamics::delassus_blocks) and the
  /// servo walls' couplings: when distributed, the rows of this rank's
  /// contacts only (a contact is its candidate body's), from the blocks of
  /// every rank's bodies, and the plan of this rank's share of the contact
  /// solves (domain)
  contact::DelassusMatrix
  delassus(const std::vector<dynamics::Contact>& contacts,
           std::vector<dynamics::DelassusBlock> blocks,
           std::span<const dynamics::WallCoupling> couplings);
  /// W of a 3D run whole on every rank, from every rank's blocks
  /// (dynamics::delassus_blocks<3> of its local bodies) gathered in the
  /// serial body order, and the servo walls' couplings (every rank's
  /// own, the whole contact list being on every rank): the 3D contact
  /// solve is not yet domain-wise, every rank solves the whole problem
  /// (docs/mpi_design.md, "3D runs")
  contact::DelassusMatrixD<3>
  delassus(std::size_t num_contacts,
           std::vector<dynamics::DelassusBlockD<3>> blocks,
           std::span<const dynamics::WallCouplingD<3>> couplings);
  /// This rank's share of the contact solves planned with the last W (null
  /// when serial)
  const contact::SweepDomain* domain() const
  {
    return _domains ? &_domains->domain() : nullptr;
  }
  /// Count the sweeps of a domain-wise contact solve
  void count_sweeps(int sweeps)
  {
    if (_domains)
      _traffic.sweeps += sweeps;
  }
  /// The problem with W's rows of every rank (a collective), to write an
  /// unsolved problem whole
  contact::FrictionContactProblem2D
  whole_problem(const contact::FrictionContactProblem2D& problem) const;
  /// The entries of the contact nodes (local nodes per body) of a node
  /// vector filled where each body is local, made whole on every rank
  void share_contact_nodes(
      const bodies::BodySet& bodies,
      const std::vector<std::vector<std::int32_t>>& contact_nodes,
      std::span<double> global) const;

private:
  /// A detection share (Contact or Contact3D) and the other ranks' put
  /// together in the serial order (contact_order_key): the whole list on
  /// every rank; the share itself when serial
  template <typename C>
  std::vector<C> in_serial_order(std::vector<C> share, int num_bodies) const;

  Distribution _dist;
  ContactTraffic _traffic;
  /// This rank's share of the step's contact solves (none when serial),
  /// planned with each W
  std::optional<ContactDomains> _domains;
};

} // namespace softpack::parallel
