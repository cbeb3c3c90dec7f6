#pragma once
// What the parts of a Moreau–Jean step share (moreau_jean.cpp and
// newton_loop.cpp): the step's contacts and start, and the clock of
// the per-part timings. Private to the scheme's implementation files.
#include "moreau_jean.h"
#include <contact/bond.h>
#include <walls/servo_walls.h>

#include <chrono>

namespace softpack::dynamics
{

using clock = std::chrono::steady_clock;

inline double seconds_since(clock::time_point t0)
{
  return std::chrono::duration<double>(clock::now() - t0).count();
}

struct MoreauJean::StepContacts
{
  ContactOperator H;
  /// Gap part of the solver's normal velocity: g~/(h th) - U_n+
  std::vector<double> shift;
  /// Cohesion impulse of each contact (cohesion_impulses in
  /// detection/friction_table.h); empty when no pair is cohesive
  std::vector<double> cohesion;
  /// The step's intact bonds and their strengths (impulses); empty when
  /// none
  StepBonds bonds;
  std::vector<contact::BondStrength> bond_strength;
  /// Local nodes of each body that carry a contact term (unique)
  std::vector<std::vector<std::int32_t>> contact_nodes;
  /// The servo walls: their free velocity in H, their coupling in W
  ServoWalls servo;
  std::size_t size() const { return H.size(); }
};

struct MoreauJean::StepStart
{
  /// Global displacement and velocity at the start of the step
  std::vector<double> u_old, v_old;
  /// Per body: v-, F_ext, M v-, C v- and the known part b
  Vectors v_old_b, f_ext_b, Mv_old, Cv_old, known;
  /// Per body, in a cell with a mass-proportional damping: alpha M
  /// v_affine, the damping's pull toward the cell's affine field, held
  /// over the step (MoreauJean::affine_drag; empty otherwise)
  Vectors affine_drag;
};

struct MoreauJean::StepProblem
{
  /// The problem of a 2D run, or of a 3D one
  contact::FrictionContactProblem2D two;
  contact::FrictionContactProblem3D three;
  /// Its free velocity (D per contact)
  std::vector<double>& q(int dim) { return dim == 2 ? two.q : three.q; }
};

struct MoreauJean::Attempt
{
  StepReport report;
  StepContacts sc;
  StepStart start;
};

} // namespace softpack::dynamics
