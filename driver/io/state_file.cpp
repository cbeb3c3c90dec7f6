#include "state_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string_view>

namespace softpack::io
{
namespace
{
constexpr std::string_view magic = "softpack-state-9";
/// Layout 8 is layout 9 without the internal variables (read: none, and a
/// run whose law has them refuses it) and the viscous account (read: 0)
constexpr std::string_view magic_v8 = "softpack-state-8";
/// Layout 7 is layout 8 without the bonds (read: none formed, none intact)
/// and the bond account (read: 0)
constexpr std::string_view magic_v7 = "softpack-state-7";
/// Layout 6 is layout 7 without the periodic cell and its accounts (read:
/// no cell, cell_work and rewrap 0)
constexpr std::string_view magic_v6 = "softpack-state-6";
/// Layout 5 is layout 6 without the accounts at the adaptive step's window
/// start (read: that window is judged by its iterations alone) and without
/// the cohesion account (read: 0)
constexpr std::string_view magic_v5 = "softpack-state-5";
/// Layout 3 is layout 5 without the adaptive time step (read: the base step)
constexpr std::string_view magic_v3 = "softpack-state-3";
/// Layout 4 was written by a lever that was reverted (one more double)
constexpr std::string_view magic_v4 = "softpack-state-4";
constexpr std::string_view magic_v1 = "softpack-state-1";
constexpr std::string_view magic_v2 = "softpack-state-2";

/// FNV-1a, 64 bits: a checksum of the payload (detects flipped bytes and
/// truncation; not a cryptographic hash).
struct Fnv1a
{
  std::uint64_t h = 0xcbf29ce484222325ULL;
  void add(const void* p, std::size_t bytes)
  {
    const auto* c = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < bytes; ++i)
      h = (h ^ c[i]) * 0x100000001b3ULL;
  }
};

/// The energy accounts in file order.
std::array<double*, 10> energy_fields(dynamics::EnergyBalance& e)
{
  return {&e.wall_work,      &e.external_work, &e.kinetic, &e.kinetic0,
          &e.strain,         &e.strain0,       &e.damping, &e.friction,
          &e.contact_normal, &e.numerical};
}

template <typename T> void put(std::string& out, const T& x)
{
  out.append(reinterpret_cast<const char*>(&x), sizeof(T));
}

template <typename T> void put(std::string& out, const std::vector<T>& x)
{
  out.append(reinterpret_cast<const char*>(x.data()), sizeof(T) * x.size());
}

/// Reads a byte buffer; running past its end is a truncated file.
struct Reader
{
  const std::string& bytes;
  const std::filesystem::path& path;
  std::size_t at = 0;
  void get(void* p, std::size_t n)
  {
    if (n > bytes.size() - at)
      throw std::runtime_error(path.string() + ": state file is truncated");
    std::memcpy(p, bytes.data() + at, n);
    at += n;
  }
  template <typename T> T get()
  {
    T x;
    get(&x, sizeof(T));
    return x;
  }
};

/// The 3D section (a 3D state only; a 2D state ends before it): the
/// dimension, the counts of plane walls, of their velocities (0 or the
/// walls) and of reactions (int64), the walls' points and velocities (3
/// doubles each) and the reactions (3 int32 keys and the world impulse, 3
/// doubles, each)
void put_3d(std::string& out, const dynamics::SchemeState& s)
{
  const bool velocities =
      s.wall_velocities_3d.size() == s.wall_points_3d.size();
  put(out, static_cast<std::int64_t>(3));
  put(out, static_cast<std::int64_t>(s.wall_points_3d.size()));
  put(out, static_cast<std::int64_t>(velocities ? s.wall_points_3d.size() : 0));
  put(out, static_cast<std::int64_t>(s.reactions_3d.size()));
  put(out, s.wall_points_3d);
  if (velocities)
    put(out, s.wall_velocities_3d);
  for (const auto& [key, R] : s.reactions_3d)
  {
    put(out, key);
    put(out, R);
  }
}

std::string payload(const dynamics::SchemeState& s, const StateIdentity& id,
                    const RunChecks& c)
{
  std::string out(magic);
  // Sized once: grown by doubling, the buffer would reach twice the state
  // (rank 0's largest allocation at an output of a distributed run)
  out.reserve(4096 +
              sizeof(double) * (s.u.size() + s.v.size() + s.u_tangent.size() +
                                4 * s.wall_points.size()) +
              s.reactions.size() * sizeof(dynamics::ImpulseHistory::Entry) +
              s.reactions_3d.size() *
                  sizeof(dynamics::ImpulseHistory::Entry3D));
  put(out, id.mesh);
  put(out, id.walls);
  const bool velocities = s.wall_velocities.size() == s.wall_points.size();
  put(out, static_cast<std::int64_t>(s.u.size()));
  put(out, static_cast<std::int64_t>(s.wall_points.size()));
  put(out, static_cast<std::int64_t>(s.reactions.size()));
  put(out, static_cast<std::int64_t>(velocities ? s.wall_points.size() : 0));
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
  if (velocities)
    put(out, s.wall_velocities);
  for (long n :
       {c.total.newton_unconverged_steps, c.total.nlgs_unconverged_steps,
        c.problems_written, c.problems_not_written})
    put(out, static_cast<std::int64_t>(n));
  put(out, c.max_overlap_depth);
  put(out, static_cast<std::int64_t>(c.overlap_steps));
  // The kept iteration matrix: its age, the last iteration count and the
  // displacement it was assembled at (none when there is no matrix).
  const bool tangent = s.matrix_age >= 0 && s.u_tangent.size() == s.u.size();
  put(out, static_cast<std::int64_t>(tangent ? s.matrix_age : -1));
  put(out, static_cast<std::int64_t>(s.last_iterations));
  put(out, static_cast<std::int64_t>(tangent ? s.u_tangent.size() : 0));
  if (tangent)
    put(out, s.u_tangent);
  // The adaptive time step (layout 5) and its window's start (6).
  put(out, s.step_size.h);
  put(out, static_cast<std::int64_t>(s.step_size.calm_steps));
  put(out, static_cast<std::int64_t>(s.step_size.window_iterations));
  put(out, static_cast<std::int64_t>(c.total.retried_steps));
  // The adaptive step's window start and the cohesion account (layout 6).
  put(out, s.step_size.window_start.residual);
  put(out, s.step_size.window_start.supplied);
  put(out, s.energy.cohesion);
  // The periodic cell and its accounts (layout 7)
  put(out, s.energy.cell_work);
  put(out, s.energy.rewrap);
  put(out, static_cast<std::int64_t>(s.cell.size()));
  put(out, s.cell);
  // The bonds (layout 8): formed or not, the intact ones, their account.
  put(out, static_cast<std::int64_t>(s.bonds_formed ? 1 : 0));
  put(out, static_cast<std::int64_t>(s.bonds.size()));
  for (const auto& [key, gap] : s.bonds)
  {
    put(out, key);
    put(out, gap);
  }
  put(out, s.energy.bond);
  // The internal variables (layout 9): the viscous account, each cell's,
  // and those of the kept tangent.
  put(out, s.energy.viscous);
  put(out, static_cast<std::int64_t>(s.internal.size()));
  put(out, s.internal);
  put(out, static_cast<std::int64_t>(s.internal_tangent.size()));
  put(out, s.internal_tangent);
  if (s.dim == 3)
    put_3d(out, s);
  return out;
}

/// Check the magic and the checksum of a whole file's bytes.
void check_layout(const std::string& bytes, const std::filesystem::path& path)
{
  const std::string_view head(bytes.data(),
                              std::min(bytes.size(), magic.size()));
  if (head == magic_v1)
    throw std::runtime_error(
        path.string() + ": state layout softpack-state-1 (no checksum, no "
                        "identity of its mesh) is no longer read: rerun the "
                        "run that wrote it");
  if (head == magic_v2)
    throw std::runtime_error(
        path.string() + ": state layout softpack-state-2 (without the kept "
                        "iteration matrix, so not resumable exactly) is no "
                        "longer read: rerun the run that wrote it");
  if (head == magic_v4)
    throw std::runtime_error(
        path.string() + ": state layout softpack-state-4 (written by a "
                        "driver of 2026-11-30 whose lever was reverted) is "
                        "not read: rerun the run that wrote it");
  if (head != magic && head != magic_v8 && head != magic_v7 &&
      head != magic_v6 && head != magic_v5 && head != magic_v3)
    throw std::runtime_error(path.string() + ": not a softpack state file");
  if (bytes.size() < magic.size() + sizeof(std::uint64_t))
    throw std::runtime_error(path.string() + ": state file is truncated");
  const std::size_t n = bytes.size() - sizeof(std::uint64_t);
  Fnv1a sum;
  sum.add(bytes.data(), n);
  std::uint64_t stored;
  std::memcpy(&stored, bytes.data() + n, sizeof(stored));
  if (stored != sum.h)
    throw std::runtime_error(path.string() +
                             ": state file checksum mismatch (the file is "
                             "truncated or corrupted)");
}
void check_identity(const std::filesystem::path& path,
                    const StateIdentity& found, const StateIdentity& expected)
{
  if (found.mesh != expected.mesh)
    throw std::runtime_error(
        path.string() + ": the state belongs to another mesh or packing "
                        "(its reference coordinates or cell-to-body tags "
                        "differ from this run's): start from a state written "
                        "by this run");
  if (found.walls != expected.walls)
    throw std::runtime_error(path.string() +
                             ": the state belongs to other walls (their "
                             "initial points or normals differ from this "
                             "run's driver.json)");
}
} // namespace

namespace
{
/// The identity's hashes: of the mesh and packing, and of the walls'
/// points and normals (2 or 3 components each)
template <typename W>
StateIdentity identity_of(const bodies::BodySet& bodies,
                          const std::vector<W>& walls)
{
  StateIdentity id;
  Fnv1a mesh;
  const std::span<const double> X = bodies.reference_coordinates();
  mesh.add(X.data(), X.size_bytes());
  const std::vector<int>& tags = bodies.cell_body();
  mesh.add(tags.data(), tags.size() * sizeof(int));
  id.mesh = mesh.h;
  Fnv1a lines;
  for (const W& w : walls)
  {
    lines.add(w.point.data(), sizeof(w.point));
    lines.add(w.normal.data(), sizeof(w.normal));
  }
  id.walls = lines.h;
  return id;
}
} // namespace

StateIdentity state_identity(const bodies::BodySet& bodies,
                             const std::vector<dynamics::Wall>& walls)
{
  return identity_of(bodies, walls);
}

StateIdentity state_identity(const bodies::BodySet& bodies,
                             const std::vector<dynamics::Wall3D>& walls)
{
  return identity_of(bodies, walls);
}

void write_state(const std::filesystem::path& path,
                 const dynamics::SchemeState& s, const StateIdentity& id,
                 const RunChecks& checks)
{
  std::string bytes = payload(s, id, checks);
  Fnv1a sum;
  sum.add(bytes.data(), bytes.size());
  put(bytes, sum.h);
  const std::filesystem::path tmp = path.string() + ".tmp";
  errno = 0;
  bool written = false;
  {
    std::ofstream out(tmp, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush(); // a full disk shows here or at close, not at write
    out.close();
    written = !out.fail();
  }
  if (!written)
  {
    const int error = errno;
    std::error_code ignored; // the partial file goes; the last state stands
    std::filesystem::remove(tmp, ignored);
    throw std::runtime_error(
        "cannot write " + path.string() + ": " +
        (error ? std::strerror(error) : "the write failed") +
        " (the state file of the previous output step is kept)");
  }
  std::filesystem::rename(tmp, path);
}

namespace
{
/// The run's checks as the state file keeps them (totals of the whole run)
void read_checks(Reader& r, RunChecks& c)
{
  for (long* n :
       {&c.total.newton_unconverged_steps, &c.total.nlgs_unconverged_steps,
        &c.problems_written, &c.problems_not_written})
    *n = r.get<std::int64_t>();
  c.max_overlap_depth = r.get<double>();
  c.overlap_steps = r.get<std::int64_t>();
}
/// The bonds of layout 8 (docs/contact_laws.md, law "bonded")
void read_bonds(Reader& r, dynamics::SchemeState& s, std::size_t bytes)
{
  const auto formed = r.get<std::int64_t>(), nb = r.get<std::int64_t>();
  if ((formed != 0 && formed != 1) || nb < 0 || nb > std::int64_t(bytes))
    throw std::runtime_error(r.path.string() + ": state file has bad sizes");
  s.bonds_formed = formed == 1;
  s.bonds.resize(nb);
  for (auto& [key, gap] : s.bonds)
  {
    r.get(key.data(), sizeof(key));
    gap = r.get<double>();
  }
  s.energy.bond = r.get<double>();
}
/// The internal variables of layout 9 (docs/materials.md)
void read_internal(Reader& r, dynamics::SchemeState& s, std::size_t bytes)
{
  s.energy.viscous = r.get<double>();
  for (std::vector<double>* v : {&s.internal, &s.internal_tangent})
  {
    const auto n = r.get<std::int64_t>();
    if (n < 0 || n > std::int64_t(bytes))
      throw std::runtime_error(r.path.string() + ": state file has bad sizes");
    v->resize(n);
    r.get(v->data(), sizeof(double) * n);
  }
}
/// The 3D section of layout 9 (put_3d)
void read_3d(Reader& r, dynamics::SchemeState& s, std::size_t bytes)
{
  const auto dim = r.get<std::int64_t>(), nw = r.get<std::int64_t>(),
             nv = r.get<std::int64_t>(), nr = r.get<std::int64_t>();
  if (dim != 3 || nw < 0 || (nv != 0 && nv != nw) || nr < 0 ||
      nw > std::int64_t(bytes) || nr > std::int64_t(bytes) ||
      !s.wall_points.empty() || !s.reactions.empty())
    throw std::runtime_error(r.path.string() + ": state file has bad sizes");
  s.dim = 3;
  s.wall_points_3d.resize(nw);
  s.wall_velocities_3d.resize(nv);
  s.reactions_3d.resize(nr);
  r.get(s.wall_points_3d.data(), sizeof(double) * 3 * nw);
  r.get(s.wall_velocities_3d.data(), sizeof(double) * 3 * nv);
  for (auto& [key, R] : s.reactions_3d)
  {
    r.get(key.data(), sizeof(key));
    r.get(R.data(), sizeof(R));
  }
}
} // namespace

StateFile read_state_file(const std::filesystem::path& path,
                          const StateIdentity* expected)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw std::runtime_error(path.string() + ": cannot open the state file");
  const std::string bytes((std::istreambuf_iterator<char>(in)),
                          std::istreambuf_iterator<char>());
  check_layout(bytes, path);
  Reader r{bytes, path, magic.size()};
  StateFile f;
  f.identity.mesh = r.get<std::uint64_t>();
  f.identity.walls = r.get<std::uint64_t>();
  const auto n = r.get<std::int64_t>(), nw = r.get<std::int64_t>(),
             nr = r.get<std::int64_t>(), nv = r.get<std::int64_t>();
  if (n < 0 || nw < 0 || nr < 0 || (nv != 0 && nv != nw) ||
      n > std::int64_t(bytes.size()) || nr > std::int64_t(bytes.size()))
    throw std::runtime_error(path.string() + ": state file has bad sizes");
  dynamics::SchemeState& s = f.state;
  s.time = r.get<double>();
  s.steps = r.get<std::int64_t>();
  s.u.resize(n);
  s.v.resize(n);
  s.wall_points.resize(nw);
  s.reactions.resize(nr);
  r.get(s.u.data(), sizeof(double) * n);
  r.get(s.v.data(), sizeof(double) * n);
  r.get(s.wall_points.data(), sizeof(double) * 2 * nw);
  for (auto& [key, R] : s.reactions)
  {
    r.get(key.data(), sizeof(key));
    r.get(R.data(), sizeof(R));
  }
  for (double* x : energy_fields(s.energy))
    r.get(x, sizeof(double));
  s.wall_velocities.resize(nv);
  r.get(s.wall_velocities.data(), sizeof(double) * 2 * nv);
  RunChecks& c = f.checks;
  read_checks(r, c);
  s.matrix_age = static_cast<int>(r.get<std::int64_t>());
  s.last_iterations = static_cast<int>(r.get<std::int64_t>());
  const auto nt = r.get<std::int64_t>();
  if ((nt != 0 && nt != n) || (nt > 0) != (s.matrix_age >= 0 && n > 0))
    throw std::runtime_error(path.string() + ": state file has bad sizes");
  s.u_tangent.resize(nt);
  r.get(s.u_tangent.data(), sizeof(double) * nt);
  const std::string_view head(bytes.data(), magic.size());
  if (head != magic_v3)
  {
    s.step_size.h = r.get<double>();
    s.step_size.calm_steps = static_cast<int>(r.get<std::int64_t>());
    s.step_size.window_iterations = static_cast<int>(r.get<std::int64_t>());
    c.total.retried_steps = r.get<std::int64_t>();
  }
  const bool v8 = head == magic || head == magic_v8;
  if (v8 || head == magic_v7 || head == magic_v6)
  {
    s.step_size.window_start.residual = r.get<double>();
    s.step_size.window_start.supplied = r.get<double>();
    s.energy.cohesion = r.get<double>();
  }
  if (v8 || head == magic_v7)
  {
    s.energy.cell_work = r.get<double>();
    s.energy.rewrap = r.get<double>();
    const auto nc = r.get<std::int64_t>();
    // (9: a cell with the isotropic mode's V, [cell] control_mean)
    if (nc != 0 && nc != 4 && nc != 8 && nc != 9)
      throw std::runtime_error(path.string() + ": state file has bad sizes");
    s.cell.resize(nc);
    r.get(s.cell.data(), sizeof(double) * nc);
  }
  if (v8)
    read_bonds(r, s, bytes.size());
  if (head == magic)
    read_internal(r, s, bytes.size());
  // (a 2D state ends here; a 3D one has its section: put_3d)
  if (head == magic && r.at + sizeof(std::uint64_t) < bytes.size())
    read_3d(r, s, bytes.size());
  if (r.at + sizeof(std::uint64_t) != bytes.size())
    throw std::runtime_error(path.string() + ": state file has bad sizes");
  if (expected)
    check_identity(path, f.identity, *expected);
  return f;
}

dynamics::SchemeState read_state(const std::filesystem::path& path)
{
  return read_state_file(path).state;
}

dynamics::SchemeState read_state(const std::filesystem::path& path,
                                 const StateIdentity& expected)
{
  return read_state_file(path, &expected).state;
}

} // namespace softpack::io
