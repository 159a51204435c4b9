// src/coupling: the monolithic fluid-structure interaction of the biofilm with the flow over it
// (paper sections 2 and 5): one Newton loop for the structure displacement, the fluid velocity and
// pressure and the fluid mesh displacement, on a mesh whose fluid and structure blocks share the
// interface nodes (conforming).
// What it may include: src/fluid, src/structure, src/ale, src/mesh, src/solvers (and src/io's
// reader helpers in parameters.hpp, its scene section). The driver (src/app) depends on it; no
// field depends on it.
//
// Formulation (fluid-split condensation, as in Küttler, Gee, Förster, Comerford & Wall 2010 and
// Gee, Küttler & Wall 2011): on the interface Γ the fluid velocity and the fluid mesh displacement
// are not unknowns of their own but functions of the structure's,
//   u_F = a s + b,   (transient: a = 1/(θ Δt), b = -(1-θ)/θ v_n, the structure's one-step-θ
//                     velocity; quasi-static structure in a transient flow: a = 1/Δt, b = 0;
//                     steady flow: a = 0, b = 0),
//   d_G = d_n + s    (the fluid mesh follows the structure),
// where s is the structure's increment d_{n+1} - d_n. The interface rows of the fluid momentum
// equations (the force the wall exerts on the fluid, at t_{n+θ} as the fluid's one-step-θ forms
// it) are added to the structure's interface rows: the tractions are in equilibrium with the
// interface force taken at the same time level by both fields. Why fluid-split: the structure's
// unknowns then carry Γ, so its Dirichlet data (a clamped flag root, the biofilm's substrate) hold
// exactly, and the fluid keeps its interface as the Dirichlet boundary it already has. The
// condensed unknowns stay in the vectors as identity rows with zero residual (like constrained
// dofs), recomputed from the structure's values before every evaluation.
//
// The fluid equations live on x = X + d_G and see the grid velocity (d_G - d_G,n)/Δt; the mesh
// obeys the pseudo-elasticity of src/ale on the reference X (walls fixed or sliding). The
// Jacobian action is matrix-free for every field, and the fluid's dependence on the mesh motion
// (the shape derivative, through geometry and grid velocity) is a directional finite difference
// of the fluid residual (one extra residual per Krylov iteration; `ShapeDerivatives::None` drops
// it, an inexact Newton whose cost in iterations tests/coupling measures).
//
// Preconditioner: one forward block Gauss-Seidel sweep fluid -> structure -> fluid mesh (the
// fluid with its interface held by the residual, the structure under the force the fluid's
// correction exerts, the mesh following the structure); each block a Krylov solve to
// inner_tolerance on the field's assembled matrix, preconditioned by the field's own AMG (systems
// BoomerAMG for the structure, with the fluid's interface velocity block a F_ΓΓ condensed into
// it; systems BoomerAMG for the fluid mesh, built once per reference; SIMPLE or monolithic AMG
// for the fluid); the lower coupling blocks applied from the assembled matrices. Left out: the
// fluid's dependence on the structure's motion (shape derivatives, and in transient runs the
// part of a F_IΓ not condensed), which is why very soft structures (see tests/coupling) stall.
// FGMRES over the whole system.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "ale/mesh_motion.hpp"
#include "fluid/fluid.hpp"
#include "structure/structure.hpp"

namespace biofsi {

enum class ShapeDerivatives { FiniteDifference, None };

struct FsiSettings {
  std::string interface = "biofilm_fluid";  // node set of Γ (nodes shared by both blocks)
  // The fluid mesh: pseudo-elastic material and walls (fixed: every component; sliding: the
  // wall-normal one). Nodes outside the fluid's blocks do not belong to the fluid mesh.
  MeshMotionSettings mesh_motion;
  ShapeDerivatives shape_derivatives = ShapeDerivatives::FiniteDifference;
  // Newton: every field's residual norm below rel_tol times its largest value in the solve (or
  // below abs_tol). Per field, because their units differ (forces, flow rates, mesh forces).
  double rel_tol = 1e-8, abs_tol = 0;
  int max_iterations = 25;
  double eta_max = 1e-3;  // Eisenstat-Walker forcing, on the field-scaled residual
  int krylov_max_iterations = 400, krylov_restart = 60;
  // Each block of the preconditioner: Krylov iterations on the field's assembled matrix with its
  // AMG to this relative tolerance (0: the field's preconditioner applied once). Why: the slender
  // flag's systems AMG and the fluid's SIMPLE each need ~50-80 iterations per solve, which the
  // restarted outer FGMRES over the matrix-free operator cannot afford (it stagnated on FSI1);
  // inner iterations cost CSR products instead of matrix-free applications. Tighter is faster on
  // FSI1 (refine 2: 1e-2 313 outer iterations, 3e-4 52; table in bench/README.md), so the FSI1
  // tests use 3e-4; the default stays 1e-2 because case (c) stalled at growth step ~51 with 3e-4
  // (not investigated), and in a transient FSI3 step (refine 1, dt 5e-3, Newton rel_tol 1e-8)
  // 3e-4 left one Newton iteration's outer FGMRES at the 400-iteration limit with the residual
  // down only 15x (1e-2 with rel_tol 1e-6: 36 outer iterations over the step's 3 Newton).
  double inner_tolerance = 1e-2;
  int inner_max_iterations = 100;
  // Keep the assembled preconditioner (the fields' matrices, the fluid's factorisation or SIMPLE,
  // the structure's AMG) across the Newton and time steps of a transient run while it serves
  // (PreconditionerReuse: the step's coefficients, the outer Krylov count). Steady solves always
  // rebuild. The scene's solver.reuse_preconditioner.
  bool reuse_preconditioner = NewtonOptions{}.reuse_preconditioner;
  // A time step whose Newton solve fails is retried as 2, 4, ... 2^max_step_cuts sub-steps.
  int max_step_cuts = 4;
};

struct FsiStats {
  int solves = 0, newton_iterations = 0, krylov_iterations = 0, cut_steps = 0;
  // Of the last solve: Krylov iterations of each Newton iteration, and each iterate's residual
  // norms (structure, fluid, fluid mesh).
  std::vector<int> last_krylov;
  std::vector<std::array<double, 3>> last_residuals;
  std::array<int, 3> inner_iterations{};  // structure, fluid, fluid mesh: inner Krylov, all solves
  std::array<double, 3> seconds_inner{};  // and their time
  double seconds_residual = 0, seconds_tangent = 0, seconds_shape = 0, seconds_assembly = 0,
         seconds_preconditioner_setup = 0, seconds_preconditioner = 0, seconds_solve = 0;
  int preconditioner_setups = 0, preconditioner_reuses = 0;
};

class FsiProblem {
 public:
  // The fields live on `mesh` (the reference configuration), the structure on its blocks, the
  // fluid on its own; the fluid must hold the interface's velocity fixed (a no_slip or velocity
  // condition on the interface set): those dofs become the condensed ones.
  FsiProblem(const Mesh& mesh, FluidField& fluid, StructureField& structure,
             const FsiSettings& settings);
  ~FsiProblem();
  FsiProblem(const FsiProblem&) = delete;
  FsiProblem& operator=(const FsiProblem&) = delete;

  // One time step t -> t + dt of the coupled problem (transient fluid; dynamic or quasi-static
  // structure). Throws SolveError (field "fsi", the label, why with each field's residual
  // history) if Newton fails even with cut steps; the state is then the last valid one.
  NewtonResult step(double dt, const std::string& label);
  // The steady coupled problem (steady fluid, the structure at equilibrium: a dynamic one is
  // solved quasi-statically for this solve and left at rest, the state a transient run may start
  // from).
  NewtonResult solve_steady(const std::string& label);

  // A growth step moved the reference mesh: the structure keeps its displacement relative to the
  // new reference, the fluid mesh is re-solved from it at the next solve.
  void set_reference(const Mesh& mesh);
  // Displacement of every node from the reference: the structure's on its nodes, the fluid
  // mesh's elsewhere (the two agree on Γ).
  std::vector<Point> displacement() const;
  // The reference moved by displacement(): the current configuration.
  Mesh current_mesh() const;
  // Nodal grid velocity of the last step (zero after a steady solve).
  std::vector<Point> grid_velocity() const;
  // The fluid mesh's displacement from the reference (checkpoints), and setting it (restarts:
  // the fluid is placed there with the given grid velocity, none if empty; a transient restart
  // that passes grid_velocity() of the run it continues predicts its next step as that run would).
  std::vector<Point> mesh_displacement() const;
  void set_mesh_displacement(const std::vector<Point>& g,
                             const std::vector<Point>& grid_velocity = {});
  const FsiStats& stats() const { return stats_; }
  // The next Newton iteration sets the preconditioner up afresh, whatever its age (a checkpoint:
  // a run continued from it starts that way).
  void invalidate_preconditioner();

  // Verification access. prepare_step/prepare_steady set a solve up (as step/solve_steady do,
  // the predictor in state()); residual and tangent are the condensed monolithic ones,
  // x = [structure increment (3 per node) | fluid (4 per node) | fluid mesh displacement (3)].
  void prepare_step(double dt);
  void prepare_steady();
  Vector state() { return x_; }
  int n_dofs() const { return 10 * n_nodes_; }
  void residual(ConstVector x, Vector r);
  void tangent(ConstVector x, ConstVector dx, Vector y);
  // 1 for the unknowns proper, 0 for constrained and condensed entries: the residual is
  // consistent with the tangent for states that keep the others at their values.
  std::vector<char> free_dofs() const;

  struct Impl;  // the fields, the fluid mesh, the condensation maps (fsi.cpp)

 private:
  NewtonResult solve();
  NewtonResult step_once(double dt, const std::string& label);
  void commit(double dt);
  void restore();

  std::unique_ptr<Impl> impl_;
  int n_nodes_ = 0;
  Vector x_;
  FsiStats stats_;
};

}  // namespace biofsi
