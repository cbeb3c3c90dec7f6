#pragma once

#include <nlohmann/json.hpp>
#include <parallel/contact_domains.h>
#include <parallel/distribution.h>

namespace softpack::simulation
{

/// Per rank (a collective: every rank calls it): its bodies, the bytes it
/// handed to collectives (before this call), their count, its peak
/// resident memory, and what its domain-wise contact solves sent (bytes,
/// messages, sweeps), as done.json's "mpi" entry.
nlohmann::json rank_report(const parallel::Distribution& dist,
                           const parallel::ContactTraffic& contact);

} // namespace softpack::simulation
