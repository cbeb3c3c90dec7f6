#include "domain_plan.h"

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

namespace softpack::contact
{

namespace
{
/// Greedy colouring of the domains' graph, in domain order; d and e are
/// linked when either lists the other.
std::vector<int> colour_domains(const std::vector<std::vector<int>>& graph)
{
  const std::size_t domains = graph.size();
  std::vector<std::set<int>> neighbours(domains);
  for (std::size_t d = 0; d < domains; ++d)
    for (const int e : graph[d])
    {
      if (e < 0 || static_cast<std::size_t>(e) >= domains)
        throw std::invalid_argument("plan_domain: a neighbour is no domain");
      neighbours[d].insert(e);
      neighbours[e].insert(static_cast<int>(d));
    }
  std::vector<int> colour(domains, -1);
  for (std::size_t d = 0; d < domains; ++d)
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

/// A rank-one term's contacts by domain: each of its contacts reads all the
/// others (through the term's sum), as if every pair had a block
std::map<int, std::vector<std::int32_t>>
term_by_domain(const DelassusMatrix::RankOne& term, std::span<const int> owner)
{
  std::map<int, std::vector<std::int32_t>> by_domain;
  for (const std::int32_t c : term.contacts)
    by_domain[owner[c]].push_back(c);
  return by_domain;
}

/// The links a rank-one term adds to domain `me`'s, and `me`'s contacts in
/// it marked interface (nothing unless `me` and another domain hold some of
/// its contacts)
void link_term(const DelassusMatrix::RankOne& term, std::span<const int> owner,
               int me, std::map<int, DomainPlan::Link>& links,
               std::vector<char>& interface)
{
  const auto by_domain = term_by_domain(term, owner);
  const auto mine = by_domain.find(me);
  if (mine == by_domain.end() or by_domain.size() < 2)
    return;
  for (const auto& [domain, contacts] : by_domain)
  {
    if (domain == me)
      continue;
    DomainPlan::Link& link = links[domain];
    link.receive.insert(link.receive.end(), contacts.begin(), contacts.end());
    link.send.insert(link.send.end(), mine->second.begin(), mine->second.end());
  }
  for (const std::int32_t c : mine->second)
    interface[c] = 1;
}
} // namespace

std::size_t DomainPlan::sent_per_sweep() const
{
  std::size_t n = 0;
  for (const Link& link : links)
    n += link.send.size();
  return n;
}

std::vector<int> neighbour_domains(const DelassusMatrix& W,
                                   std::span<const int> owner, int me)
{
  std::set<int> domains;
  for (std::size_t a = 0; a < owner.size(); ++a)
    if (owner[a] == me)
      for (const std::int32_t b : W.row_columns(a))
        if (owner[b] != me)
          domains.insert(owner[b]);
  for (const DelassusMatrix::RankOne& term : W.rank_one_terms())
  {
    const auto by_domain = term_by_domain(term, owner);
    if (by_domain.count(me))
      for (const auto& [domain, contacts] : by_domain)
        if (domain != me)
          domains.insert(domain);
  }
  return {domains.begin(), domains.end()};
}

DomainPlan plan_domain(const DelassusMatrix& W, std::span<const int> owner,
                       int me, const std::vector<std::vector<int>>& graph)
{
  const std::size_t n = W.num_contacts();
  if (owner.size() != n)
    throw std::invalid_argument("plan_domain: one owner per contact");
  const int domains = static_cast<int>(graph.size());
  DomainPlan plan;
  plan.domain = me;
  plan.colour = colour_domains(graph);
  plan.colours = domains > 0 ? 1 + *std::max_element(plan.colour.begin(),
                                                     plan.colour.end())
                             : 0;
  plan.stages.resize(1 + plan.colours);
  // Row a reads r_b for each stored block W_ab, and (the pattern being
  // symmetric) row b, owned by b's domain, reads r_a.
  std::map<int, DomainPlan::Link> links;
  std::vector<char> interface(n, 0);
  for (const DelassusMatrix::RankOne& term : W.rank_one_terms())
    link_term(term, owner, me, links, interface);
  for (std::size_t a = 0; a < n; ++a)
  {
    if (owner[a] != me)
      continue;
    for (const std::int32_t b : W.row_columns(a))
      if (owner[b] != me)
      {
        interface[a] = 1;
        links[owner[b]].receive.push_back(b);
        links[owner[b]].send.push_back(static_cast<std::int32_t>(a));
      }
    plan.stages[interface[a] ? 1 + plan.colour[me] : 0].push_back(
        static_cast<std::int32_t>(a));
  }
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
