#pragma once
// The options of the time stepping, and the detection's and contact
// solver's options derived from the contact parameters (the one place).
#include <contact/nlgs.h>
#include <detection/detection.h>
#include <detection/friction_table.h>
#include <softpack/parameters.h>

namespace softpack::dynamics
{

/// Options of the time stepping: the schema's sections (the structs
/// generated from schema/parameters.toml, with its defaults; the ranges are
/// checked against the schema when the scheme is built) and the velocity
/// scale of the Newton test, which is derived from the walls, not a
/// parameter.
struct MoreauJeanOptions
{
  /// Time step, theta, mass, Newton iterations, iteration-matrix reuse
  parameters::Time time;
  /// Friction, detection distances, the NLGS solver, the Delassus drop
  parameters::Contact contact;
  /// Rayleigh damping C = alpha M + beta K
  parameters::Damping damping;
  /// Velocity below which changes do not matter in the Newton test (the
  /// fastest wall speed); must be set, > 0
  double velocity_scale = 0;
  /// Friction coefficient of each contact by its pair of species (or
  /// species and wall); pairs it does not set: contact.friction
  FrictionTable friction;
  /// How a distributed run's bodies stay split (rebalance_tolerance)
  parameters::Parallel parallel;
};

/// The detection's options from the contact parameters (the one place).
DetectionOptions detection_options(const parameters::Contact& contact);

/// The contact solver's options from the contact parameters (the one
/// place; the solver's other options keep their defaults).
contact::NlgsOptions nlgs_options(const parameters::Contact& contact);

/// The options as given, after checking them against the schema's ranges
/// and choices (the generated reader, on the options as JSON): the scheme
/// has none of its own.
/// @throws std::runtime_error if an option is outside the schema's range
/// @throws std::invalid_argument if velocity_scale is not positive
const MoreauJeanOptions& checked(const MoreauJeanOptions& options);

} // namespace softpack::dynamics
