#include "material_defaults.h"

#include <algorithm>
#include <stdexcept>

namespace softpack::forms
{

ParameterValues with_defaults(std::string_view law, ParameterValues given)
{
  const std::span<const ParameterDefault> rules = parameter_defaults(law);
  if (rules.empty())
    throw std::invalid_argument("unknown material '" + std::string(law) +
                                "': no declared defaults");
  std::vector<const ParameterDefault*> pending;
  for (const ParameterDefault& rule : rules)
    if (!given.contains(rule.name))
      pending.push_back(&rule);
  while (!pending.empty())
  {
    // the defaults whose names are all known; at least one each round
    const auto ready = std::stable_partition(
        pending.begin(), pending.end(),
        [&](const ParameterDefault* rule)
        {
          return !std::all_of(rule->uses.begin(), rule->uses.end(),
                              [&](const std::string& name)
                              { return given.contains(name); });
        });
    if (ready == pending.end())
      throw std::invalid_argument("material " + std::string(law) +
                                  ": defaults that refer to each other or to "
                                  "unknown names");
    for (auto it = ready; it != pending.end(); ++it)
      given[(*it)->name] = (*it)->value(given);
    pending.erase(ready, pending.end());
  }
  return given;
}

} // namespace softpack::forms
