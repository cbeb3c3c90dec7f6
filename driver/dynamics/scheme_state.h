#pragma once
// The scheme's state between steps: what a state file holds and a run
// continues from.
#include "step_size.h"
#include <array>
#include <detection/bond_history.h>
#include <detection/contact_history.h>
#include <energy/energy_balance.h>
#include <vector>

namespace softpack::dynamics
{

/// Everything the time stepping carries from one step to the next: enough
/// to continue a run from where it was, exactly. With modified Newton the
/// kept iteration matrix is part of the state: the restore reassembles and
/// refactors it at the displacement it was assembled at, and the age and
/// the last iteration count make the resumed run take the same refactor
/// decisions as the uninterrupted one.
struct SchemeState
{
  double time = 0;
  long steps = 0;
  /// Global displacement and velocity
  std::vector<double> u, v;
  /// Each wall's current point
  std::vector<std::array<double, 2>> wall_points;
  /// Each wall's current velocity (a servo wall's is part of the state;
  /// empty: keep the walls' own)
  std::vector<std::array<double, 2>> wall_velocities;
  /// Last impulses (warm start) by (candidate body, node, antagonist key)
  std::vector<ImpulseHistory::Entry> reactions;
  /// The intact bonds (docs/contact_laws.md, law "bonded"), and whether
  /// bonds formed (false: they form at the first step after the restore)
  std::vector<BondHistory::Entry> bonds;
  bool bonds_formed = false;
  /// The energy accounts since the start of the run
  EnergyBalance energy;
  /// Steps since the last factorization of the iteration matrix (-1: none;
  /// the first step after the restore then refactors)
  int matrix_age = -1;
  /// Newton iterations of the last step (the early-refactor rule uses it)
  int last_iterations = 0;
  /// Global displacement at which the kept tangent was assembled (empty
  /// when matrix_age < 0)
  std::vector<double> u_tangent;
  /// The adaptive time step (h = 0: a state without one; the base step)
  StepSize::State step_size;
  /// A periodic cell's edge vectors a1, a2 and their rates (8 numbers;
  /// 4 in a state written before the rates were kept; empty: no cell)
  std::vector<double> cell;
  /// Each cell's internal variables (BodySet::internal_variables; empty:
  /// no law has any), and those the kept tangent was assembled with (empty
  /// unless both the tangent and the internal variables are)
  std::vector<double> internal, internal_tangent;
  /// The bodies' dimension. A 3D state has no 2D walls or reactions
  /// (wall_points, wall_velocities and reactions empty): its plane walls
  /// (Wall3D) and its warm start are the three below.
  int dim = 2;
  /// 3D: each plane wall's current point and velocity
  std::vector<std::array<double, 3>> wall_points_3d, wall_velocities_3d;
  /// 3D: the last impulses (warm start) in world components, by key
  std::vector<ImpulseHistory::Entry3D> reactions_3d;
};

} // namespace softpack::dynamics
