// Inexact Newton: Eisenstat-Walker forcing decides how accurately each linear system is solved,
// and a backtracking line search on the residual norm globalises the iteration.
#include <algorithm>
#include <cmath>
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

NewtonResult newton_solve(const NewtonSystem& system, Vector u, const NewtonOptions& opt) {
  NewtonResult res;
  const int n = static_cast<int>(u.extent(0));
  Vector r = make_vector("biofsi::newton::r", n);
  Vector rhs = make_vector("biofsi::newton::rhs", n);
  Vector du = make_vector("biofsi::newton::du", n);
  Vector u_trial = make_vector("biofsi::newton::u_trial", n);
  Vector r_trial = make_vector("biofsi::newton::r_trial", n);

  system.residual(u, r);
  Real r_norm = norm2(r);
  res.residual_history.push_back(r_norm);
  if (!std::isfinite(r_norm)) {
    res.reason = "NaN";
    return res;
  }
  const Real tol = std::max(opt.abs_tol, opt.rel_tol * r_norm);

  const ApplyFn jacobian = [&](ConstVector x, Vector y) { system.tangent(u, x, y); };
  Real r_prev = r_norm, eta = opt.eta_max;

  while (true) {
    if (r_norm <= tol) {
      res.converged = true;
      res.reason = "converged";
      break;
    }
    if (res.iterations >= opt.max_iterations) {
      res.reason = "max iterations";
      break;
    }

    eta = forcing_term(opt, res.iterations, r_norm / r_prev, eta, 0.5 * tol / r_norm);
    if (system.linearise) system.linearise(u);
    if (system.setup_preconditioner) system.setup_preconditioner(u);
    KrylovOptions kopt = opt.krylov;
    kopt.rel_tol = eta;
    axpby(-1.0, r, 0.0, rhs);
    fill(du, 0.0);
    const KrylovResult lin = system.symmetric
                                 ? cg(jacobian, system.precondition, rhs, du, kopt)
                                 : fgmres(jacobian, system.precondition, rhs, du, kopt);
    res.krylov_iterations += lin.iterations;
    if (lin.reason == "NaN" || !std::isfinite(lin.final_residual) || !all_finite(du)) {
      res.reason = "NaN";
      break;
    }
    if (!(lin.final_residual < lin.initial_residual)) {
      res.reason = "linear solver";
      break;
    }

    // Armijo on phi = 0.5 ||r||^2. The exact slope r . J du is not computed (it would cost a
    // tangent application); the inexact-Newton bound r . J du <= -||r|| (||r|| - ||J du + r||),
    // which is negative because the Krylov solve made progress, stands in for it.
    const Real phi0 = 0.5 * r_norm * r_norm;
    const Real slope = -r_norm * (r_norm - lin.final_residual);
    Real lambda = 1.0, r_trial_norm = 0;
    bool accepted = false;
    for (int bt = 0; bt <= opt.max_backtracks; ++bt) {
      copy(u, u_trial);
      axpy(lambda, du, u_trial);
      system.residual(u_trial, r_trial);
      r_trial_norm = norm2(r_trial);
      // A non-finite trial residual (a step outside the residual's domain) is a failed trial,
      // answered by a shorter step like any other.
      if (std::isfinite(r_trial_norm) &&
          0.5 * r_trial_norm * r_trial_norm <= phi0 + armijo_c * lambda * slope) {
        accepted = true;
        break;
      }
      lambda *= 0.5;
    }
    if (!accepted) {
      res.reason = "line search failed";
      break;
    }
    copy(u_trial, u);
    std::swap(r, r_trial);
    r_prev = r_norm;
    r_norm = r_trial_norm;
    ++res.iterations;
    res.residual_history.push_back(r_norm);
  }
  return res;
}

NewtonResult retry_in_sub_steps(
    const SolveError& first, const std::string& field, const std::string& label, double dt,
    int max_cuts, const std::function<NewtonResult(double, const std::string&)>& sub_step,
    const std::function<void()>& restore, int& cut_steps) {
  for (int level = 1; level <= max_cuts; ++level) {
    const int n = 1 << level;
    try {
      NewtonResult r;
      for (int i = 0; i < n; ++i)
        r = sub_step(dt / n,
                     label + " (sub-step " + std::to_string(i + 1) + "/" + std::to_string(n) + ")");
      ++cut_steps;
      return r;
    } catch (const SolveError&) {
      restore();
    }
  }
  throw SolveError(field, label,
                   first.why() + "; cutting the step into up to " + std::to_string(1 << max_cuts) +
                       " sub-steps did not help");
}

}  // namespace biofsi
