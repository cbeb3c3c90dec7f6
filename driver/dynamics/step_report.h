#pragma once
// What one Moreau–Jean step did: read by the step-size control, the raw
// output and the run's warnings, not only by the integrator.
#include <contact/problem.h>
#include <memory>
#include <vector>

namespace softpack::dynamics
{

/// Wall time spent in each part of a step (s).
struct StepTimings
{
  double detection = 0, assembly = 0, factorization = 0, delassus = 0, nlgs = 0,
         solves = 0;
  double total() const
  {
    return detection + assembly + factorization + delassus + nlgs + solves;
  }
  StepTimings& operator+=(const StepTimings& o)
  {
    detection += o.detection;
    assembly += o.assembly;
    factorization += o.factorization;
    delassus += o.delassus;
    nlgs += o.nlgs;
    solves += o.solves;
    return *this;
  }
};

/// What one step did.
struct StepReport
{
  StepTimings seconds;
  /// The step's size (s)
  double time_step = 0;
  /// Attempts of this step abandoned (Newton or a contact solve failed) and
  /// started again at half the size (StepSize::retry); their time is in
  /// `seconds`
  int retries = 0;
  /// The iteration matrix was refactorized in this step
  bool refactorized = false;
  int newton_iterations = 0;
  bool newton_converged = false;
  /// A Newton iterate was not finite (an inverted element, a step too
  /// large): the iterations stopped there, the step is not taken
  bool newton_diverged = false;
  int nlgs_iterations = 0; ///< sweeps, summed over the Newton iterations
  double nlgs_error = 0;   ///< error of the last contact solve
  bool nlgs_converged = true;
  int contacts = 0;
  int active_contacts = 0;    ///< R_n > 0
  double max_penetration = 0; ///< max(-gap) at the end of the step, >= 0
  /// Contact solves of this step (one per Newton iteration) that did not
  /// converge: a writer of unsolved problems can bound what it keeps
  int unsolved_contact_solves = 0;
  /// Null when every contact solve of the step converged; otherwise the
  /// last unsolved problem exactly as it was given to the solver, to be
  /// replayed (e.g. written by contact::dump_problem): in 2D
  /// unsolved_problem, in 3D unsolved_problem_3d
  std::shared_ptr<const contact::FrictionContactProblem2D> unsolved_problem;
  std::shared_ptr<const contact::FrictionContactProblem3D> unsolved_problem_3d;
  /// The reactions that solve started from (its warm start; with the
  /// unsolved problem, it reproduces the failure bit for bit)
  std::vector<double> unsolved_start;
  /// An unsolved problem is kept (of either dimension)
  bool keeps_unsolved_problem() const
  {
    return unsolved_problem || unsolved_problem_3d;
  }
};

} // namespace softpack::dynamics
