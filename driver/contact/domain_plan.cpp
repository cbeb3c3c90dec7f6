#include "domain_plan.h"

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

namespace softpack::contact
{

namespace
{
/// Greedy colouring of the domains' graph, in domain order.
std::vector<int> colour_domains(const std::vector<std::set<int>>& neighbours)
{
  std::vector<int> colour(neighbours.size(), -1);
  for (std::size_t d = 0; d < neighbours.size(); ++d)
  {
    std::set<int> taken;
    for (const int e : neighbours[d])
      if (colour[e] >= 0)
        taken.insert(colour[e]);
    int c = 0;
    while (taken.count(c))
      ++c;
    colour[d] = c;
  }
  return colour;
}

void sort_unique(std::vector<std::int32_t>& v)
{
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}
} // namespace

std::size_t DomainPlan::sent_per_sweep() const
{
  std::size_t n = 0;
  for (const Link& link : links)
    n += link.send.size();
  return n;
}

DomainPlan plan_domain(const DelassusMatrix& W, std::span<const int> owner,
                       int domains, int me)
{
  const std::size_t n = W.num_contacts();
  if (owner.size() != n)
    throw std::invalid_argument("plan_domain: one owner per contact");
  std::vector<std::set<int>> neighbours(domains);
  std::vector<char> interface(n, 0);
  // Row a reads r_b for each stored block W_ab.
  std::map<int, DomainPlan::Link> links;
  for (std::size_t a = 0; a < n; ++a)
    for (const std::int32_t b : W.row_columns(a))
    {
      const int da = owner[a], db = owner[b];
      if (da == db)
        continue;
      neighbours[da].insert(db);
      neighbours[db].insert(da);
      interface[a] = interface[b] = 1;
      if (da == me)
        links[db].receive.push_back(b);
      else if (db == me)
        links[da].send.push_back(b);
    }
  DomainPlan plan;
  plan.domain = me;
  plan.colour = colour_domains(neighbours);
  plan.colours = domains > 0 ? 1 + *std::max_element(plan.colour.begin(),
                                                     plan.colour.end())
                             : 0;
  plan.stages.resize(1 + plan.colours);
  for (std::size_t a = 0; a < n; ++a)
    if (owner[a] == me)
      plan.stages[interface[a] ? 1 + plan.colour[me] : 0].push_back(
          static_cast<std::int32_t>(a));
  for (auto& [domain, link] : links)
  {
    link.domain = domain;
    sort_unique(link.send);
    sort_unique(link.receive);
    plan.links.push_back(std::move(link));
  }
  return plan;
}

} // namespace softpack::contact
