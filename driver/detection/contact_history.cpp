#include "contact_history.h"

namespace softpack::dynamics
{

void ImpulseHistory::record(const std::vector<Contact>& contacts,
                            std::span<const double> R)
{
  _last.clear();
  for (std::size_t a = 0; a < contacts.size(); ++a)
    _last[contact_key(contacts[a])] = {R[2 * a], R[2 * a + 1]};
}

std::vector<double>
ImpulseHistory::warm_start(const std::vector<Contact>& contacts) const
{
  std::vector<double> R(2 * contacts.size(), 0.0);
  for (std::size_t a = 0; a < contacts.size(); ++a)
    if (auto it = _last.find(contact_key(contacts[a])); it != _last.end())
    {
      R[2 * a] = it->second[0];
      R[2 * a + 1] = it->second[1];
    }
  return R;
}

void ImpulseHistory::record(const std::vector<Contact3D>& contacts,
                            std::span<const double> R)
{
  _last_world.clear();
  for (std::size_t a = 0; a < contacts.size(); ++a)
  {
    const Contact3D& c = contacts[a];
    std::array<double, 3> world;
    for (int i = 0; i < 3; ++i)
      world[i] =
          R[3 * a] * c.n[i] + R[3 * a + 1] * c.t1[i] + R[3 * a + 2] * c.t2[i];
    _last_world[contact_key(c)] = world;
  }
}

std::vector<double>
ImpulseHistory::warm_start(const std::vector<Contact3D>& contacts) const
{
  std::vector<double> R(3 * contacts.size(), 0.0);
  for (std::size_t a = 0; a < contacts.size(); ++a)
  {
    const Contact3D& c = contacts[a];
    const auto it = _last_world.find(contact_key(c));
    if (it == _last_world.end())
      continue;
    const std::array<double, 3>& w = it->second;
    R[3 * a] = w[0] * c.n[0] + w[1] * c.n[1] + w[2] * c.n[2];
    R[3 * a + 1] = w[0] * c.t1[0] + w[1] * c.t1[1] + w[2] * c.t1[2];
    R[3 * a + 2] = w[0] * c.t2[0] + w[1] * c.t2[1] + w[2] * c.t2[2];
  }
  return R;
}

namespace
{
/// A map of impulses by contact key as (key, impulse) entries (the state
/// file's form), in the map's (key) order
template <std::size_t N>
std::vector<std::pair<std::array<int, 3>, std::array<double, N>>>
listed(const std::map<ContactKey, std::array<double, N>>& impulses)
{
  std::vector<std::pair<std::array<int, 3>, std::array<double, N>>> out;
  out.reserve(impulses.size());
  for (const auto& [key, R] : impulses)
    out.push_back({{std::get<0>(key), std::get<1>(key), std::get<2>(key)}, R});
  return out;
}

/// The map `listed` gave the entries of
template <std::size_t N>
void refill(
    std::map<ContactKey, std::array<double, N>>& impulses,
    const std::vector<std::pair<std::array<int, 3>, std::array<double, N>>>&
        entries)
{
  impulses.clear();
  for (const auto& [key, R] : entries)
    impulses[{key[0], key[1], key[2]}] = R;
}
} // namespace

std::vector<ImpulseHistory::Entry> ImpulseHistory::entries() const
{
  return listed(_last);
}

void ImpulseHistory::restore(const std::vector<Entry>& entries)
{
  refill(_last, entries);
}

std::vector<ImpulseHistory::Entry3D> ImpulseHistory::entries_3d() const
{
  return listed(_last_world);
}

void ImpulseHistory::restore(const std::vector<Entry3D>& entries)
{
  refill(_last_world, entries);
}

void ContactForceAverage::add_step(const std::vector<Contact>& contacts,
                                   std::span<const double> R,
                                   std::size_t num_walls, double h)
{
  _wall_impulse.resize(num_walls, {0, 0});
  for (std::size_t a = 0; a < contacts.size(); ++a)
  {
    const Contact& c = contacts[a];
    const std::array<double, 2> impulse = {
        R[2 * a] * c.n[0] + R[2 * a + 1] * c.t[0],
        R[2 * a] * c.n[1] + R[2 * a + 1] * c.t[1]};
    auto [it, added] = _index.try_emplace(contact_key(c), _sum.size());
    if (added)
      _sum.push_back({c, {0, 0}, 0});
    AveragedContactForce& s = _sum[it->second];
    s.contact = c;
    s.force[0] += impulse[0];
    s.force[1] += impulse[1];
    ++s.steps;
    if (c.wall >= 0)
    {
      // The wall receives the opposite of the candidate's impulse.
      _wall_impulse[c.wall][0] -= impulse[0];
      _wall_impulse[c.wall][1] -= impulse[1];
    }
  }
  _duration += h;
}

std::vector<AveragedContactForce> ContactForceAverage::contact_forces() const
{
  std::vector<AveragedContactForce> mean = _sum;
  if (_duration > 0)
    for (AveragedContactForce& m : mean)
      for (double& f : m.force)
        f /= _duration;
  return mean;
}

std::vector<std::array<double, 2>> ContactForceAverage::wall_forces() const
{
  std::vector<std::array<double, 2>> mean = _wall_impulse;
  if (_duration > 0)
    for (auto& f : mean)
      for (double& x : f)
        x /= _duration;
  return mean;
}

void ContactForceAverage::reset()
{
  _index.clear();
  _sum.clear();
  for (auto& f : _wall_impulse)
    f = {0, 0};
  _duration = 0;
}

} // namespace softpack::dynamics
