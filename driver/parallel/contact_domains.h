#pragma once

#include <contact/DelassusMatrix.h>
#include <contact/domain_plan.h>
#include <contact/nlgs.h>
#include <cstddef>
#include <mpi.h>
#include <parallel/communicator.h>
#include <span>
#include <vector>

namespace softpack::parallel
{

/// What the domain-wise contact solves of a run have sent, per rank.
struct ContactTraffic
{
  std::size_t bytes = 0;    ///< reactions and sums handed to MPI
  std::size_t messages = 0; ///< point-to-point messages and allreduces
  std::size_t sweeps = 0;   ///< sweeps (one allreduce each)
};

/// The domain-wise NLGS over MPI ranks (docs/mpi_design.md): a rank is a
/// domain of contact::DomainPlan; after each interface stage the ranks of
/// that stage's colour send the new reactions of their interface contacts
/// to the neighbours that read them (point to point), and each sweep's
/// sums go through one allreduce. A rank holds W's rows of its own contacts
/// only; W's pattern being symmetric, both ends of every message derive the
/// same lists from their own rows, and one allgather of every rank's
/// neighbours gives all the same colours.
class ContactDomains
{
public:
  /// @param[in] own The ranks (one domain each)
  /// @param[in] W The step's Delassus operator: at least the rows of this
  /// rank's contacts, its pattern symmetric (contact::plan_domain)
  /// @param[in] owner The rank owning each contact
  /// @param[in,out] traffic Where the exchanges are counted
  ContactDomains(const Communicator& comm, const contact::DelassusMatrix& W,
                 std::span<const int> owner, ContactTraffic& traffic);
  // The solver's view points into this object.
  ContactDomains(const ContactDomains&) = delete;
  ContactDomains& operator=(const ContactDomains&) = delete;

  /// The solver's view (contact::solve_nlgs); valid while this lives
  const contact::SweepDomain& domain() const { return _domain; }

  /// The plan (stages, colours, links)
  const contact::DomainPlan& plan() const { return _plan; }

private:
  void exchange(int stage, std::span<double> r);
  void reduce(std::span<double> values);
  void gather(std::span<double> x);

  MPI_Comm _comm;
  contact::DomainPlan _plan;
  ContactTraffic& _traffic;
  contact::SweepDomain _domain;
};

} // namespace softpack::parallel
