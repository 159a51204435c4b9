// src/solvers: Krylov methods on Kokkos Views, hypre BoomerAMG on an assembled matrix, the one
// Newton method of every field and of the FSI (inexact forcing, pluggable line search, block
// norms, round-off floors, admissible states, when to set the preconditioner up) and the
// time-stepping helpers (step cutting,
// pseudo-transient continuation), all field-independent.
// What it may include: kernels/core, hypre, MPI. Fields (src/scalar, ...) and the driver depend on
// it; it depends on no field.
#pragma once

#include <chrono>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "kernels/core/csr.hpp"
#include "kernels/core/types.hpp"

namespace biofsi {

// ---- vector operations (Kokkos reductions in the execution space) ----
Real dot(ConstVector a, ConstVector b);
Real norm2(ConstVector a);
Real max_abs(ConstVector a);  // max_i |a_i|
bool all_finite(ConstVector a);
void axpy(Real alpha, ConstVector x, Vector y);              // y += alpha x
void axpby(Real alpha, ConstVector x, Real beta, Vector y);  // y = alpha x + beta y
void scale(Real alpha, Vector x);                            // x *= alpha
void fill(Vector x, Real value);
void copy(ConstVector from, Vector to);

// Host and device copies of 1-D views (set-up, output and verification; never inside solver
// loops): any element type (dof values, indices, masks).
template <class View>
std::vector<typename View::non_const_value_type> to_host(const View& d) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), d);
  return std::vector<typename View::non_const_value_type>(h.data(), h.data() + h.extent(0));
}
template <class T>
Kokkos::View<T*, MemSpace> to_device(const std::vector<T>& v, const std::string& label) {
  Kokkos::View<T*, MemSpace> d(label, v.size());
  auto h = Kokkos::create_mirror_view(d);
  for (size_t i = 0; i < v.size(); ++i) h(i) = v[i];
  Kokkos::deep_copy(d, h);
  return d;
}
inline std::vector<double> to_host_vector(ConstVector d) { return to_host(d); }
inline Vector to_device_vector(const std::vector<double>& v, const std::string& label) {
  return to_device(v, label);
}

// Accumulates the fenced wall time of a scope into `seconds` (per-phase timings of the fields).
class ScopedTimer {
 public:
  explicit ScopedTimer(double& seconds)
      : seconds_(seconds), start_(std::chrono::steady_clock::now()) {}
  ~ScopedTimer() {
    Kokkos::fence();
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  double& seconds_;
  std::chrono::steady_clock::time_point start_;
};

// y = A x for an operator that is only known by its action.
using ApplyFn = std::function<void(ConstVector x, Vector y)>;

struct KrylovOptions {
  Real rel_tol = 1e-8;  // on ||r|| / ||b||
  Real abs_tol = 0.0;   // on ||r||
  int max_iterations = 1000;
  int restart = 50;  // (F)GMRES only
};

struct KrylovResult {
  bool converged = false;
  int iterations = 0;
  Real initial_residual = 0;  // ||b - A x0||
  Real final_residual = 0;    // ||b - A x|| (true residual, recomputed at exit)
  std::string reason;         // "converged", "max iterations", "breakdown", "NaN"
};

// Preconditioned CG for SPD operators; `precondition` may be empty (identity).
KrylovResult cg(const ApplyFn& apply, const ApplyFn& precondition, ConstVector b, Vector x,
                const KrylovOptions& opt);
// Right-preconditioned flexible GMRES(restart) for general operators.
KrylovResult fgmres(const ApplyFn& apply, const ApplyFn& precondition, ConstVector b, Vector x,
                    const KrylovOptions& opt);

struct AmgOptions {
  int num_functions = 1;          // unknowns per node (systems AMG when > 1)
  bool nodal_coarsening = false;  // BoomerAMG nodal option for systems
  Real strong_threshold = 0.25;
  int max_levels = 25;
  int cycles = 1;  // V-cycles per preconditioner application
  // Levels of aggressive coarsening from the finest level down: a cheaper set-up for a few more
  // iterations (48^3 Poisson, 2 cores: set-up 0.43 s -> 0.16 s, AMG-CG 8 -> 11 iterations), worth
  // it where the hierarchy is rebuilt every Newton iteration.
  int aggressive_levels = 0;
  int print_level = 0;
  // Near-null-space vectors for systems AMG (num_functions > 1 with nodal coarsening), e.g. the
  // rigid-body rotations of elasticity, each of length n_rows: BoomerAMG's interpolation-vector
  // variant (GM-2, with hypre's recommended nodal norm 4 and smoothed vectors) fits them exactly in
  // the interpolation, which the plain nodal interpolation cannot do for rotations.
  std::vector<std::vector<Real>> interpolation_vectors;
};

// A preconditioner built from an assembled matrix: set up once per matrix, applied at every
// Krylov iteration (BoomerAMG, the sparse LU, the fluid's block preconditioners).
class AssembledPreconditioner {
 public:
  AssembledPreconditioner() = default;
  virtual ~AssembledPreconditioner() = default;
  AssembledPreconditioner(const AssembledPreconditioner&) = delete;
  AssembledPreconditioner& operator=(const AssembledPreconditioner&) = delete;
  virtual void setup(const CsrMatrix& a) = 0;
  virtual void apply(ConstVector r, Vector z) const = 0;
};

// BoomerAMG on a CSR matrix (copied to a hypre IJ/ParCSR matrix; single rank: global row ids equal
// local ones, the rows are the rank's owned rows). apply() runs `cycles` V-cycles from a zero
// guess.
class BoomerAmg : public AssembledPreconditioner {
 public:
  explicit BoomerAmg(const AmgOptions& opt = {});
  ~BoomerAmg() override;

  void setup(const CsrMatrix& a) override;
  void apply(ConstVector r, Vector z) const override;
  ApplyFn as_function() const;
  int levels() const;
  double setup_seconds() const { return setup_seconds_; }

 private:
  struct Impl;
  Impl* impl_ = nullptr;
  AmgOptions opt_;
  double setup_seconds_ = 0;
};

// Sparse LU factorisation of an assembled matrix (UMFPACK, its own fill-reducing ordering), used as
// an exact preconditioner where the factors stay small: pseudo-2-D and small 3-D problems, whose
// block-preconditioned Krylov solves otherwise need hundreds of iterations (bench/README.md). The
// symbolic analysis is kept while the sparsity pattern is unchanged, so a Newton step refactors
// numerically only. Runs on the host, one thread; vectors cross to host memory at each application.
class SparseLu : public AssembledPreconditioner {
 public:
  SparseLu();
  ~SparseLu() override;

  // Throws std::runtime_error when the matrix is structurally or numerically singular.
  void setup(const CsrMatrix& a) override;
  void apply(ConstVector r, Vector z) const override;
  // Nonzeros of the L and U factors (their fill), for the summary and the bench.
  long factor_nonzeros() const;

 private:
  struct Impl;
  Impl* impl_ = nullptr;
};

// A failed solve: names the field, the step and why.
class SolveError : public std::runtime_error {
 public:
  SolveError(const std::string& field, const std::string& step, const std::string& why)
      : std::runtime_error(field + ": " + step + ": " + why),
        field_(field),
        step_(step),
        why_(why) {}
  const std::string& field() const { return field_; }
  const std::string& step() const { return step_; }
  const std::string& why() const { return why_; }

 private:
  std::string field_, step_, why_;
};

// A field's assembled preconditioner kept across Newton iterations, Newton solves and time steps
// while it still serves (NewtonOptions::reuse_preconditioner). The Jacobian action stays exact
// (matrix-free), so only the Krylov iterations can change: the preconditioner is set up again when
// a linear solve needs more than 1.5 times (plus 3) the Krylov iterations of the first solve after
// the last set-up, or more than a quarter of the Krylov limit, when a solve with it does not
// converge within a quarter of the limit (that solve is then repeated with a fresh one), and when
// the coefficients it was built with change. The field owns one per preconditioner and says what
// else makes it stale.
class PreconditionerReuse {
 public:
  // Coefficients the assembled matrix depends on besides the state (1/dt, theta, the interface's
  // velocity factor): a change forces the next set-up.
  void require(std::vector<Real> coefficients);
  // Something the count cannot see made it stale (the field's own set-up was replaced, a step was
  // restored after a failure): the next Newton iteration sets it up.
  void invalidate() { built_ = false; }
  bool still_serves(int krylov_limit) const;
  void record_setup();
  void record_reuse() { ++reuses_; }
  void record_solve(int krylov_iterations);
  int setups() const { return setups_; }
  int reuses() const { return reuses_; }

 private:
  bool built_ = false;
  std::vector<Real> coefficients_, built_with_;
  int baseline_ = -1, last_ = 0, setups_ = 0, reuses_ = 0;
};

// What Newton needs from a field. Residuals include constraints: constrained rows are zero once the
// iterate satisfies them, and tangent() acts as identity on constrained dofs.
struct NewtonSystem {
  std::function<void(ConstVector u, Vector r)> residual;
  std::function<void(ConstVector u, ConstVector du, Vector y)> tangent;  // y = J(u) du
  // Called once per Newton iteration at the iterate u before the preconditioner and the Krylov
  // solve (may be empty): a field stores its tangent at u there, and tangent() applies the stored
  // one until the next call.
  std::function<void(ConstVector u)> linearise;
  // Called once per Newton iteration before the linear solve (assemble + AMG set-up); may be empty.
  std::function<void(ConstVector u)> setup_preconditioner;
  ApplyFn precondition;    // may be empty
  bool symmetric = false;  // CG if true, FGMRES otherwise
  // The preconditioner's age; with NewtonOptions::reuse_preconditioner it decides whether
  // setup_preconditioner runs (may be null: set up at every Newton iteration).
  PreconditionerReuse* reuse = nullptr;

  // Optional pieces; left empty, Newton measures the whole residual with one norm.
  // Blocks [first, last) of the unknowns whose residuals are measured, and converge, separately
  // (the fields of a coupled problem, whose units differ).
  std::vector<std::pair<int, int>> blocks;
  // Per block, the round-off level of its residual at the iterate u, below which no iteration can
  // reduce it: a block that reaches it has converged (from the second iterate on).
  std::function<std::vector<Real>(ConstVector u)> roundoff_floors;
  // False for a state outside the residual's domain (an element turned inside out): the line
  // search then tries a shorter step.
  std::function<bool(ConstVector u)> admissible;
};

// A field's system whose residual and stored-tangent application add their wall time to the
// field's statistics; the caller adds the preconditioner and the optional pieces.
NewtonSystem timed_newton_system(std::function<void(ConstVector u, Vector r)> residual,
                                 std::function<void(ConstVector u)> linearise,
                                 std::function<void(ConstVector du, Vector y)> apply_linearised,
                                 double& seconds_residual, double& seconds_tangent);

enum class LineSearch {
  // Backtracking (halving) on ||r||^2 with the Armijo test on the inexact-Newton slope bound.
  ResidualArmijo,
  // On G(s) = du . r(u + s du), the derivative of the potential energy along du for conservative
  // problems: s = 1 when |G(1)| <= 0.8 |G(0)| or ||r|| fell, otherwise regula falsi on G for up to
  // 8 trials in s in [0.05, 1], keeping the trial of smallest ||r||; halving on ||r|| when du is
  // not a descent direction (indefinite tangent). For slender or soft bodies under large
  // rotations, whose stiff directions dominate ||r||.
  EnergyRegulaFalsi,
  // Halving on the block-scaled merit sum_i (||r_i|| / scale_i)^2 until it falls by 2e-4 lambda,
  // keeping the best trial.
  BlockMerit
};

struct NewtonOptions {
  Real rel_tol = 1e-10;  // on ||r|| / ||r0|| (per block: of that block)
  Real abs_tol = 1e-14;  // on ||r||
  int max_iterations = 25;
  // Eisenstat-Walker (choice 2) forcing: eta_k = gamma (||r_k|| / ||r_{k-1}||)^alpha, clipped to
  // [eta_min, eta_max]; eta_max also bounds the first linear solve.
  Real eta_max = 1e-2, eta_min = 1e-10, gamma = 0.9, alpha = 2.0;
  int max_backtracks = 20;  // line-search trials after the full step
  KrylovOptions krylov;     // rel_tol is replaced by the forcing term
  LineSearch line_search = LineSearch::ResidualArmijo;
  // Solve for the residual scaled block by block to unit norm (so one block's units cannot hide
  // another's error); the forcing term then follows the scaled residual.
  bool scale_blocks = false;
  // The relative tolerance of each block against the largest residual it had in the solve
  // (false: against the initial one).
  bool tolerance_from_largest = false;
  // The forcing term's floor: this factor times the eta at which the next iterate would already
  // meet the tolerance (solving more accurately than that is wasted work); with
  // `floor_includes_roundoff`, the tolerance there includes the round-off floors.
  Real forcing_floor_factor = 0.5;
  bool floor_includes_roundoff = false;
  // Keep the assembled preconditioner while it serves (PreconditionerReuse; needs
  // NewtonSystem::reuse), instead of setting it up at every Newton iteration.
  bool reuse_preconditioner = true;
};

struct NewtonResult {
  bool converged = false;
  int iterations = 0;
  int krylov_iterations = 0;           // summed over all Newton iterations
  std::vector<Real> residual_history;  // ||r|| at every iterate, starting with the initial one
  // Per iterate, each block's residual norm (one entry without blocks), and per Newton iteration
  // its Krylov iterations.
  std::vector<std::vector<Real>> block_history;
  std::vector<int> krylov_history;
  std::string
      reason;  // "converged", "max iterations", "line search failed", "NaN", "linear solver"
};

// Why a field's Newton solve failed (it did not converge, or converged to a non-finite state):
// "diverged: Newton <reason> after N iterations; residual history: r0 r1 ...".
std::string newton_failure(const NewtonResult& result);

// A time step that failed with `first`, retried as 2, 4, ... 2^max_cuts sub-steps: sub_step(dt,
// label) takes one; restore() puts the fields back to the step's start after a failed try, so
// that a failure leaves the last valid state. A success counts in cut_steps; when every level
// fails, throws SolveError(field, label, why first failed and that cutting did not help).
NewtonResult retry_in_sub_steps(
    const SolveError& first, const std::string& field, const std::string& label, double dt,
    int max_cuts, const std::function<NewtonResult(double, const std::string&)>& sub_step,
    const std::function<void()>& restore, int& cut_steps);

// A steady solve, steady(label), continued in pseudo-time if it fails (and max_steps > 0): from
// the state it started from (`state` restored, then restored()), backward-Euler pseudo-time steps
// pseudo_step(dt, label) (SolveError on failure; `time`, the physical time, is put back after
// each), the step doubled after a success (counted in pseudo_steps) and quartered after a
// failure; once a step changes `state` by less than 1e-3 of its norm, steady(label) is tried
// again. Without a steady solution after max_steps pseudo-time steps, the start is restored and
// SolveError(field, label, why the first solve failed and that continuation did not help) thrown.
NewtonResult solve_steady_with_continuation(
    const std::string& field, const std::string& label, Vector state, double& time, int max_steps,
    double dt0, const std::function<NewtonResult(const std::string&)>& steady,
    const std::function<void(double, const std::string&)>& pseudo_step,
    const std::function<void()>& restored, int& pseudo_steps);

// Eisenstat-Walker choice 2 for Newton iteration k: gamma contraction^alpha (contraction =
// ||r_k|| / ||r_{k-1}||), with their safeguard against a sudden drop of eta when the previous one
// was already large, and `floor`: the eta at which the next iterate would already meet the
// nonlinear tolerance (solving more accurately than that is wasted work, and below round-off it
// only exhausts the Krylov iterations). Clipped to [eta_min, eta_max].
Real forcing_term(const NewtonOptions& opt, int k, Real contraction, Real eta_prev, Real floor);

// Solves residual(u) = 0 starting from u (updated in place) by inexact Newton: Eisenstat-Walker
// forcing decides how accurately each linear system is solved, and the options' line search
// globalises the iteration. Never throws for non-convergence: the caller decides (and raises
// SolveError with its field and step).
NewtonResult newton_solve(const NewtonSystem& system, Vector u, const NewtonOptions& opt);

}  // namespace biofsi
