#include "moreau_jean_options.h"

#include <algorithm>
#include <omp.h>
#include <stdexcept>

namespace softpack::dynamics
{
namespace
{
/// Contact problems from this size on are swept in split order (nlgs.h).
constexpr std::size_t split_sweep_min_contacts = 256;
} // namespace

DetectionOptions detection_options(const parameters::Contact& contact)
{
  return {.alert_distance = contact.alert_distance,
          .max_penetration = contact.max_penetration};
}

contact::NlgsOptions nlgs_options(const parameters::Contact& contact)
{
  contact::NlgsOptions o;
  o.tolerance = contact.nlgs_tolerance;
  o.max_sweeps = contact.nlgs_max_sweeps;
  o.relaxation = contact.nlgs_relaxation;
  o.order = contact::sweep_order(contact.nlgs_order);
  o.update = contact::nlgs_update(contact.nlgs_update);
  o.extrapolation = contact::nlgs_extrapolation(contact.nlgs_extrapolation);
  // Large problems are swept in split order, on two threads when the
  // driver has them; the order depends on the problem's size only, so a
  // run gives the same answers on any number of threads or processes. Below a
  // few hundred contacts a sweep is too short to pay for its two
  // synchronizations.
  o.split_min_contacts = split_sweep_min_contacts;
  o.threads = std::min(omp_get_max_threads(), 2);
  return o;
}

const MoreauJeanOptions& checked(const MoreauJeanOptions& o)
{
  parameters::Time time;
  parameters::read(parameters::to_json(o.time), time, "MoreauJeanOptions");
  parameters::Contact contact;
  parameters::read(parameters::to_json(o.contact), contact,
                   "MoreauJeanOptions");
  parameters::Damping damping;
  parameters::read(parameters::to_json(o.damping), damping,
                   "MoreauJeanOptions");
  if (!(o.velocity_scale > 0))
    throw std::invalid_argument("MoreauJeanOptions: velocity_scale must be "
                                "positive (the fastest wall speed)");
  return o;
}

} // namespace softpack::dynamics
