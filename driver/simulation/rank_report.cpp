#include "rank_report.h"

#include <algorithm>
#include <sys/resource.h>

namespace softpack::simulation
{

nlohmann::json rank_report(const parallel::Distribution& dist,
                           const parallel::ContactTraffic& contact)
{
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const parallel::Communicator& comm = dist.comm();
  const std::vector<int>& body_rank = dist.index_map().body_rank();
  constexpr std::size_t n = 7;
  const double mine[n] = {
      double(std::count(body_rank.begin(), body_rank.end(), comm.rank())),
      double(comm.bytes_sent()),
      double(comm.messages()),
      usage.ru_maxrss / 1024.0,
      double(contact.bytes),
      double(contact.messages),
      double(contact.sweeps)};
  const std::vector<double> all = comm.gather(mine);
  const char* keys[n] = {"bodies",      "bytes_sent",      "collectives",
                         "peak_rss_mb", "nlgs_bytes_sent", "nlgs_messages",
                         "nlgs_sweeps"};
  nlohmann::json report;
  for (std::size_t k = 0; k < n; ++k)
    report[keys[k]] = nlohmann::json::array();
  for (std::size_t r = 0; r < all.size() / n; ++r)
    for (std::size_t k = 0; k < n; ++k)
      report[keys[k]].push_back(k == 3 ? nlohmann::json(all[n * r + k])
                                       : nlohmann::json(long(all[n * r + k])));
  report["rebalances"] = dist.rebalances();
  report["bodies_moved"] = dist.bodies_moved();
  return report;
}

} // namespace softpack::simulation
