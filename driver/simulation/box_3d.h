#pragma once

#include <array>
#include <bodies/BodySet.h>
#include <detection/detection.h>
#include <dynamics/moreau_jean.h>
#include <io/driver_config.h>
#include <mpi.h>
#include <vector>

/// What a 3D run (scene.model.dimension = 3) adds to the time loop of
/// run_simulation.cpp, which is the same for both dimensions: the box as
/// six plane walls, its volume, the refusals of what 3D lacks, the walls'
/// forces averaged between outputs and the overlap measured at an output.
namespace softpack::simulation
{

/// Names of the two planes a 3D box adds to the four box walls of 2D.
inline const std::vector<std::string> box_planes_3d = {"base", "lid"};

/// The box of a 3D run as plane walls, in the order of their friction
/// parties (io::read_friction_table): driver.json's walls (left, right,
/// bottom, top: vertical planes, their point, normal and imposed velocity
/// in the x-y plane, z = 0), then the base (z = 0, normal +z) and the lid
/// (z = scene.box.height, normal -z), both fixed.
std::vector<dynamics::Wall3D> box_walls_3d(const io::DriverConfig& config);

/// The volume (x_right - x_left) (y_top - y_bottom) (z_lid - z_base) of
/// the box from its walls' current positions.
/// @throws std::runtime_error if a wall of box_walls_3d is missing
double box_volume(const std::vector<dynamics::Wall3D>& walls);

/// A bottom face lies on the base when its three nodes are within this of
/// z = 0 in the reference configuration (m): the scene stands its
/// cylinders on z = 0 exactly, up to rounding (as
/// softpack.analysis.solids.BASE_TOLERANCE)
inline constexpr double base_tolerance = 1e-9;

/// The base area fraction phi_base of a 3D run (docs/bodies_3d.md): the
/// bodies' boundary faces on the base in the reference configuration
/// (every node within base_tolerance of z = 0: the bottom faces of
/// standing cylinders), projected on the base plane in the current
/// configuration, over the box's plan (x_right - x_left) (y_top -
/// y_bottom) from its walls' current positions. What the experiment's
/// scanner saw through the glass: the area the bottom faces cover, whether
/// or not a face has lifted off the base.
double base_area_fraction(const bodies::BodySet& bodies,
                          const std::vector<dynamics::Wall3D>& walls);

/// Refuse what the 3D time loop lacks, naming driver.json and the key:
/// a periodic cell (cell.enabled), no box (scene.box.enabled).
/// @throws std::runtime_error
void check_3d_run(MPI_Comm comm, const io::DriverConfig& config);

/// The walls' forces of a 3D run averaged over the steps between two
/// outputs (the impulses over the interval's duration), as
/// dynamics::ContactForceAverage does for 2D walls.
class WallForceAverage3D
{
public:
  /// Add the step just done (MoreauJean::wall_forces_3d, time_step)
  void add_step(const dynamics::MoreauJean& scheme);
  /// Mean force on each of `num_walls` walls (zero if no step was added)
  std::vector<std::array<double, 3>> forces(std::size_t num_walls) const;
  /// Start a new interval
  void reset();

private:
  std::vector<std::array<double, 3>> _impulse;
  double _duration = 0;
};

/// The deepest overlap of the bodies now, m (0 if none): the deepest
/// negative gap of the node-to-face and node-to-wall contacts detected
/// (detect_contacts_3d) at the current configuration. Not independent of
/// the detection as the 2D check (overlap_check.h) is.
double max_overlap_depth_3d(const bodies::BodySet& bodies,
                            const std::vector<dynamics::Wall3D>& walls,
                            const dynamics::DetectionOptions& options);

} // namespace softpack::simulation
