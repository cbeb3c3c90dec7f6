#include "contact_domains.h"

#include <algorithm>

namespace softpack::parallel
{

namespace
{
/// Every rank's neighbour_domains, on every rank
std::vector<std::vector<int>> domain_graph(const Communicator& comm,
                                           const contact::DelassusMatrix& W,
                                           std::span<const int> owner)
{
  const std::vector<int> mine =
      contact::neighbour_domains(W, owner, comm.rank());
  const int n = static_cast<int>(mine.size());
  const std::vector<int> counts = comm.gather_items<int>({&n, 1});
  const std::vector<int> all = comm.gather_items<int>(mine);
  std::vector<std::vector<int>> graph(comm.size());
  auto next = all.begin();
  for (int r = 0; r < comm.size(); ++r)
  {
    graph[r].assign(next, next + counts[r]);
    next += counts[r];
  }
  return graph;
}
} // namespace

ContactDomains::ContactDomains(const Communicator& comm,
                               const contact::DelassusMatrix& W,
                               std::span<const int> owner,
                               ContactTraffic& traffic)
    : _comm(comm.comm()),
      _plan(contact::plan_domain(W, owner, comm.rank(),
                                 domain_graph(comm, W, owner))),
      _traffic(traffic)
{
  _domain.stages = _plan.stages;
  _domain.exchange = [this](int stage, std::span<double> r)
  { exchange(stage, r); };
  _domain.reduce = [this](std::span<double> values) { reduce(values); };
  _domain.gather = [this](std::span<double> x) { gather(x); };
}

void ContactDomains::exchange(int stage, std::span<double> r)
{
  // Stage 1 + c was swept by the domains of colour c: they send, their
  // neighbours receive. Both ends list a message's contacts in order.
  const int c = stage - 1;
  const bool sender = _plan.colour[_plan.domain] == c;
  std::vector<std::vector<double>> out(_plan.links.size()),
      in(_plan.links.size());
  std::vector<MPI_Request> requests;
  for (std::size_t k = 0; k < _plan.links.size(); ++k)
  {
    const contact::DomainPlan::Link& link = _plan.links[k];
    if (_plan.colour[link.domain] == c && !link.receive.empty())
    {
      in[k].resize(2 * link.receive.size());
      requests.emplace_back();
      MPI_Irecv(in[k].data(), static_cast<int>(in[k].size()), MPI_DOUBLE,
                link.domain, stage, _comm, &requests.back());
    }
    if (sender && !link.send.empty())
    {
      for (const std::int32_t b : link.send)
        out[k].insert(out[k].end(), {r[2 * b], r[2 * b + 1]});
      requests.emplace_back();
      MPI_Isend(out[k].data(), static_cast<int>(out[k].size()), MPI_DOUBLE,
                link.domain, stage, _comm, &requests.back());
      _traffic.bytes += out[k].size() * sizeof(double);
      ++_traffic.messages;
    }
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(),
              MPI_STATUSES_IGNORE);
  for (std::size_t k = 0; k < _plan.links.size(); ++k)
    for (std::size_t i = 0; i < in[k].size() / 2; ++i)
    {
      const std::int32_t b = _plan.links[k].receive[i];
      r[2 * b] = in[k][2 * i];
      r[2 * b + 1] = in[k][2 * i + 1];
    }
}

void ContactDomains::reduce(std::span<double> values)
{
  MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()),
                MPI_DOUBLE, MPI_SUM, _comm);
  _traffic.bytes += values.size() * sizeof(double);
  ++_traffic.messages;
}

void ContactDomains::gather(std::span<double> x)
{
  // Every owner's entries, summed into zeros elsewhere: exact.
  std::vector<double> all(x.size(), 0.0);
  for (const std::vector<std::int32_t>& stage : _plan.stages)
    for (const std::int32_t a : stage)
    {
      all[2 * a] = x[2 * a];
      all[2 * a + 1] = x[2 * a + 1];
    }
  MPI_Allreduce(MPI_IN_PLACE, all.data(), static_cast<int>(all.size()),
                MPI_DOUBLE, MPI_SUM, _comm);
  _traffic.bytes += all.size() * sizeof(double);
  ++_traffic.messages;
  std::copy(all.begin(), all.end(), x.begin());
}

} // namespace softpack::parallel
