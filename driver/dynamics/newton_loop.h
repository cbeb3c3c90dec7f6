#pragma once
// The Newton loop of one attempt at a Moreau–Jean step. Private to the
// scheme's implementation files.
#include "contact_tolerance.h"
#include "moreau_jean_step.h"

namespace softpack::dynamics
{

/// Newton iterations on the velocity of one attempt at a step (METHOD.md
/// §3): each iteration sets the displacement of the iterate, forms the
/// residual r = (M + h th C) v_k + h th (F_int(q_k) - F_ext) - b, solves the
/// contact problem at the free velocity v_k - Kbar^-1 r (NLGS), and updates
/// every local body with one solve each. It stops when the estimated error
/// of the iterate (MoreauJean's rule) is within the tolerance, when an
/// iterate is not finite, or at time.newton_max_iterations; the last
/// iterate becomes the scheme's velocity, its boundaries shared. When the
/// iterations stall after converged contact solves, the next solves are
/// given a smaller tolerance (ContactTolerance).
class NewtonLoop
{
public:
  NewtonLoop(MoreauJean& scheme, const MoreauJean::StepContacts& sc,
             const MoreauJean::StepStart& start,
             MoreauJean::StepProblem& problem, StepReport& report)
      : _s(scheme), _sc(sc), _start(start), _problem(problem), _report(report),
        _tolerance(scheme._nlgs.tolerance)
  {
  }

  /// Iterate; the iteration count and convergence go to the report
  void run();

private:
  using Vectors = BodyVectors;
  /// One iteration: vk <- v_{k+1} on the local bodies (the other entries
  /// zero); returns ||v_{k+1} - v_k||_inf over the local bodies
  double iteration(int k, std::vector<double>& vk);
  /// Newton residual of every local body at the iterate v_k
  Vectors residual(const Vectors& vk, const Vectors& f_int) const;
  /// The contact solve of an iteration: the new velocity v_k - Kbar^-1 (r -
  /// H R) of each local deformable body that carries a contact goes to
  /// v_new (the others' stay empty)
  void solve_contacts(const Vectors& vk, const Vectors& r, Vectors& v_new);
  /// The free velocity v_k - Kbar^-1 r of each local body that carries a
  /// contact (returned), read at its contact nodes into the scheme's
  /// contact-node work vector, shared, as the contacts' relative velocity
  Vectors free_velocity(const Vectors& vk, const Vectors& r,
                        std::vector<double>& U_free);
  /// NLGS on the problem at the free relative velocity; the reactions go
  /// to the scheme's impulses, an unsolved problem to the report
  void solve_problem(const std::vector<double>& U_free);
  /// The NLGS's outcome into the report (an unsolved 2D problem kept)
  void report_nlgs(const contact::NlgsResult& nlgs, std::vector<double> start);
  /// v = v_free + Kbar^-1 H R on the bodies that carry a contact (every
  /// rigid body moved with its impulse)
  void add_impulse_response(const Vectors& free, Vectors& v_new);

  MoreauJean& _s;
  const MoreauJean::StepContacts& _sc;
  const MoreauJean::StepStart& _start;
  MoreauJean::StepProblem& _problem;
  StepReport& _report;
  ContactTolerance _tolerance;
};

} // namespace softpack::dynamics
