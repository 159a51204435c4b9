// Inexact Newton with pluggable pieces (blocks, line search, round-off floors, admissible states):
// the one Newton of every field and of the coupled FSI system.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "solvers/solvers.hpp"

namespace biofsi {

namespace {

// Sufficient-decrease constant of the Armijo test (the customary 1e-4: accept nearly any
// decrease that is proportional to the predicted one).
constexpr Real armijo_c = 1e-4;

Vector make_vector(const std::string& label, int n) {
  return Vector(Kokkos::view_alloc(Kokkos::WithoutInitializing, label), n);
}

}  // namespace

Real forcing_term(const NewtonOptions& opt, int k, Real contraction, Real eta_prev, Real floor) {
  Real eta = opt.eta_max;
  if (k > 0) {
    eta = opt.gamma * std::pow(contraction, opt.alpha);
    const Real from_prev = opt.gamma * std::pow(eta_prev, opt.alpha);
    if (from_prev > 0.1) eta = std::max(eta, from_prev);
  }
  eta = std::max(std::min(eta, opt.eta_max), floor);
  return std::max(std::min(eta, opt.eta_max), opt.eta_min);
}

namespace {

using Blocks = std::vector<std::pair<int, int>>;

Blocks blocks_of(const NewtonSystem& system, int n) {
  return system.blocks.empty() ? Blocks{{0, n}} : system.blocks;
}

std::vector<Real> block_norms(const Blocks& blocks, ConstVector r) {
  if (blocks.size() == 1 && blocks[0].first == 0 && blocks[0].second == int(r.extent(0)))
    return {norm2(r)};
  std::vector<Real> norms;
  for (const auto& b : blocks) norms.push_back(norm2(Kokkos::subview(r, b)));
  return norms;
}

Real total_norm(const std::vector<Real>& norms) {
  if (norms.size() == 1) return norms[0];
  Real sum = 0;
  for (Real v : norms) sum += v * v;
  return std::sqrt(sum);
}

// r := r / scale block by block.
void divide_blocks(const Blocks& blocks, const std::vector<Real>& scale, Vector r) {
  for (size_t i = 0; i < blocks.size(); ++i)
    biofsi::scale(1.0 / scale[i], Kokkos::subview(r, blocks[i]));
}

struct Workspace {
  Vector r, rhs, du, trial, r_trial, best, r_best, work;
  explicit Workspace(int n)
      : r(make_vector("biofsi::newton::r", n)),
        rhs(make_vector("biofsi::newton::rhs", n)),
        du(make_vector("biofsi::newton::du", n)),
        trial(make_vector("biofsi::newton::trial", n)),
        r_trial(make_vector("biofsi::newton::r_trial", n)) {}
};

// The iterate and what the line search needs of the step just solved for.
struct Iterate {
  std::vector<Real> norms;   // per block, of the residual at u
  std::vector<Real> scale;   // per block, the merit's scale
  Real r_norm = 0;           // total
  Real linear_residual = 0;  // ||J du + r|| left by the Krylov solve
};

struct Accepted {
  bool ok = false;
  bool any_admissible = true;
  std::vector<Real> norms;
  Real ratio = 1;  // contraction of the (merit) norm, for the forcing term
};

bool admissible(const NewtonSystem& system, ConstVector u) {
  return !system.admissible || system.admissible(u);
}

// Armijo on phi = 0.5 ||r||^2. The exact slope r . J du is not computed (it would cost a tangent
// application); the inexact-Newton bound r . J du <= -||r|| (||r|| - ||J du + r||), which is
// negative because the Krylov solve made progress, stands in for it.
Accepted residual_armijo(const NewtonSystem& system, const NewtonOptions& opt, const Blocks& blocks,
                         const Iterate& it, Vector u, Workspace& w) {
  Accepted a;
  const Real phi0 = 0.5 * it.r_norm * it.r_norm;
  const Real slope = -it.r_norm * (it.r_norm - it.linear_residual);
  Real lambda = 1.0;
  for (int bt = 0; bt <= opt.max_backtracks; ++bt, lambda *= 0.5) {
    copy(u, w.trial);
    axpy(lambda, w.du, w.trial);
    if (!admissible(system, w.trial)) continue;
    system.residual(w.trial, w.r_trial);
    const std::vector<Real> norms = block_norms(blocks, w.r_trial);
    const Real r_trial_norm = total_norm(norms);
    // A non-finite trial residual (a step outside the residual's domain) is a failed trial,
    // answered by a shorter step like any other.
    if (std::isfinite(r_trial_norm) &&
        0.5 * r_trial_norm * r_trial_norm <= phi0 + armijo_c * lambda * slope) {
      copy(w.trial, u);
      std::swap(w.r, w.r_trial);
      a.ok = true;
      a.norms = norms;
      a.ratio = r_trial_norm / it.r_norm;
      return a;
    }
  }
  return a;
}

Accepted energy_regula_falsi(const NewtonSystem& system, const NewtonOptions& opt,
                             const Blocks& blocks, const Iterate& it, Vector u, Workspace& w) {
  Accepted a;
  const int n = static_cast<int>(u.extent(0));
  if (w.best.extent(0) == 0) {
    w.best = make_vector("biofsi::newton::best", n);
    w.r_best = make_vector("biofsi::newton::r_best", n);
  }
  const Real r_norm = it.r_norm;
  const Real g0 = dot(w.du, w.r);  // < 0 for a descent direction of the energy
  Real lo = 0, g_lo = g0, hi = 1, s = 1, best_norm = std::numeric_limits<Real>::infinity();
  // An indefinite tangent (compressed fibres, buckling) can give a direction along which the
  // energy rises (G(0) >= 0): then plain halving on ||r||.
  const bool descent = g0 < 0;
  for (int trial_no = 0; trial_no <= opt.max_backtracks && (!descent || trial_no < 8); ++trial_no) {
    copy(u, w.trial);
    axpy(s, w.du, w.trial);
    if (!admissible(system, w.trial)) {
      hi = s;
      s = 0.5 * (lo + s);
      continue;
    }
    system.residual(w.trial, w.r_trial);
    const Real rn = norm2(w.r_trial);
    if (std::isfinite(rn) && rn < best_norm) {
      best_norm = rn;
      copy(w.trial, w.best);
      copy(w.r_trial, w.r_best);
    }
    if (!descent) {
      if (std::isfinite(rn) && rn < (1 - 1e-4 * s) * r_norm) break;
      s *= 0.5;
      continue;
    }
    const Real g =
        std::isfinite(rn) ? dot(w.du, w.r_trial) : std::numeric_limits<Real>::quiet_NaN();
    if (std::isfinite(g) && (std::abs(g) <= 0.8 * std::abs(g0) || (trial_no == 0 && rn < r_norm)))
      break;
    if (!std::isfinite(g) || g > 0) {
      hi = s;
      // Regula falsi between the last point with G < 0 and this one (bisection after a NaN).
      s = std::isfinite(g) ? lo + (s - lo) * (-g_lo) / (g - g_lo) : 0.5 * (lo + s);
    } else {
      lo = s, g_lo = g;
      s = 0.5 * (s + hi);
      if (hi == s) break;
    }
    s = std::min(std::max(s, 0.05), 1.0);
  }
  if (!std::isfinite(best_norm)) return a;
  copy(w.best, u);
  copy(w.r_best, w.r);
  a.ok = true;
  a.norms = block_norms(blocks, w.r);
  a.ratio = best_norm / r_norm;
  return a;
}

Accepted block_merit(const NewtonSystem& system, const NewtonOptions& opt, const Blocks& blocks,
                     const Iterate& it, Vector u, Workspace& w) {
  Accepted a;
  auto merit_of = [&](const std::vector<Real>& norms) {
    Real m = 0;
    for (size_t i = 0; i < norms.size(); ++i) m += std::pow(norms[i] / it.scale[i], 2);
    return m;
  };
  const Real merit0 = merit_of(it.norms);
  Real lambda = 1, best = std::numeric_limits<Real>::infinity(), best_lambda = 0;
  std::vector<Real> best_norms;
  int admissible_trials = 0;
  for (int bt = 0; bt <= opt.max_backtracks; ++bt) {
    copy(u, w.trial);
    axpy(lambda, w.du, w.trial);
    if (!admissible(system, w.trial)) {  // an inadmissible state: a shorter step
      lambda *= 0.5;
      continue;
    }
    ++admissible_trials;
    system.residual(w.trial, w.r_trial);
    const std::vector<Real> norms = block_norms(blocks, w.r_trial);
    const Real merit = merit_of(norms);
    if (std::isfinite(merit) && merit < best) {
      best = merit;
      best_lambda = lambda;
      best_norms = norms;
    }
    if (std::isfinite(merit) && merit <= (1 - 2e-4 * lambda) * merit0) break;
    lambda *= 0.5;
  }
  a.any_admissible = admissible_trials > 0;
  if (!(best < merit0)) return a;
  if (best_lambda != lambda) {  // the last trial was not the best one: redo the best
    copy(u, w.trial);
    axpy(best_lambda, w.du, w.trial);
    system.residual(w.trial, w.r_trial);
  }
  copy(w.trial, u);
  copy(w.r_trial, w.r);
  a.ok = true;
  a.norms = best_norms;
  a.ratio = std::sqrt(best / merit0);
  return a;
}

// One linear solve J du = -r from du = 0 at the Krylov options' tolerance; with
// NewtonOptions::scale_blocks, of the system scaled block by block to unit residual norm.
KrylovResult solve_linear(const NewtonSystem& system, const NewtonOptions& opt,
                          const KrylovOptions& kopt, const Blocks& blocks,
                          const std::vector<Real>& scale, ConstVector u, Workspace& w) {
  fill(w.du, 0.0);
  if (!opt.scale_blocks) {
    axpby(-1.0, w.r, 0.0, w.rhs);
    const ApplyFn jacobian = [&](ConstVector x, Vector y) { system.tangent(u, x, y); };
    return system.symmetric ? cg(jacobian, system.precondition, w.rhs, w.du, kopt)
                            : fgmres(jacobian, system.precondition, w.rhs, w.du, kopt);
  }
  // D J du = -D r with D = diag(1 / scale) per block, preconditioned by P D^-1.
  if (w.work.extent(0) == 0) w.work = make_vector("biofsi::newton::work", w.r.extent(0));
  copy(w.r, w.rhs);
  divide_blocks(blocks, scale, w.rhs);
  biofsi::scale(-1.0, w.rhs);
  std::vector<Real> inverse(scale.size());
  for (size_t i = 0; i < scale.size(); ++i) inverse[i] = 1 / scale[i];
  const ApplyFn jacobian = [&](ConstVector x, Vector y) {
    system.tangent(u, x, y);
    divide_blocks(blocks, scale, y);
  };
  // P approximates J^-1, so P D^-1 approximates (D J)^-1; without P, none.
  ApplyFn precondition;
  if (system.precondition)
    precondition = [&](ConstVector x, Vector z) {
      copy(x, w.work);
      divide_blocks(blocks, inverse, w.work);
      system.precondition(w.work, z);
    };
  return system.symmetric ? cg(jacobian, precondition, w.rhs, w.du, kopt)
                          : fgmres(jacobian, precondition, w.rhs, w.du, kopt);
}

}  // namespace

void PreconditionerReuse::require(std::vector<Real> coefficients) {
  coefficients_ = std::move(coefficients);
}

bool PreconditionerReuse::still_serves(int krylov_limit) const {
  if (!built_ || coefficients_ != built_with_) return false;
  return baseline_ < 0 || last_ <= std::min(baseline_ * 3 / 2 + 3, krylov_limit / 4);
}

void PreconditionerReuse::record_setup() {
  built_ = true;
  built_with_ = coefficients_;
  baseline_ = -1;
  ++setups_;
}

void PreconditionerReuse::record_solve(int krylov_iterations) {
  last_ = krylov_iterations;
  if (baseline_ < 0) baseline_ = krylov_iterations;
}

NewtonResult newton_solve(const NewtonSystem& system, Vector u, const NewtonOptions& opt) {
  NewtonResult res;
  const int n = static_cast<int>(u.extent(0));
  const Blocks blocks = blocks_of(system, n);
  const size_t nb = blocks.size();
  Workspace w(n);

  system.residual(u, w.r);
  Iterate it;
  it.norms = block_norms(blocks, w.r);
  it.r_norm = total_norm(it.norms);
  std::vector<Real> reference = it.norms;
  res.residual_history.push_back(it.r_norm);
  res.block_history.push_back(it.norms);
  if (!std::isfinite(it.r_norm)) {
    res.reason = "NaN";
    return res;
  }

  Real eta = opt.eta_max, ratio = 1;
  while (true) {
    // The round-off floor grows with the solution, so it is re-evaluated at every iterate.
    std::vector<Real> floors(nb, 0.0);
    if (res.iterations > 0 && system.roundoff_floors) floors = system.roundoff_floors(u);
    std::vector<Real> tol(nb), tol_floor(nb);
    bool done = true;
    for (size_t i = 0; i < nb; ++i) {
      if (opt.tolerance_from_largest) reference[i] = std::max(reference[i], it.norms[i]);
      tol[i] = std::max(opt.abs_tol, opt.rel_tol * reference[i]);
      tol_floor[i] = std::max(tol[i], floors[i]);
      done = done && it.norms[i] <= tol_floor[i];
    }
    if (done) {
      res.converged = true;
      res.reason = "converged";
      break;
    }
    if (res.iterations >= opt.max_iterations) {
      res.reason = "max iterations";
      break;
    }
    it.scale.assign(nb, 1.0);
    if (opt.scale_blocks) {
      for (size_t i = 0; i < nb; ++i) it.scale[i] = std::max(it.norms[i], tol_floor[i]);
      const Real largest = *std::max_element(it.scale.begin(), it.scale.end());
      for (auto& s : it.scale)
        if (s == 0) s = largest;  // a block that is zero throughout: neutral weight
    }
    Real needed = 1;
    for (size_t i = 0; i < nb; ++i)
      if (it.norms[i] > 0)
        needed =
            std::min(needed, (opt.floor_includes_roundoff ? tol_floor[i] : tol[i]) / it.norms[i]);
    eta = forcing_term(opt, res.iterations, ratio, eta, opt.forcing_floor_factor * needed);

    if (system.linearise) system.linearise(u);
    KrylovOptions kopt = opt.krylov;
    kopt.rel_tol = eta;
    const bool reuse = opt.reuse_preconditioner && system.reuse && system.setup_preconditioner;
    const auto set_up = [&] {
      if (!system.setup_preconditioner) return;
      system.setup_preconditioner(u);
      if (system.reuse) system.reuse->record_setup();
    };
    const bool reused = reuse && system.reuse->still_serves(kopt.max_iterations);
    if (reused)
      system.reuse->record_reuse();
    else
      set_up();
    // An aged preconditioner gets a quarter of the Krylov limit: one that has gone stale (the
    // state moved far since its set-up) stalls, and the solve is repeated with a fresh one.
    KrylovOptions aged = kopt;
    aged.max_iterations = std::max(1, kopt.max_iterations / 4);
    KrylovResult lin = solve_linear(system, opt, reused ? aged : kopt, blocks, it.scale, u, w);
    int spent = 0;
    if (reused && !lin.converged) {
      spent = lin.iterations;
      set_up();
      lin = solve_linear(system, opt, kopt, blocks, it.scale, u, w);
    }
    if (system.reuse) system.reuse->record_solve(lin.iterations);
    lin.iterations += spent;
    res.krylov_iterations += lin.iterations;
    res.krylov_history.push_back(lin.iterations);
    if (lin.reason == "NaN" || !std::isfinite(lin.final_residual) || !all_finite(w.du)) {
      res.reason = "NaN";
      break;
    }
    if (!(lin.final_residual < lin.initial_residual)) {
      res.reason = "linear solver";
      break;
    }
    it.linear_residual = lin.final_residual;

    Accepted a;
    switch (opt.line_search) {
      case LineSearch::ResidualArmijo:
        a = residual_armijo(system, opt, blocks, it, u, w);
        break;
      case LineSearch::EnergyRegulaFalsi:
        a = energy_regula_falsi(system, opt, blocks, it, u, w);
        break;
      case LineSearch::BlockMerit:
        a = block_merit(system, opt, blocks, it, u, w);
        break;
    }
    if (!a.ok) {
      res.reason = a.any_admissible
                       ? "line search failed"
                       : "line search failed: every trial step turned an element inside out";
      break;
    }
    ratio = a.ratio;
    it.norms = a.norms;
    it.r_norm = total_norm(it.norms);
    ++res.iterations;
    res.residual_history.push_back(it.r_norm);
    res.block_history.push_back(it.norms);
  }
  return res;
}

NewtonSystem timed_newton_system(std::function<void(ConstVector u, Vector r)> residual,
                                 std::function<void(ConstVector u)> linearise,
                                 std::function<void(ConstVector du, Vector y)> apply_linearised,
                                 double& seconds_residual, double& seconds_tangent) {
  NewtonSystem sys;
  sys.residual = [residual, &seconds_residual](ConstVector u, Vector r) {
    ScopedTimer t(seconds_residual);
    residual(u, r);
  };
  sys.linearise = std::move(linearise);
  sys.tangent = [apply_linearised, &seconds_tangent](ConstVector, ConstVector du, Vector y) {
    ScopedTimer t(seconds_tangent);
    apply_linearised(du, y);
  };
  return sys;
}

std::string newton_failure(const NewtonResult& result) {
  std::ostringstream why;
  why << "diverged: Newton ";
  if (!result.converged && result.reason == "NaN")
    why << "produced NaN";
  else if (!result.converged)
    why << result.reason;
  else
    why << "returned a non-finite state";
  why << " after " << result.iterations << " iterations; residual history:";
  for (double r : result.residual_history) why << ' ' << r;
  return why.str();
}

}  // namespace biofsi
