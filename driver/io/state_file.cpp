#include "state_file.h"

#include <cstring>
#include <fstream>
#include <stdexcept>

namespace softpack::io
{
namespace
{
constexpr char magic[16] = {'s', 'o', 'f', 't', 'p', 'a', 'c', 'k',
                            '-', 's', 't', 'a', 't', 'e', '-', '1'};

/// The energy accounts in file order.
std::array<double*, 10> energy_fields(dynamics::EnergyBalance& e)
{
  return {&e.wall_work,      &e.external_work, &e.kinetic, &e.kinetic0,
          &e.strain,         &e.strain0,       &e.damping, &e.friction,
          &e.contact_normal, &e.numerical};
}

template <typename T> void put(std::ofstream& out, const T& x)
{
  out.write(reinterpret_cast<const char*>(&x), sizeof(T));
}

template <typename T> void put(std::ofstream& out, const std::vector<T>& x)
{
  out.write(reinterpret_cast<const char*>(x.data()), sizeof(T) * x.size());
}
} // namespace

void write_state(const std::filesystem::path& path,
                 const dynamics::SchemeState& s)
{
  const std::filesystem::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out)
      throw std::runtime_error("cannot write " + tmp.string());
    out.write(magic, sizeof(magic));
    put(out, static_cast<std::int64_t>(s.u.size()));
    put(out, static_cast<std::int64_t>(s.wall_points.size()));
    put(out, static_cast<std::int64_t>(s.reactions.size()));
    put(out, s.time);
    put(out, static_cast<std::int64_t>(s.steps));
    put(out, s.u);
    put(out, s.v);
    put(out, s.wall_points);
    for (const auto& [key, R] : s.reactions)
    {
      put(out, key);
      put(out, R);
    }
    dynamics::EnergyBalance e = s.energy;
    for (double* x : energy_fields(e))
      put(out, *x);
    // Appended (older files end before it): a servo wall's velocity is
    // state.
    if (s.wall_velocities.size() == s.wall_points.size())
      put(out, s.wall_velocities);
    if (!out)
      throw std::runtime_error("cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, path);
}

dynamics::SchemeState read_state(const std::filesystem::path& path)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw std::runtime_error(path.string() + ": cannot open the state file");
  auto get = [&](void* p, std::size_t bytes)
  {
    in.read(static_cast<char*>(p), static_cast<std::streamsize>(bytes));
    if (!in)
      throw std::runtime_error(path.string() + ": state file is truncated");
  };
  char head[sizeof(magic)];
  get(head, sizeof(head));
  if (std::memcmp(head, magic, sizeof(magic)) != 0)
    throw std::runtime_error(path.string() + ": not a softpack state file");
  std::int64_t n, nw, nr, steps;
  dynamics::SchemeState s;
  get(&n, sizeof(n));
  get(&nw, sizeof(nw));
  get(&nr, sizeof(nr));
  if (n < 0 || nw < 0 || nr < 0 || n > (std::int64_t(1) << 34))
    throw std::runtime_error(path.string() + ": state file has bad sizes");
  get(&s.time, sizeof(double));
  get(&steps, sizeof(steps));
  s.steps = steps;
  s.u.resize(n);
  s.v.resize(n);
  s.wall_points.resize(nw);
  s.reactions.resize(nr);
  get(s.u.data(), sizeof(double) * n);
  get(s.v.data(), sizeof(double) * n);
  get(s.wall_points.data(), sizeof(double) * 2 * nw);
  for (auto& [key, R] : s.reactions)
  {
    get(key.data(), sizeof(key));
    get(R.data(), sizeof(R));
  }
  for (double* x : energy_fields(s.energy))
    get(x, sizeof(double));
  // The walls' velocities, absent from files written before servo walls.
  std::vector<std::array<double, 2>> velocities(nw);
  const auto bytes = static_cast<std::streamsize>(sizeof(double) * 2 * nw);
  if (in.read(reinterpret_cast<char*>(velocities.data()), bytes) &&
      in.gcount() == bytes)
    s.wall_velocities = std::move(velocities);
  return s;
}

} // namespace softpack::io
