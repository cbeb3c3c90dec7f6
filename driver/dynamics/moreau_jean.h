#pragma once

#include "moreau_jean_options.h"
#include "scheme_state.h"
#include "step_report.h"
#include "step_size.h"
#include <bodies/BodySet.h>
#include <compliance/contact_operator.h>
#include <compliance/damping.h>
#include <compliance/delassus.h>
#include <compliance/effective_stiffness.h>
#include <compliance/rigid_bodies.h>
#include <contact/frictionless_condensation.h>
#include <contact/nlgs.h>
#include <contact/problem.h>
#include <detection/bond_history.h>
#include <detection/contact_history.h>
#include <detection/detection.h>
#include <detection/detection_3d.h>
#include <detection/friction_table.h>
#include <energy/energy_balance.h>
#include <functional>
#include <memory>
#include <optional>
#include <parallel/contact_exchange.h>
#include <softpack/parameters.h>
#include <vector>
#include <walls/periodic_cell.h>
#include <walls/walls.h>

/// Nonsmooth contact dynamics of deformable bodies (Moreau–Jean).
namespace softpack::dynamics
{
struct ServoWalls;
struct ServoStep;

/// The Moreau–Jean theta-method with Newton iterations on finite-strain
/// bodies and Signorini–Coulomb contacts solved by NLGS (METHOD.md §3).
///
/// A step: detect the contacts at the start configuration, decide whether
/// to refactor the iteration matrix, form the known part of the momentum
/// balance, iterate Newton on the velocity (one contact solve per
/// iteration), then update the displacement, the walls and the energy
/// accounts (energy_balance.h) and remember the impulses for the next warm
/// start (contact_history.h).
///
/// Newton stops when the estimated error of the iterate, ||v_{k+1} -
/// v_k||_inf rho / (1 - rho) with rho the observed contraction rate (or the
/// increment itself while rho >= 1/2), is at most time.newton_tolerance *
/// max(||v||_inf, velocity_scale) (in a periodic cell: velocity_scale, the
/// edges' speed, alone). With time.full_newton = false the
/// iteration matrix (and the per-body compliances behind the Delassus
/// operator) is kept for up to time.tangent_reuse_steps steps, and
/// refactored after a step that needed more than
/// time.refactor_above_iterations iterations: it is mass-dominated at small
/// h, so a lagged one still converges fast to the same step.
class MoreauJean
{
public:
  /// @param[in,out] bodies Bodies; their displacement is the state
  /// @param[in] walls Walls
  /// @param[in] options Time step, damping, friction, tolerances
  /// @throws std::runtime_error if an option is outside the schema's range
  /// @throws std::invalid_argument if velocity_scale is not positive, a
  /// servo wall has no positive mass or a pressure-controlled wall no pair
  /// of facing walls to measure its length (link_walls)
  /// @param[in] distribution The bodies over the processes (default:
  /// serial, one process computing every body); each step is then the
  /// same in every process (docs/mpi_design.md)
  MoreauJean(bodies::BodySet& bodies, std::vector<Wall> walls,
             MoreauJeanOptions options,
             parallel::Distribution distribution = {});

  /// A 3D run (BodySet::dim() = 3; docs/contact_3d.md, "The 3D step"):
  /// the same step over 3 components per node, node-to-face contacts
  /// (detect_contacts_3d) in the frame (n, t1, t2) and plane walls moved
  /// at their imposed velocities or servo-controlled as in 2D, over the
  /// processes as a 2D run (docs/mpi_design.md, "3D runs"), rigid bodies
  /// of six degrees of freedom; no cohesion, bonds or periodic cell yet
  /// (refused).
  /// @throws std::invalid_argument if the bodies are not 3D, a wall's
  /// normal is not a unit vector, or an option asks for what 3D lacks
  /// (The options before the walls: a 2D run's `{}` for no walls stays
  /// unambiguous.)
  MoreauJean(bodies::BodySet& bodies, MoreauJeanOptions options,
             std::vector<Wall3D> walls,
             parallel::Distribution distribution = {});

  /// Advance one time step.
  StepReport step();

  /// Current time
  double time() const { return _time; }
  /// The size of the last step taken (before the first: of the first)
  double time_step() const { return _h; }
  /// Velocity, as the bodies store node vectors (BodySet::keep_storage: a
  /// distributed run's share stores its local bodies, every boundary and
  /// every rigid body; the entry of the others' interiors is NaN)
  std::span<const double> velocity() const { return _v; }
  /// The displacement the kept tangent was assembled at, stored as the
  /// velocity (current while matrix_age() >= 0)
  std::span<const double> tangent_displacement() const { return _u_tangent; }
  /// The internal variables the kept tangent was assembled with
  /// (BodySet::internal_variables; current while matrix_age() >= 0)
  std::span<const double> tangent_internal() const { return _internal_tangent; }
  /// Steps since the last factorization of the iteration matrix (-1: none
  /// kept; the next step refactors)
  int matrix_age() const { return _matrix_age; }
  /// Make the energies current for an output (a collective: every process
  /// calls it at the same point; nothing when serial): each body's strain
  /// energy, computed where the body is local, everywhere (energy(),
  /// body_strain_energy()). Rank 0's global copies of the vectors for an
  /// output are gathered apart (io::OutputGather).
  void prepare_output();
  /// Initial conditions: the global velocity vector (2 entries per mesh
  /// node) before the first step (collective: every rank of a distributed
  /// run gives the same vector)
  /// @throws std::invalid_argument if the size is wrong
  /// @throws std::logic_error after the first step
  void set_initial_velocity(std::vector<double> v);
  /// Constant external nodal forces (global vector, 2 entries per mesh
  /// node; default zero)
  void set_external_force(std::vector<double> f);

  /// Contacts of the last step and their impulses (dim per contact, (n,
  /// t) or (n, t1, t2)); 3D runs' contacts are contacts_3d()
  const std::vector<Contact>& contacts() const { return _contacts; }
  const std::vector<Contact3D>& contacts_3d() const { return _contacts3; }
  const std::vector<double>& impulses() const { return _R; }
  /// Force each wall received during the last step (impulse / h)
  std::vector<std::array<double, 2>> wall_forces() const;
  /// The same for the walls of a 3D run
  std::vector<std::array<double, 3>> wall_forces_3d() const;
  /// The plane walls of a 3D run (writable: a wall's velocity, control,
  /// pressure or force may be changed between steps; link_walls(walls_3d())
  /// after changing a control)
  std::vector<Wall3D>& walls_3d() { return _walls3; }
  const std::vector<Wall3D>& walls_3d() const { return _walls3; }
  /// The bodies' dimension, 2 or 3
  int dimension() const { return dim(); }
  /// Energy balance since the start (the strain energy is evaluated on
  /// demand: a state function, not needed to step; the kinetic energy is
  /// summed over the ranks where every rank passes, at a step's end, a
  /// restore and the initial velocity, so rank 0 alone may call this)
  /// @throws std::logic_error on a distributed run unless prepare_output()
  /// was called since the last step (the strain energy is summed from the
  /// bodies' owners)
  const EnergyBalance& energy() const;
  /// Each body's strain energy (energy()'s strain is their sum, in body
  /// order); the same conditions as energy()
  const std::vector<double>& body_strain_energy() const
  {
    energy();
    return _body_strain;
  }
  /// The walls (writable: a wall's velocity, control, pressure or force may
  /// be changed between steps; link_walls(walls()) after changing a
  /// control)
  std::vector<Wall>& walls() { return _walls; }
  const std::vector<Wall>& walls() const { return _walls; }
  /// Options
  const MoreauJeanOptions& options() const { return _options; }
  /// The friction coefficient of the pairs the friction table does not set
  /// ([contact] friction), from the next step on (a stage's contact.friction)
  void set_default_friction(double mu) { _options.contact.friction = mu; }
  /// The state after the last step, its vectors global (2 entries per
  /// mesh node)
  /// @throws std::logic_error on a distributed run (no process holds every
  /// body's interior: io::OutputGather gathers them on rank 0)
  SchemeState state() const;
  /// The state's time, steps, walls, reactions, energies and step, without
  /// its vectors (the energies must be current, as for energy())
  SchemeState scalar_state() const;
  /// Continue from a state saved by state() on the same bodies and walls
  /// (2D walls, or a 3D run's plane walls: their points; an imposed
  /// velocity stays the run's).
  /// @throws std::invalid_argument if the dimension or the sizes do not
  /// match
  void restore(const SchemeState& state);
  /// New drives within a run (a stage's start), taken as a run continued
  /// from its state file would take them: the walls become `walls` (their
  /// points and a servo wall's velocity stay the state's) and the scheme
  /// restores its own state as `edit` changes it. Each rank works on its
  /// own bodies' entries: no vector is made whole (a collective: the
  /// kinetic energy is summed); the energies must be current (as for
  /// energy()).
  void continue_with(std::vector<Wall> walls,
                     const std::function<void(SchemeState&)>& edit);
  /// The same for a 3D run's plane walls
  void continue_with(std::vector<Wall3D> walls,
                     const std::function<void(SchemeState&)>& edit);
  /// Make the run a periodic cell (docs/periodic_cell.md), before the
  /// first step: contacts with the images of the bodies, the cell moved by
  /// its velocity gradient at each step and the bodies re-wrapped into it.
  /// @throws std::logic_error after the first step
  /// @throws std::runtime_error on several processes, with rigid bodies, a
  /// mass-proportional damping or a cell of no positive area (not yet:
  /// refused)
  void set_cell(const PeriodicCell& cell);
  /// Change the cell's drive between two steps (a stage's; docs/
  /// periodic_cell.md, "Stages"): the imposed rates L h (h the cell now),
  /// the stress-controlled components `drive.servo`, a component (xx, yy,
  /// xy) keeping its rate and the isotropic mode starting at rest; every body
  /// receives the rates' change of the affine field at its centroid (its
  /// kinetic energy booked in rewrap), a servo unknown's m V^2 / 2 that
  /// leaves or enters the accounts in cell_work. Before the first step (or
  /// a restore) only the drive is set.
  void change_cell_drive(const CellDrive& drive, double start_time);
  /// The periodic cell as it is now (none: a run with walls)
  const std::optional<PeriodicCell>& cell() const { return _cell; }
  /// Steps done so far (including those before a restore)
  long steps() const { return _steps; }
  /// Intact bonds (docs/contact_laws.md, law "bonded"; 0 without one)
  std::size_t intact_bonds() const { return _bonds.size(); }
  /// Form bonds at the next step (true), or none at the first step (false:
  /// a stage program that forms them at its stages' starts)
  void form_bonds(bool at_next_step) { _bonds.set_formed(!at_next_step); }
  /// Factorizations of the iteration matrix so far
  int factorizations() const { return _kbar.factorizations(); }
  /// Distinct symbolic factorizations of this rank's bodies (one per mesh
  /// when bodies are copies of a few meshes)
  int factor_patterns() const { return _kbar.factor_patterns(); }
  /// The bodies over the processes, and the collectives' volume so far
  const parallel::Distribution& distribution() const { return dist(); }
  /// What the domain-wise contact solves have sent so far (distributed)
  const parallel::ContactTraffic& contact_traffic() const
  {
    return _exchange.traffic();
  }

private:
  /// The Newton iterations of a step (newton_loop.h) work on the scheme's
  /// vectors and factors
  friend class NewtonLoop;
  using Vectors = BodyVectors;
  /// state() from the stored entries: on a distributed run the vectors'
  /// entries of the interiors not stored are NaN
  SchemeState stored_state() const;
  /// Refuse a state whose internal variables are not the bodies' (missing:
  /// naming the key internal_variables)
  void check_internal(const SchemeState& s) const;
  /// Refuse a state of another dimension, or whose sizes (DOFs, walls,
  /// kept tangent, internal variables) are not the run's
  void check_state(const SchemeState& s) const;
  /// The contacts of a step and their data fixed during the step
  struct StepContacts;
  /// What the step knows before its Newton iterations
  struct StepStart;
  /// The step's contact problem, of the bodies' dimension
  struct StepProblem;
  /// The bodies' dimension, 2 or 3
  int dim() const { return _bodies.dim(); }
  /// continue_with's restore, the walls set
  void continue_edited(SchemeState& s,
                       const std::function<void(SchemeState&)>& edit);
  /// Refuse what 3D runs lack (the constructors' checks)
  void check_3d() const;
  /// The step's 3D contacts and their operator (prepare_contacts)
  ContactOperator detect_3d();
  /// The cohesion impulse of each 3D contact: h x its wall's
  /// tensile_strength when closed, else 0; empty when no wall has one
  std::vector<double> wall_cohesion_3d() const;
  const parallel::Distribution& dist() const
  {
    return _exchange.distribution();
  }
  /// Before a refactorization of a distributed run: split the bodies
  /// again if the split has drifted (parallel::drifted_split), and
  /// give the per-body work to the new owners
  void rebalance();
  /// The contacts at the bodies' current configuration (the start of the
  /// step) and their data fixed during the step
  StepContacts prepare_contacts(const std::vector<double>& v_old);
  /// The contact problem of the step (W, and mu; q is set by each solve)
  StepProblem prepare_problem(const StepContacts& sc, StepReport& report);
  bool needs_refactorization() const;
  /// W into `problem` from the local bodies' compliances (and the plan of
  /// the contact solves, parallel::ContactExchange::delassus)
  void set_delassus(const StepContacts& sc, StepProblem& problem,
                    StepReport& report);
  /// add_body_terms over the local bodies and their part of the stiffness
  /// dissipation, summed over the processes, and the bodies' kinetic
  /// energy at the step's end (in the same sum)
  void add_local_body_terms(const BodyStep& step, double stiffness_numerical);
  /// Assemble K at the bodies' current displacement, factorize Kbar and
  /// form A (the arithmetic of every refactorization, and of a restore);
  /// adds its times to `report` when given
  void factorize_tangent(StepReport* report);
  void refactorize(const StepContacts& sc, StepProblem& problem,
                   StepReport& report);
  /// The known part b = M v- + h (1 - th) (F_ext - F_int(q-) - C v-) of the
  /// momentum balance, and the start-of-step vectors the accounts need
  StepStart start_step(std::vector<double> u_old, std::vector<double> v_old);
  /// One attempt at a step: its contacts, start and report
  struct Attempt;
  /// Back to the step's start after an attempt failed (a retry at h / 2)
  void return_to_step_start();
  /// The accounts after a finished step when the adaptive step judges a
  /// window there (StepSize::needs_energy; a collective then)
  std::optional<StepSize::WindowEnergy> window_energy(const StepReport& report);
  /// Detection, the contact problem and the Newton iterations of one
  /// attempt at the step, from the current state at step size _h
  Attempt attempt();
  /// q = q- + h (th v + (1 - th) v-) into the bodies' displacement
  void set_displacement(const std::vector<double>& u_old,
                        const std::vector<double>& v_old,
                        const std::vector<double>& v);
  /// Displacement, internal force, time and walls at the end of the step
  void finish_step(StepContacts& sc, const StepStart& start,
                   StepReport& report);
  /// The periodic cell's end of step: its edges advanced (the
  /// stress-controlled components at their mid-step rates), the affine
  /// kick of a changed rate, the cell remapped when it leans too far, every
  /// body whose centroid left it moved back by a whole cell vector (u -= h
  /// k, v -= (dh/dt) k), the contacts' images and the accounts changed
  /// with them
  void finish_cell_step(double h, const ServoWalls& servo);
  /// Every body's velocity changed by the change of the stress-controlled
  /// rates' affine field at its centroid (and its position by th h times
  /// that); false when no rate changed
  bool affine_kick(double h, const ServoWalls& servo);
  /// The cell's edges and rates (and the isotropic mode's V) from a state
  void restore_cell(const std::vector<double>& cell);
  /// The rates at the servo unknowns' `velocity` (V_mid, V+) from the
  /// step's start rates: a diagonal component's set, the isotropic mode's
  /// (V - V-) W added
  void set_servo_rates(const ServoWalls& servo,
                       const std::array<double, 2>& a1_rate,
                       const std::array<double, 2>& a2_rate,
                       double ServoStep::*velocity);
  /// The isotropic mode's rates V+ W moved to V+ W+ (the mode at the
  /// advanced cell); the change of the rates (a1's x, y, a2's x, y)
  std::array<double, 4> rebase_mean_mode(const ServoWalls& servo);
  /// The isotropic mode's affine changes of the bodies' velocities (and
  /// positions), as affine_kick's; false without the mode
  bool mean_mode_kick(double h, const ServoWalls& servo,
                      const std::array<double, 4>& rebase);
  /// Every body whose centroid left the cell moved back by a whole cell
  /// vector, with its image's velocity; false when none moved
  bool rewrap();
  /// The bodies' centroids (the mean of their nodes), now
  std::vector<std::array<double, 2>> body_centroids() const;
  /// In a cell with [damping] alpha: alpha M v_affine of each local body,
  /// v_affine = (dh/dt) h^-1 x at its nodes now; empty otherwise
  Vectors affine_drag() const;
  /// The step's energy terms, contact report and impulse history
  void account_step(StepContacts& sc, const StepStart& start,
                    StepReport& report, double stiffness_numerical);
  /// The step's intact bonds (formed first when none have): their gap in
  /// the shift, their strengths (docs/contact_laws.md, law "bonded")
  void prepare_bonds(StepContacts& sc);
  /// The break rule over the step's bonds, at the step's impulses; the
  /// bonds that hold in tension counted as active contacts
  void break_bonds(const StepContacts& sc, StepReport& report);
  void update_products(const Vectors& v);
  /// M v of the local bodies (the others' stay empty)
  Vectors mass_products(const Vectors& v) const;
  /// The local bodies' parts of a node vector (the others' are empty: a
  /// copy of every body in each process would grow with the whole model)
  Vectors gather(std::span<const double> global) const;
  /// Write the nonempty per-body vectors into the global vector
  void scatter(const Vectors& per_body, std::span<double> global) const;

  bodies::BodySet& _bodies;
  /// The distribution, and the contact problem's exchanges between
  /// processes
  parallel::ContactExchange _exchange;
  /// The contact problem renumbered for its sweeps (serial runs): made at
  /// the first solve after W changes, reused by the step's other Newton
  /// iterations
  std::optional<contact::SweepPlan> _sweep_plan;
  /// The same for a 3D problem (whole on every process)
  std::optional<contact::SweepPlan3D> _sweep_plan3;
  /// Whether a 3D problem's small frictionless sets are held exactly
  /// (contact.nlgs_condensation), and their condensation: made at the
  /// first solve after W changes, as the plans
  bool _condense = false;
  std::optional<contact::FrictionlessCondensation<3>> _condensation;
  std::vector<Wall> _walls;
  /// The plane walls of a 3D run
  std::vector<Wall3D> _walls3;
  /// A 3D run's bodies' boundary surfaces (built once)
  std::vector<BoundarySurface> _surfaces;
  /// The periodic cell (none: walls only)
  std::optional<PeriodicCell> _cell;
  MoreauJeanOptions _options;
  DetectionOptions _detection;
  contact::NlgsOptions _nlgs;
  RayleighDamping _damping;
  EffectiveStiffness _kbar;
  /// The rigid bodies' three degrees of freedom (none: every body soft)
  RigidBodies _rigid;
  /// Tangent stiffness as last assembled (this rank's bodies; the others'
  /// matrices have no entry)
  std::vector<bodies::BodyMatrix> _K;
  /// A = M + h th C with that K and the h of its factorization: the
  /// coefficients only (A v_k in the Newton residual is formed from M and K)
  RayleighDamping::Combination _A{1, 0};
  /// M v and K v at the current velocity (valid while K is unchanged)
  Vectors _Mv, _Kv;
  bool _products_valid = false;
  double _time = 0;
  long _steps = 0;
  bool _started = false;
  /// Velocity (whole), external force, internal force (this rank's bodies
  /// only: the other entries are zero)
  std::vector<double> _v, _f_ext, _f_int;
  /// Free velocity at contact nodes only (work array)
  std::vector<double> _v_contact;
  std::vector<Contact> _contacts;
  std::vector<Contact3D> _contacts3;
  std::vector<double> _R;
  /// The previous step's impulses: the warm start
  ImpulseHistory _history;
  /// The intact bonds, each with the gap it holds
  BondHistory _bonds;
  mutable EnergyBalance _energy;
  /// The bodies' kinetic energy at the last step's end (or at the initial
  /// velocity or restored state), summed over the ranks
  double _body_kinetic = 0;
  /// The bodies' kinetic energy at the current velocity (collective)
  double body_kinetic_energy() const;
  mutable bool _energy_stale = true;
  /// Each body's strain energy at the current displacement, when energy()
  /// was last made current
  mutable std::vector<double> _body_strain;
  /// Whether _body_strain was shared (a distributed run's construction,
  /// prepare_output) since the displacement last changed (the same on
  /// every rank)
  bool _strain_shared = false;
  int _matrix_age = -1; ///< steps since the last factorization (-1: none)
  int _last_iterations = 0;
  /// Displacement at which _K was assembled (saved in the state)
  std::vector<double> _u_tangent;
  std::vector<double> _internal_tangent;
  /// The step's start (displacement, velocity) while a retry of the step
  /// is possible (StepSize::can_retry); a rebalance hands them over with
  /// u and v
  std::vector<double> _retry_u, _retry_v;
  /// time.time_step, or adapted up to time.max_step_factor times it
  StepSize _step_size;
  /// The size of the current (or last) step
  double _h;
};

} // namespace softpack::dynamics
