// Preconditioned CG and right-preconditioned flexible GMRES on Kokkos vectors. Vectors stay in the
// execution space; only scalars (and GMRES' small Hessenberg system) live on the host.
#include <cmath>
#include <string>
#include <vector>

#include "solvers/solvers.hpp"

namespace biofsi {

namespace {

Vector make_vector(const std::string& label, int n) {
  return Vector(Kokkos::view_alloc(Kokkos::WithoutInitializing, label), n);
}

void apply_preconditioner(const ApplyFn& precondition, ConstVector r, Vector z) {
  if (precondition)
    precondition(r, z);
  else
    copy(r, z);
}

// r = b - A x
void true_residual(const ApplyFn& apply, ConstVector b, ConstVector x, Vector r) {
  apply(x, r);
  axpby(1.0, b, -1.0, r);
}

// A zero right-hand side has the exact solution x = 0, and a relative tolerance on ||b|| = 0 could
// never be met, so both methods answer without iterating.
bool zero_rhs(Real b_norm, Vector x, KrylovResult& res) {
  if (b_norm != 0) return false;
  fill(x, 0.0);
  res.converged = true;
  res.reason = "converged";
  return true;
}

// A non-finite right-hand side ("NaN") or a zero one (x = 0) needs no iteration; otherwise tol
// is the stopping tolerance on the residual norm.
bool answered_without_iterating(ConstVector b, Vector x, const KrylovOptions& opt,
                                KrylovResult& res, Real& tol) {
  const Real b_norm = norm2(b);
  if (!std::isfinite(b_norm)) {
    res.reason = "NaN";
    res.initial_residual = res.final_residual = b_norm;
    return true;
  }
  tol = std::max(opt.abs_tol, opt.rel_tol * b_norm);
  return zero_rhs(b_norm, x, res);
}

}  // namespace

KrylovResult cg(const ApplyFn& apply, const ApplyFn& precondition, ConstVector b, Vector x,
                const KrylovOptions& opt) {
  KrylovResult res;
  const int n = static_cast<int>(b.extent(0));
  Real tol = 0;
  if (answered_without_iterating(b, x, opt, res, tol)) return res;

  Vector r = make_vector("biofsi::cg::r", n);
  Vector z = make_vector("biofsi::cg::z", n);
  Vector p = make_vector("biofsi::cg::p", n);
  Vector q = make_vector("biofsi::cg::q", n);

  true_residual(apply, b, x, r);
  Real r_norm = norm2(r);
  res.initial_residual = r_norm;
  res.reason = "max iterations";

  // The recurrence residual drifts from b - A x in finite precision; when it claims convergence the
  // true residual decides, and CG restarts from it if the claim was wrong.
  bool restart = true, r_is_true = true;
  Real rz = 0;
  while (true) {
    if (!std::isfinite(r_norm)) {
      res.reason = "NaN";
      break;
    }
    if (r_norm <= tol) {
      if (!r_is_true) {
        true_residual(apply, b, x, r);
        r_norm = norm2(r);
        r_is_true = true;
      }
      if (r_norm <= tol) {
        res.converged = true;
        res.reason = "converged";
        break;
      }
      restart = true;
    }
    if (res.iterations >= opt.max_iterations) break;
    if (restart) {
      apply_preconditioner(precondition, r, z);
      rz = dot(r, z);
      copy(z, p);
      restart = false;
    }
    if (!(rz > 0)) {
      // A non-positive <r, M r> means the preconditioner is not SPD (or produced NaN).
      res.reason = std::isfinite(rz) ? "breakdown" : "NaN";
      break;
    }
    apply(p, q);
    const Real pq = dot(p, q);
    if (!(pq > 0)) {
      res.reason = std::isfinite(pq) ? "breakdown" : "NaN";
      break;
    }
    const Real alpha = rz / pq;
    axpy(alpha, p, x);
    axpy(-alpha, q, r);
    r_norm = norm2(r);
    r_is_true = false;
    ++res.iterations;
    if (r_norm <= tol) continue;  // the convergence check at the top needs no new z
    apply_preconditioner(precondition, r, z);
    const Real rz_new = dot(r, z);
    axpby(1.0, z, rz_new / rz, p);
    rz = rz_new;
  }

  if (!r_is_true) {
    true_residual(apply, b, x, r);
    r_norm = norm2(r);
  }
  res.final_residual = r_norm;
  return res;
}

KrylovResult fgmres(const ApplyFn& apply, const ApplyFn& precondition, ConstVector b, Vector x,
                    const KrylovOptions& opt) {
  KrylovResult res;
  const int n = static_cast<int>(b.extent(0));
  Real tol = 0;
  if (answered_without_iterating(b, x, opt, res, tol)) return res;
  const int m = std::max(1, opt.restart);

  // Krylov basis v_0..v_m and preconditioned directions z_0..z_{m-1} (flexible: the preconditioner
  // may change between applications, e.g. an inner Krylov solve or AMG with a nonlinear smoother).
  // Allocated as the first cycle reaches them, so that a solve converging in a few iterations does
  // not pay for the full restart length.
  std::vector<Vector> v, z;
  v.push_back(make_vector("biofsi::fgmres::v", n));
  Vector w = make_vector("biofsi::fgmres::w", n);

  // Hessenberg matrix, column-major (m + 1) x m, reduced to triangular form by Givens rotations.
  std::vector<Real> h((m + 1) * m), cs(m), sn(m), g(m + 1), y(m);
  auto H = [&](int i, int j) -> Real& { return h[i + j * (m + 1)]; };

  true_residual(apply, b, x, v[0]);
  Real beta = norm2(v[0]);
  res.initial_residual = beta;
  res.reason = "max iterations";

  while (true) {
    if (!std::isfinite(beta)) {
      res.reason = "NaN";
      break;
    }
    if (beta <= tol) {
      res.converged = true;
      res.reason = "converged";
      break;
    }
    if (res.iterations >= opt.max_iterations) break;

    scale(1.0 / beta, v[0]);
    std::fill(g.begin(), g.end(), 0.0);
    g[0] = beta;
    int k = 0;  // columns built in this cycle
    bool happy = false, nan = false;
    while (k < m && res.iterations < opt.max_iterations) {
      const int j = k;
      if (static_cast<int>(z.size()) <= j) z.push_back(make_vector("biofsi::fgmres::z", n));
      if (static_cast<int>(v.size()) <= j + 1) v.push_back(make_vector("biofsi::fgmres::v", n));
      apply_preconditioner(precondition, v[j], z[j]);
      apply(z[j], w);
      // Modified Gram-Schmidt: orthogonalise against each basis vector in turn, which keeps the
      // basis orthogonal to working precision for the restart lengths used here.
      for (int i = 0; i <= j; ++i) {
        H(i, j) = dot(w, v[i]);
        axpy(-H(i, j), v[i], w);
      }
      H(j + 1, j) = norm2(w);
      if (!std::isfinite(H(j + 1, j))) {
        nan = true;
        break;
      }
      const Real h_next = H(j + 1, j);
      for (int i = 0; i < j; ++i) {
        const Real t = cs[i] * H(i, j) + sn[i] * H(i + 1, j);
        H(i + 1, j) = -sn[i] * H(i, j) + cs[i] * H(i + 1, j);
        H(i, j) = t;
      }
      const Real denom = std::hypot(H(j, j), H(j + 1, j));
      if (denom == 0) {
        // The new direction is in the span of the old ones and H is singular: no progress possible.
        res.reason = "breakdown";
        break;
      }
      cs[j] = H(j, j) / denom;
      sn[j] = H(j + 1, j) / denom;
      H(j, j) = denom;
      H(j + 1, j) = 0;
      g[j + 1] = -sn[j] * g[j];
      g[j] = cs[j] * g[j];
      ++k;
      ++res.iterations;
      // An invariant subspace ("happy breakdown"): the cycle's solution is exact.
      if (h_next <= 1e-14 * beta) {
        happy = true;
        break;
      }
      copy(w, v[j + 1]);
      scale(1.0 / h_next, v[j + 1]);
      if (std::abs(g[j + 1]) <= tol) break;
    }
    if (nan) {
      // x is left at the last finite iterate: the caller's state is not corrupted.
      res.reason = "NaN";
      break;
    }
    // Back substitution for y in the triangular k x k system R y = g, then x += Z y.
    for (int i = k - 1; i >= 0; --i) {
      Real s = g[i];
      for (int l = i + 1; l < k; ++l) s -= H(i, l) * y[l];
      y[i] = s / H(i, i);
    }
    for (int i = 0; i < k; ++i) axpy(y[i], z[i], x);
    true_residual(apply, b, x, v[0]);
    beta = norm2(v[0]);
    if (std::isfinite(beta) && beta <= tol) continue;  // the check at the top reports convergence
    if (res.reason == "breakdown") break;
    if (happy && std::isfinite(beta)) {
      // An exact cycle solution whose true residual still misses the tolerance: restarting would
      // reproduce the same subspace, so stop instead of looping.
      res.reason = "breakdown";
      break;
    }
  }

  res.final_residual = beta;
  return res;
}

}  // namespace biofsi
