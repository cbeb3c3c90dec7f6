#pragma once

#include "detection.h"
#include "detection_3d.h"
#include <array>
#include <map>
#include <span>
#include <tuple>
#include <utility>
#include <vector>

/// What the time stepping remembers of a contact from one step to the next.
namespace softpack::dynamics
{

/// Identity of a contact across time steps: (candidate body, candidate
/// node, antagonist body, or -1 - wall for a wall). The one key of the warm
/// start (ImpulseHistory) and of the force averaging (ContactForceAverage).
using ContactKey = std::tuple<int, int, int>;

inline ContactKey contact_key(const Contact& c)
{
  return {c.candidate_body, c.candidate_node,
          c.antagonist_body >= 0 ? c.antagonist_body : -1 - c.wall};
}

/// The same identity of a 3D contact
inline ContactKey contact_key(const Contact3D& c)
{
  return {c.candidate_body, c.candidate_node,
          c.antagonist_body >= 0 ? c.antagonist_body : -1 - c.wall};
}

/// The impulses of the last step by contact identity: the warm start of the
/// next step's contact solve.
class ImpulseHistory
{
public:
  /// One entry as stored in a state file: (candidate body, node, antagonist
  /// key) and the impulses (n, t)
  using Entry = std::pair<std::array<int, 3>, std::array<double, 2>>;
  /// A 3D entry: the key and the impulse in world components (x, y, z)
  using Entry3D = std::pair<std::array<int, 3>, std::array<double, 3>>;

  /// Replace the remembered impulses by those of a step.
  /// @param[in] contacts The step's contacts
  /// @param[in] R Their impulses, 2 per contact (n, t)
  void record(const std::vector<Contact>& contacts, std::span<const double> R);

  /// Starting impulses for a step's contacts: the previous step's impulses
  /// of a contact that persists, zero for a new one.
  /// @return 2 per contact (n, t)
  std::vector<double> warm_start(const std::vector<Contact>& contacts) const;

  /// 3D: the impulses are remembered in world coordinates (R_n n + R_t1 t1
  /// + R_t2 t2) and given back in the new frame: a contact's tangents
  /// turn with its normal, and the first tangent switches axis where the
  /// normal crosses a tie of contact_frame's rule
  /// @param[in] R 3 per contact (n, t1, t2)
  void record(const std::vector<Contact3D>& contacts,
              std::span<const double> R);
  /// @return 3 per contact (n, t1, t2): the remembered world impulse of a
  /// persisting contact in its new frame, zero for a new one
  std::vector<double> warm_start(const std::vector<Contact3D>& contacts) const;

  /// Every remembered contact, in key order (2D)
  std::vector<Entry> entries() const;

  /// Every remembered 3D contact (world impulses), in key order
  std::vector<Entry3D> entries_3d() const;

  /// Replace the remembered impulses by saved entries (see entries()).
  void restore(const std::vector<Entry>& entries);
  /// Replace the remembered 3D impulses by saved entries (entries_3d())
  void restore(const std::vector<Entry3D>& entries);

private:
  std::map<ContactKey, std::array<double, 2>> _last;
  /// 3D: world impulses
  std::map<ContactKey, std::array<double, 3>> _last_world;
};

/// A contact's force averaged over an interval of time steps.
struct AveragedContactForce
{
  /// The contact as last detected in the interval (frame, gap, segment)
  Contact contact;
  /// Mean force on the candidate, world frame: the impulses summed over the
  /// interval divided by its duration
  std::array<double, 2> force;
  /// Steps of the interval in which the contact was detected
  int steps;
};

/// Contact and wall forces averaged over the steps between two outputs.
///
/// With theta = 1/2 the Signorini condition on the predicted gap makes the
/// velocities of contact nodes alternate from one step to the next
/// (U+ = -U-), and the impulses with them: a single step's reactions are a
/// poor picture of the force a contact carries (a particle's resultant
/// can then reach 1 % of the piston force at rest). The mean impulse rate
/// over an interval is what a force sensor records and what the
/// observables (balance of particles, force-bearing contacts) need.
class ContactForceAverage
{
public:
  /// Add the impulses of a step just done (MoreauJean::contacts,
  /// impulses, the number of walls and the step's size h).
  void add_step(const std::vector<Contact>& contacts, std::span<const double> R,
                std::size_t num_walls, double h);

  /// Duration of the interval so far (s)
  double duration() const { return _duration; }

  /// Mean force of every contact seen in the interval, in order of first
  /// appearance. Empty if no step was added.
  std::vector<AveragedContactForce> contact_forces() const;

  /// Mean force received by each wall over the interval (zero if no step
  /// was added).
  std::vector<std::array<double, 2>> wall_forces() const;

  /// Start a new interval.
  void reset();

private:
  std::map<ContactKey, std::size_t> _index;
  std::vector<AveragedContactForce> _sum;
  std::vector<std::array<double, 2>> _wall_impulse;
  double _duration = 0;
};

} // namespace softpack::dynamics
