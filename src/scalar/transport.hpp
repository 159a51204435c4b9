// src/scalar: the substrate transport field (paper eqs. 8-10) on one continuous scalar over all
// blocks — boundary conditions, time stepping (one-step-theta or steady), Newton-Krylov with
// BoomerAMG, and the consistent boundary flux that the growth model reads.
// What it may include: kernels/core, kernels/scalar, src/mesh, src/solvers; only its scene-section
// reader (parameters.hpp) includes src/io's reader helpers. The driver and the scene depend on it.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "kernels/core/face.hpp"
#include "kernels/core/stored_tangent.hpp"
#include "kernels/scalar/pointwise.hpp"
#include "mesh/mesh.hpp"
#include "solvers/solvers.hpp"

namespace biofsi {

// Value of a boundary or initial condition at a point and time.
using SpaceTimeFunction = std::function<double(const Point& x, double t)>;

enum class ScalarBcKind { Dirichlet, Flux, Robin };

// On a named face set (its node set for Dirichlet):
//   Dirichlet: phi = value;  Flux: D grad(phi).n_out = value (inward flux);
//   Robin: D grad(phi).n_out = coefficient (value - phi).
struct ScalarBoundaryCondition {
  std::string set;
  ScalarBcKind kind = ScalarBcKind::Dirichlet;
  SpaceTimeFunction value;
  double coefficient = 0;
};

// The preconditioner of the Krylov solves, applied to the assembled tangent: BoomerAMG, or a
// sparse LU (SparseLu), which makes every Krylov solve one or two iterations and pays where the
// factors stay small (pseudo-2-D and small 3-D meshes; bench/README.md has the measurement).
enum class ScalarPreconditioner { Amg, Direct };

struct TransportSettings {
  TransportCoefficients coefficients;  // per block index
  bool supg = true;
  double theta = 0.66;
  Scatter scatter = Scatter::Colored;
  NewtonOptions newton;
  ScalarPreconditioner preconditioner = ScalarPreconditioner::Amg;
  AmgOptions amg;
  // A time step whose Newton solve fails is retried as 2, 4, ... 2^max_step_cuts sub-steps.
  int max_step_cuts = 8;
  // A steady solve whose Newton fails falls back to pseudo-transient continuation with at most
  // this many backward-Euler pseudo-time steps, the first of size pseudo_dt0 (0 disables it).
  int pseudo_transient_steps = 200;
  double pseudo_dt0 = 1.0;
};

// Consistent flux through a node set: the nodal reaction of the residual restricted to the
// elements on one side, so it is the flux *into* those elements (and the storage and reaction they
// contain, consistently with the discrete balance).
struct BoundaryFlux {
  std::vector<int> nodes;
  std::vector<double> nodal_flux;   // r_a [amount/time]
  std::vector<double> lumped_area;  // int_set N_a dA
  std::vector<double> density;      // r_a / A_a [amount/(area time)]
  double total = 0;                 // sum of nodal_flux
};

struct TransportStats {
  int steps = 0, newton_iterations = 0, krylov_iterations = 0, preconditioner_setups = 0;
  int cut_steps = 0;        // time steps that needed sub-steps
  int pseudo_steps = 0;     // pseudo-time steps of steady solves that needed continuation
  int continued_steps = 0;  // time steps solved by continuation in Monod's half-saturation
  double seconds_residual = 0, seconds_tangent = 0, seconds_linearise = 0, seconds_assembly = 0,
         seconds_preconditioner_setup = 0, seconds_solve = 0;
};

class TransportField {
 public:
  TransportField(const Mesh& mesh, const TransportSettings& settings,
                 std::vector<ScalarBoundaryCondition> conditions);

  void set_initial(const SpaceTimeFunction& phi0, double t0);
  void set_solution(const std::vector<double>& phi);
  // Nodal ALE convective velocity c = u - u_grid (zero where not set).
  void set_convective_velocity(const std::vector<Point>& c);
  // Velocity of the material in the blocks whose coefficients.material_motion is set (the
  // biofilm deforming under FSI): its divergence enters as Phi div w (eq. 9).
  void set_material_velocity(const std::vector<Point>& w);
  // Volumetric source s(x, t), evaluated at the nodes at t_{n+theta} of each step.
  void set_source(const SpaceTimeFunction& s);
  // The mesh has moved (ALE): take its current coordinates.
  void update_coordinates(const Mesh& mesh);

  // One-step-theta step from the current state at time t to t + dt. Throws SolveError (field
  // "scalar", the step label) if Newton fails or the solution is not finite; the state is then
  // left at the last valid solution.
  NewtonResult step(double dt, const std::string& label);
  // Steady problem at the current time.
  NewtonResult solve_steady(const std::string& label);

  double time() const { return time_; }
  void set_time(double t) { time_ = t; }
  ConstVector solution() const { return phi_; }
  std::vector<double> solution_host() const;
  // The next Newton iteration sets the preconditioner up afresh, whatever its age (a checkpoint:
  // a run continued from it starts that way).
  void invalidate_preconditioner() { reuse_.invalidate(); }
  // Integral of phi over the blocks (all when block < 0).
  double integral(int block = -1) const;
  // Total consumption rate int R(phi) dV over all blocks, at the current solution.
  double reaction_integral() const;

  // Consistent flux through a named node set into the elements of `block` (all when < 0).
  BoundaryFlux boundary_flux(const std::string& set, int block) const;

  const TransportStats& stats() const { return stats_; }
  const Mesh& mesh() const { return mesh_; }

  // Residual and tangent of the current step (exposed for verification).
  void residual(ConstVector phi, Vector r) const;
  void apply_tangent(ConstVector phi, ConstVector dphi, Vector y) const;
  // The same tangent stored at the quadrature points at phi (what Newton's Krylov solves apply):
  // apply_linearised(dphi, y) equals apply_tangent(phi, dphi, y) of the last linearise(phi).
  void linearise(ConstVector phi);
  void apply_linearised(ConstVector dphi, Vector y) const;

 private:
  struct FaceTerm {
    ScalarBoundaryCondition bc;
    FaceView faces;
    NodalView aux;  // [phi_n, h, alpha, phi_inf]
    FaceOperator<TransportBoundaryPhysics> op;
  };

  // fresh_preconditioner: set the AMG hierarchy up at every Newton iteration.
  NewtonResult advance(const std::string& label, double abs_floor, bool fresh_preconditioner);
  // residual() from step_states_, valid within advance()'s solve.
  void residual_of_step(ConstVector phi, Vector r) const;
  NewtonResult step_once(double dt, double theta, const std::string& label,
                         bool fresh_preconditioner);
  // One step of dt from phi_old_ to phi_ (phi_ the first iterate) with the given coefficients.
  NewtonResult solve_step(double dt, double theta, const std::string& label,
                          bool fresh_preconditioner, const TransportCoefficients& coefficients);
  // step_once, and where its Newton fails on a Monod block with a small half-saturation constant,
  // the same step again by continuation in that constant; a failure reports step_once's.
  NewtonResult step_or_continue(double dt, double theta, const std::string& label,
                                bool fresh_preconditioner);
  // The step from phi_old_ with K' = start, start/100, ... down to `smallest` in every Monod block.
  NewtonResult step_by_half_saturation_continuation(double dt, double theta,
                                                    const std::string& label, double start,
                                                    double smallest);
  NewtonResult steady_newton(const std::string& label);
  double storage_roundoff(double inv_dt) const;
  void impose_dirichlet(double t);
  void update_face_data(double t_eval);
  void setup_preconditioner(ConstVector phi);
  void set_step_physics(double inv_dt, double theta);
  void set_step_physics(double inv_dt, double theta, const TransportCoefficients& coefficients);
  void update_source(double t_eval);

  Mesh mesh_;
  TransportSettings settings_;
  DeviceMesh dmesh_;
  std::vector<int> all_elements_;
  ElementGroups groups_;
  NodalView aux_;  // [phi_n, w_x, w_y, w_z, c_x, c_y, c_z, s]
  SpaceTimeFunction source_;
  ElementOperator<TransportPhysics> op_;
  Linearisation<TransportPhysics> linearisation_;
  // The step's data at the quadrature points, stored when a Newton solve starts (advance): its
  // residuals and linearisations read them instead of the auxiliary fields and the geometry.
  StoredPointStates<TransportPhysics, simd_width, StepStates> step_states_;
  std::vector<FaceTerm> faces_;
  std::map<int, SpaceTimeFunction> dirichlet_;  // node -> value (later conditions win)
  Kokkos::View<char*, MemSpace> fixed_;
  IndexView fixed_dofs_;
  Vector fixed_values_;
  Vector phi_, phi_old_;
  Vector scratch_;  // constrained-zeroed direction in apply_tangent
  Vector volume_weights_;
  CsrMatrix matrix_;
  std::unique_ptr<AssembledPreconditioner> preconditioner_;
  bool has_convection_ = false;
  // The preconditioner is kept over Newton iterations and time steps (newton.reuse_preconditioner)
  // while dt, the mesh and the velocity stay the same: the Monod derivative is then the only
  // change, and a slightly stale preconditioner costs a few Krylov iterations instead of an
  // assembly and a set-up per step.
  PreconditionerReuse reuse_;
  double time_ = 0;
  TransportStats stats_;
};

}  // namespace biofsi
