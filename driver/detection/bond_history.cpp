#include "bond_history.h"

#include <stdexcept>

namespace softpack::dynamics
{

void BondHistory::form(const FrictionTable& table,
                       const std::vector<Contact>& contacts)
{
  for (const Contact& c : contacts)
  {
    const Bond law = table.bond(c);
    if (law.tensile > 0 && c.gap <= law.distance)
      _gap.emplace(contact_key(c), c.gap);
  }
  _formed = true;
}

StepBonds BondHistory::intact(const std::vector<Contact>& contacts) const
{
  StepBonds step;
  if (_gap.empty())
    return step;
  for (std::size_t a = 0; a < contacts.size(); ++a)
  {
    const auto it = _gap.find(contact_key(contacts[a]));
    if (it == _gap.end())
      continue;
    step.contacts.push_back(static_cast<std::int32_t>(a));
    step.gap.push_back(it->second);
  }
  return step;
}

int BondHistory::keep_intact(const std::vector<Contact>& contacts,
                             const StepBonds& step,
                             std::span<const char> broken)
{
  if (broken.size() != step.contacts.size())
    throw std::invalid_argument("BondHistory: one flag per bond of the step");
  std::map<ContactKey, double> kept;
  for (std::size_t k = 0; k < step.contacts.size(); ++k)
    if (!broken[k])
      kept.emplace(contact_key(contacts[step.contacts[k]]), step.gap[k]);
  const int lost = static_cast<int>(_gap.size() - kept.size());
  _gap = std::move(kept);
  return lost;
}

std::vector<BondHistory::Entry> BondHistory::entries() const
{
  std::vector<Entry> out;
  out.reserve(_gap.size());
  for (const auto& [key, gap] : _gap)
    out.push_back(
        {{std::get<0>(key), std::get<1>(key), std::get<2>(key)}, gap});
  return out;
}

void BondHistory::restore(const std::vector<Entry>& entries, bool formed)
{
  _gap.clear();
  for (const auto& [key, gap] : entries)
    _gap.emplace(ContactKey{key[0], key[1], key[2]}, gap);
  _formed = formed;
}

} // namespace softpack::dynamics
