// src/fluid: the incompressible fluid field (paper eqs. 2-5) on fixed and on prescribed moving
// meshes — boundary conditions, one-step-theta or steady solves by Newton-Krylov with a
// monolithic systems-AMG or a SIMPLE-type block preconditioner, and the consistent boundary
// traction and wall shear stress that the growth model (sigma in eq. 11) and FSI read.
// What it may include: kernels/core, kernels/fluid, src/mesh, src/solvers; only its scene-section
// reader (parameters.hpp) includes src/io's reader helpers. The driver (src/app), the scene
// (src/io/scene.hpp) and the FSI coupling depend on it.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "kernels/core/face.hpp"
#include "kernels/core/stored_tangent.hpp"
#include "kernels/fluid/pointwise.hpp"
#include "mesh/mesh.hpp"
#include "solvers/solvers.hpp"

namespace biofsi {

// A value at a point and time (boundary data, initial conditions).
using FluidFunction = std::function<double(const Point& x, double t)>;
using FluidVectorFunction = std::function<Point(const Point& x, double t)>;

enum class FluidBcKind {
  Velocity,  // prescribed velocity components on the set's nodes (no-slip: all zero)
  Slip,      // zero normal velocity on a wall whose normal is a coordinate axis
  Traction,  // prescribed traction sigma.n_out on the set's faces
  Pressure,  // prescribed pressure on the set's nodes
  DoNothing  // natural outflow: nothing is added (documents the choice)
};

struct FluidBoundaryCondition {
  std::string set;
  FluidBcKind kind = FluidBcKind::Velocity;
  std::array<FluidFunction, 3> value;  // velocity or traction components; [0]: pressure
  std::array<bool, 3> components = {true, true, true};  // Velocity: which components are fixed
};

FluidBoundaryCondition fluid_no_slip(const std::string& set);
FluidBoundaryCondition fluid_velocity(const std::string& set, FluidFunction ux, FluidFunction uy,
                                      FluidFunction uz);
FluidBoundaryCondition fluid_slip(const std::string& set);
FluidBoundaryCondition fluid_traction(const std::string& set, FluidFunction hx, FluidFunction hy,
                                      FluidFunction hz);
FluidBoundaryCondition fluid_pressure(const std::string& set, FluidFunction p);
FluidBoundaryCondition fluid_do_nothing(const std::string& set);

enum class FluidPreconditioner {
  MonolithicAmg,  // BoomerAMG, 4 functions per node with nodal coarsening, on the whole Jacobian
  Simple,         // SIMPLE: AMG on the velocity block and on C - B diag(A)^-1 G
  SimpleC,        // SIMPLEC: the same with absolute row sums of A for diag(A)
  Direct          // sparse LU of the whole Jacobian: an exact preconditioner
};

struct FluidSettings {
  double density = 1.0;
  double viscosity = 1e-3;  // dynamic
  // Every term at u_theta = theta u_{n+1} + (1 - theta) u_n: 1 backward Euler, 0.5 the implicit
  // midpoint rule (second order); a step's pressure is the one at t_{n+theta}.
  double theta = 0.66;
  bool supg = true, grad_div = true;
  bool symmetric_viscous = true;  // false: grad u form (benchmark do-nothing outflow)
  // tau_M with the (2/dt)^2 term (Bazilevs et al.); false: the steady tau_M in every step.
  bool transient_tau = true;
  FluidLinearisation linearisation = FluidLinearisation::Full;
  bool pseudo_2d = false;           // w = 0 at every node
  std::vector<std::string> blocks;  // blocks that hold fluid (empty: all); other nodes are fixed
  // SIMPLE by measurement (bench/README.md, tests/fluid): monolithic systems AMG stagnates on
  // finer meshes of the stabilised saddle-point Jacobian.
  FluidPreconditioner preconditioner = FluidPreconditioner::Simple;
  // BoomerAMG strong threshold of the velocity block (SIMPLE, SIMPLEC). 0.7 by measurement on
  // the Turek-Hron channel (refine 2, CFD1: 1345, 1064, 570 FGMRES iterations over 5 Newton steps
  // at 0.25, 0.5, 0.7; its stretched wake and boundary-layer cells need the higher threshold),
  // equal counts on the square cavity.
  double velocity_strong_threshold = 0.7;
  Scatter scatter = Scatter::Colored;
  NewtonOptions newton_options = default_newton();
  // A time step whose Newton solve fails is retried as 2, 4, ... 2^max_step_cuts sub-steps.
  int max_step_cuts = 6;
  // A steady solve whose Newton fails falls back to pseudo-transient continuation.
  int pseudo_transient_steps = 100;
  double pseudo_dt0 = 1.0;

  static NewtonOptions default_newton() {
    NewtonOptions o;
    o.rel_tol = 1e-10;
    o.abs_tol = 1e-12;
    o.max_iterations = 30;
    o.krylov.max_iterations = 400;
    o.krylov.restart = 100;
    return o;
  }
};

// Consistent traction on a named face set: the nodal reaction of the fluid's residual.
struct BoundaryTraction {
  std::vector<int> nodes;       // the set's nodes (sorted)
  std::vector<Point> force;     // force of the fluid on the wall at each node [force]
  std::vector<double> area;     // lumped area int_set N_a dA
  std::vector<Point> normal;    // unit, area-weighted, out of the face set's elements
  std::vector<Point> traction;  // force / area [force/area]
  std::vector<Point> shear;     // tangential part of the traction (wall shear stress vector)
  Point total{0, 0, 0};         // sum of the nodal forces
};

struct FluidStats {
  int steps = 0, newton_iterations = 0, krylov_iterations = 0, preconditioner_setups = 0;
  int cut_steps = 0, pseudo_steps = 0;
  double seconds_residual = 0, seconds_tangent = 0, seconds_linearise = 0, seconds_assembly = 0,
         seconds_preconditioner_setup = 0, seconds_solve = 0;
};

class SimplePreconditioner;

class FluidField {
 public:
  FluidField(const Mesh& mesh, const FluidSettings& settings,
             std::vector<FluidBoundaryCondition> conditions);
  ~FluidField();
  FluidField(const FluidField&) = delete;
  FluidField& operator=(const FluidField&) = delete;

  void set_initial(const FluidVectorFunction& velocity, const FluidFunction& pressure, double t0);
  // Nodal state, 4 values per node (u, v, w, p).
  void set_solution(const std::vector<double>& state);
  void set_body_force(const FluidVectorFunction& b);
  // Nodal grid velocity u_grid (zero until set).
  void set_grid_velocity(const std::vector<Point>& ug);
  // The mesh has moved (ALE) over the coming step of length dt: takes the new coordinates and sets
  // the grid velocity (x_new - x_old)/dt. dt <= 0 takes the coordinates only. A step then solves
  // on the configuration at t_{n+theta}, theta x_new + (1 - theta) x_old (the time level of every
  // term, kernels/fluid/pointwise.hpp), and leaves that configuration in place for tractions
  // until the next update; mesh() and boundary data use x_new.
  void update_coordinates(const Mesh& moved, double dt);

  // One-step-theta step from t to t + dt; throws SolveError("fluid", label, why) if Newton fails
  // (after step cutting) or the state is not finite; the state is then the last valid one.
  NewtonResult step(double dt, const std::string& label);
  NewtonResult solve_steady(const std::string& label);

  double time() const { return time_; }
  void set_time(double t) { time_ = t; }
  ConstVector solution() const { return state_; }
  std::vector<double> solution_host() const;
  std::vector<Point> velocity() const;
  std::vector<double> pressure() const;
  // (u, v, w, p) interpolated at a point (host search; throws if the point is in no element).
  std::array<double, 4> probe(const Point& x) const;

  BoundaryTraction boundary_traction(const std::string& face_set) const;
  // Wall shear stress vector at the nodes of a face set (order of mesh().node_sets.at(set)).
  std::vector<Point> wall_shear_stress(const std::string& face_set) const;
  // Total force of the fluid on the walls of a face set.
  Point force(const std::string& face_set) const { return boundary_traction(face_set).total; }

  const FluidStats& stats() const { return stats_; }
  const Mesh& mesh() const { return mesh_; }
  const FluidSettings& settings() const { return settings_; }
  // One-step-theta's theta from the next step on, in [0.5, 1] (std::invalid_argument otherwise).
  void set_theta(double theta);
  int n_dofs() const { return 4 * mesh_.n_nodes(); }

  // Verification access: set up the physics of a step (inv_dt = 0: steady) without solving; the
  // residual and tangent with constraints, and the assembled (constraint-eliminated) Jacobian.
  void prepare(double inv_dt, double theta);
  void residual(ConstVector u, Vector r) const;
  void apply_tangent(ConstVector u, ConstVector du, Vector y) const;
  void diagonal(ConstVector u, Vector d) const;
  const CsrMatrix& assemble_jacobian(ConstVector u, bool eliminate = true);

  // ---- the pieces of a step, for a coupled (monolithic) solve that owns the Newton loop ----
  // Sets up the step t -> t + dt (or the steady problem): old state, physics, boundary data at
  // the step's times, Dirichlet values imposed on state().
  void begin_step(double dt);
  void begin_steady();
  // Accepts state() as the solution of the step begun last.
  void end_step(double dt);
  Vector state() { return state_; }
  // Element and face terms only: no constraints, the direction used as given.
  void residual_unconstrained(ConstVector u, Vector r) const;
  void tangent_unconstrained(ConstVector u, ConstVector du, Vector y) const;
  // The tangent stored at the quadrature points at u (what the Krylov solves apply):
  // tangent_linearised_unconstrained(du, y) equals tangent_unconstrained(u, du, y) and
  // apply_linearised(du, y) equals apply_tangent(u, du, y), for the u of the last linearise(u),
  // as long as the mesh and the step's data stay as they were.
  void linearise(ConstVector u);
  void tangent_linearised_unconstrained(ConstVector du, Vector y) const;
  void apply_linearised(ConstVector du, Vector y) const;
  ConstIndexView constrained_dofs() const { return fixed_dofs_; }
  Kokkos::View<const char*, MemSpace> constrained_mask() const { return fixed_; }
  const CsrMatrix& matrix() const { return matrix_; }
  // Back to the state the step began from (a coupled solve that failed).
  void restore_old_state() {
    copy(state_old_, state_);
    reuse_.invalidate();
  }
  ConstVector constrained_values() const { return fixed_values_; }
  // The mesh as the coupling moves it: node coordinates and nodal grid velocity (3 per node) on
  // the device; the host copy of the coordinates (boundary data, tractions, output) is refreshed
  // by sync_host_coordinates().
  void set_geometry(ConstCoordView x, ConstVector grid_velocity);
  void sync_host_coordinates();
  ConstCoordView device_coordinates() const { return dmesh_.x; }
  // Preconditioner set-up on the matrix of assemble_jacobian(u, true), as changed by the caller.
  void setup_preconditioner_on_matrix();
  void precondition(ConstVector r, Vector z) const;
  // The next Newton iteration sets the preconditioner up afresh, whatever its age (a checkpoint:
  // a run continued from it starts that way).
  void invalidate_preconditioner() { reuse_.invalidate(); }
  const std::vector<int>& elements() const { return elements_; }

 private:
  struct FixedDof {
    int dof;
    const FluidFunction* value;  // nullptr: zero
  };
  struct FaceTerm {
    std::string set;
    std::array<FluidFunction, 3> value;
    FaceView faces;
    NodalView aux;
    FaceOperator<FluidTractionPhysics> op;
  };

  NewtonResult advance(const std::string& label);
  NewtonResult step_once(double dt, double theta, const std::string& label);
  NewtonResult steady_newton(const std::string& label);
  void impose_dirichlet(double t);
  void update_face_data(double t_eval);
  void update_body_force(double t_eval);
  void setup_preconditioner(ConstVector u);
  void save_old_state();
  int axis_normal_of(const std::string& set) const;

  // The operator's configuration: weight 1 is mesh_.x, theta is t_{n+theta} of the last move.
  void place_configuration(double weight);

  Mesh mesh_;
  std::vector<Point> previous_x_;  // coordinates before the last update_coordinates with dt > 0
  FluidSettings settings_;
  std::vector<FluidBoundaryCondition> conditions_;
  DeviceMesh dmesh_;
  std::vector<int> elements_;
  ElementGroups groups_;
  NodalView aux_;  // [u_n, u_grid, b]
  FluidVectorFunction body_force_;
  ElementOperator<FluidPhysics> op_;
  Linearisation<FluidPhysics> linearisation_;
  std::vector<FaceTerm> faces_;
  std::vector<FixedDof> fixed_list_;
  Kokkos::View<char*, MemSpace> fixed_;
  IndexView fixed_dofs_;
  Vector fixed_values_;
  Vector state_, state_old_, scratch_;
  CsrMatrix matrix_;
  std::unique_ptr<AssembledPreconditioner> preconditioner_;
  PreconditionerReuse reuse_;  // of preconditioner_ in this field's own Newton solves
  double time_ = 0;
  FluidStats stats_;
};

}  // namespace biofsi
