#pragma once

#include "detection.h"
#include "moreau_jean.h"
#include <array>
#include <map>
#include <tuple>
#include <vector>

namespace softpack::dynamics
{

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
  /// Add the impulses of the step the scheme has just done.
  void add_step(const MoreauJean& scheme);

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
