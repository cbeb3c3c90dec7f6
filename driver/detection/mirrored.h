#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace softpack::dynamics
{

/// Among contacts[first:] (one pair of bodies), drop a contact whose mirror
/// is already kept: node a of A near node b of B and node b near node a,
/// near_node(contact) naming the antagonist node the contact point is
/// close to (-1: none). The two are (nearly) the same constraint; keeping
/// both makes the contact problem degenerate and the NLGS slow, and one
/// suffices where the meshes face node to node. Either dimension.
template <typename C, typename NearNode>
void remove_mirrored(std::vector<C>& contacts, std::size_t first,
                     NearNode near_node)
{
  std::vector<std::array<std::int64_t, 2>> kept;
  auto end = std::remove_if(
      contacts.begin() + first, contacts.end(),
      [&](const C& c)
      {
        const std::int32_t b = near_node(c);
        if (b < 0)
          return false;
        const std::int64_t p =
            (std::int64_t(c.candidate_body) << 32) | c.candidate_node;
        const std::int64_t q = (std::int64_t(c.antagonist_body) << 32) | b;
        const std::array<std::int64_t, 2> key = {std::min(p, q),
                                                 std::max(p, q)};
        if (std::find(kept.begin(), kept.end(), key) != kept.end())
          return true;
        kept.push_back(key);
        return false;
      });
  contacts.erase(end, contacts.end());
}

} // namespace softpack::dynamics
