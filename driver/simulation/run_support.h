#pragma once

#include "box_3d.h"
#include <bodies/body_forces.h>
#include <dynamics/moreau_jean.h>
#include <filesystem>
#include <io/driver_config.h>
#include <io/raw_output.h>
#include <mpi.h>
#include <optional>
#include <string>

/// What the time loop of run_simulation.cpp uses beside its Run object,
/// for runs of either dimension: the stop criteria, the progress line, the
/// warnings' rate and the replay files of unsolved contact problems.
namespace softpack::simulation
{

/// Unsolved contact problems dumped at most (each can be megabytes): the
/// first ones show the failure; the rest are only counted (done.json).
inline constexpr long max_problem_dumps = 20;

/// The run's [gravity] acceleration in space (z = 0 when two components
/// are given); refuses, naming the file and key, a z component in a 2D run
/// (whose gravity acts in the plane).
bodies::Acceleration gravity(const io::DriverConfig& config);

/// The sum of the bodies' current areas (3D: volumes) over `space`, the
/// box's or the periodic cell's area (3D: the box's volume).
double packing_fraction(const bodies::BodySet& bodies, double space);

/// One progress line on stdout.
/// @param[in] fraction The fraction of the run done (0..1)
void print_progress(double fraction, long step,
                    const dynamics::MoreauJean& scheme,
                    std::optional<double> phi, const dynamics::StepReport& r,
                    double seconds);

/// Add the parts of a step's wall time to `sum`.
void add_timings(dynamics::StepTimings& sum, const dynamics::StepTimings& t);

/// A warning on stderr for the first unconverged step and every 100th
/// after it: a run that never converges must not flood the log.
bool warn_now(long count);

/// raw/failed_contact_problems/step_NNNNNNNN.hdf5 (FCLIB layout, replay
/// with ./softpack fclib, --dim 3 for a 3D run) when the step left a contact
/// problem unsolved.
void write_unsolved_problem(const std::filesystem::path& raw, long step,
                            const dynamics::StepReport& r);

/// This process's rank in `comm`.
int rank_of(MPI_Comm comm);

/// The stop criterion met after `step` (counted from `first`), or "":
/// stop.packing_fraction on `phi`, stop.base_area_fraction on
/// `phi_base` (3D runs), stop.max_time, stop.steps.
std::string stop_reason(const io::DriverConfig& config,
                        const dynamics::MoreauJean& scheme, long first,
                        long step, std::optional<double> phi,
                        std::optional<double> phi_base = std::nullopt);

/// Each body's Cauchy integral (bodies/stress_average.h), every body's
/// from its owner (a collective on a distributed run): 4 components per
/// body in 2D, 9 in 3D.
std::vector<double> body_cauchy(const dynamics::MoreauJean& scheme,
                                const bodies::BodySet& bodies);

/// Each wall's point now and its force averaged since the last output:
/// `average`'s for a 2D run, `average_3d`'s for a 3D one.
std::vector<io::WallRow> wall_rows(dynamics::MoreauJean& scheme,
                                   const dynamics::ContactForceAverage& average,
                                   const WallForceAverage3D& average_3d);

} // namespace softpack::simulation
