// Newton's method: quadratic convergence with tight forcing, Eisenstat-Walker forcing saving
// Krylov work, the line search globalising a problem on which plain Newton diverges, and failures
// (NaN, no linear progress, iteration limit) reported through the result instead of exceptions;
// the optional pieces: per-block norms and tolerances, admissible states, the energy line search
// and round-off floors; keeping the preconditioner while it serves (PreconditionerReuse).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include "solvers/solvers.hpp"
#include "test_matrices.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

using Policy = Kokkos::RangePolicy<ExecSpace>;

// ---- A u + c u^3 = f: a discrete semilinear elliptic problem (A: scaled 7-point Laplacian) ----

void cubic_residual(const CsrMatrix& a, Real c, ConstVector f, ConstVector u, Vector r) {
  csr_multiply(a, u, r);
  Kokkos::parallel_for(
      "test::cubic_residual", Policy(0, a.n_rows),
      KOKKOS_LAMBDA(int i) { r(i) += c * u(i) * u(i) * u(i) - f(i); });
}

void cubic_tangent(const CsrMatrix& a, Real c, ConstVector u, ConstVector du, Vector y) {
  csr_multiply(a, du, y);
  Kokkos::parallel_for(
      "test::cubic_tangent", Policy(0, a.n_rows),
      KOKKOS_LAMBDA(int i) { y(i) += 3 * c * u(i) * u(i) * du(i); });
}

// The assembled Jacobian A + diag(3 c u^2), on the pattern of A.
void cubic_jacobian(const CsrMatrix& a, Real c, ConstVector u, const CsrMatrix& j) {
  auto rp = a.row_ptr;
  auto col = a.col;
  auto val = a.val;
  auto jval = j.val;
  Kokkos::parallel_for(
      "test::cubic_jacobian", Policy(0, a.n_rows), KOKKOS_LAMBDA(int r) {
        for (int k = rp(r); k < rp(r + 1); ++k)
          jval(k) = val(k) + (col(k) == r ? 3 * c * u(r) * u(r) : 0.0);
      });
}

struct CubicProblem {
  HostCsr ah;
  CsrMatrix a, jacobian;
  Real c;
  Vector f;
  std::vector<double> u_exact;
  std::unique_ptr<BoomerAmg> amg = std::make_unique<BoomerAmg>();

  CubicProblem(int m, Real c_) : ah(poisson(m)), a(to_device(ah)), c(c_) {
    jacobian = a;
    jacobian.val = Vector("test::jacobian", a.nnz());
    // Manufactured: f = A u* + c u*^3 with u* of size ~1.5, so the cubic term is as large as the
    // diffusion and the first (linear) step overshoots.
    u_exact = manufactured(ah.n_rows);
    for (auto& v : u_exact) v *= 1.5;
    auto fh = ah.multiply(u_exact);
    for (int i = 0; i < ah.n_rows; ++i) fh[i] += c * std::pow(u_exact[i], 3);
    f = to_device(fh, "test::f");
  }

  NewtonSystem system() {
    NewtonSystem s;
    s.residual = [this](ConstVector u, Vector r) { cubic_residual(a, c, f, u, r); };
    s.tangent = [this](ConstVector u, ConstVector du, Vector y) { cubic_tangent(a, c, u, du, y); };
    s.setup_preconditioner = [this](ConstVector u) {
      cubic_jacobian(a, c, u, jacobian);
      amg->setup(jacobian);
    };
    s.precondition = amg->as_function();
    s.symmetric = true;
    return s;
  }
};

// ---- componentwise atan(u) = 0 and sqrt(u) = 1/2 ----

void atan_residual(ConstVector u, Vector r) {
  Kokkos::parallel_for(
      "test::atan_residual", Policy(0, u.extent(0)),
      KOKKOS_LAMBDA(int i) { r(i) = math::atan(u(i)); });
}

void atan_tangent(ConstVector u, ConstVector du, Vector y) {
  Kokkos::parallel_for(
      "test::atan_tangent", Policy(0, u.extent(0)),
      KOKKOS_LAMBDA(int i) { y(i) = du(i) / (1 + u(i) * u(i)); });
}

void sqrt_residual(ConstVector u, Vector r) {
  Kokkos::parallel_for(
      "test::sqrt_residual", Policy(0, u.extent(0)),
      KOKKOS_LAMBDA(int i) { r(i) = math::sqrt(u(i)) - 0.5; });
}

void sqrt_tangent(ConstVector u, ConstVector du, Vector y) {
  Kokkos::parallel_for(
      "test::sqrt_tangent", Policy(0, u.extent(0)),
      KOKKOS_LAMBDA(int i) { y(i) = du(i) / (2 * math::sqrt(u(i))); });
}

// Starting values 3, 3.1, ..., 3.9: all in atan's divergence region for plain Newton (|u| > 1.39).
Vector atan_start(int n) {
  std::vector<double> u(n);
  for (int i = 0; i < n; ++i) u[i] = 3.0 + 0.1 * (i % 10);
  return to_device(u, "u");
}

NewtonSystem diagonal_system(void (*residual)(ConstVector, Vector),
                             void (*tangent)(ConstVector, ConstVector, Vector)) {
  NewtonSystem s;
  s.residual = residual;
  s.tangent = tangent;
  s.symmetric = true;  // diagonal Jacobians with positive entries: CG applies
  return s;
}

}  // namespace

TEST(Newton, ConvergesQuadraticallyWithTightForcing) {
  CubicProblem p(12, 2.0);
  NewtonOptions opt;
  opt.rel_tol = 1e-13;
  opt.abs_tol = 0;
  opt.eta_max = 1e-12;  // exact linear solves up to round-off: the pure Newton rate shows
  opt.eta_min = 1e-12;
  Vector u("u", p.ah.n_rows);
  const NewtonResult res = newton_solve(p.system(), u, opt);
  ASSERT_TRUE(res.converged) << res.reason;
  const auto& h = res.residual_history;
  std::printf("[ measure  ] Newton cubic 12^3, tight forcing: %d iterations, %d Krylov:",
              res.iterations, res.krylov_iterations);
  for (double r : h) std::printf(" %.2e", r);
  std::printf("\n");
  ASSERT_GE(h.size(), 4u);
  // Residual evaluation loses ~eps * ||f|| * sqrt(n) ~ 1e-13 relative to r0 = ||f|| (u0 = 0);
  // ratios are taken only where r_{k+1} stays clear of that floor.
  const double floor = 1e-12 * h[0];
  size_t last = h.size() - 1;
  while (last > 0 && h[last] < floor) --last;
  ASSERT_GE(last, 2u);
  // Quadratic rate: r_{k+1} / r_k^2 bounded over the last two steps above the floor. Measured
  // ~0.01 (this problem's |F''| / |F'| scale); 0.1 leaves a 10x margin but fails for a linear rate,
  // whose ratio r_{k+1} / r_k^2 = const / r_k blows up as r_k -> 0.
  for (size_t k = last - 1; k <= last; ++k)
    EXPECT_LE(h[k] / (h[k - 1] * h[k - 1]), 0.1) << "step " << k;
  // Observed order log(r_{k+1} / r_k) / log(r_k / r_{k-1}) on the last triple: 2 for Newton
  // (measured 1.96); 1.8 allows for the inexactness eta = 1e-12 and round-off.
  const double order = std::log(h[last] / h[last - 1]) / std::log(h[last - 1] / h[last - 2]);
  EXPECT_GE(order, 1.8);
  // Solution error: the Jacobian A + diag(3 c u^2) has its smallest eigenvalue >= that of A,
  // 6 (1 - cos(pi / 13)) = 0.175 for m = 12, so the error is at most 1 / 0.175 < 6 times the final
  // residual.
  EXPECT_LE(distance(to_host(u), p.u_exact), 6 * h.back());
}

TEST(Newton, EisenstatWalkerForcingSavesKrylovIterations) {
  CubicProblem tight_problem(12, 2.0), ew_problem(12, 2.0);
  NewtonOptions tight;
  tight.eta_max = tight.eta_min = 1e-12;
  const NewtonOptions ew{};  // defaults: eta_max 1e-2, choice 2
  Vector u1("u1", tight_problem.ah.n_rows), u2("u2", ew_problem.ah.n_rows);
  const NewtonResult r_tight = newton_solve(tight_problem.system(), u1, tight);
  const NewtonResult r_ew = newton_solve(ew_problem.system(), u2, ew);
  ASSERT_TRUE(r_tight.converged) << r_tight.reason;
  ASSERT_TRUE(r_ew.converged) << r_ew.reason;
  std::printf(
      "[ measure  ] Newton cubic 12^3: tight forcing %d Newton / %d Krylov, "
      "Eisenstat-Walker %d Newton / %d Krylov\n",
      r_tight.iterations, r_tight.krylov_iterations, r_ew.iterations, r_ew.krylov_iterations);
  // Loose early solves cost a Newton step or two but save many Krylov iterations.
  EXPECT_LT(r_ew.krylov_iterations, r_tight.krylov_iterations);
  EXPECT_LE(r_ew.iterations, r_tight.iterations + 3);
}

TEST(Newton, LineSearchGlobalisesArctanWherePlainNewtonDiverges) {
  // Plain Newton on atan(u) = 0 from u = 3: u <- u - (1 + u^2) atan(u) grows without bound.
  double plain = 3.0;
  for (int k = 0; k < 5; ++k) plain -= (1 + plain * plain) * std::atan(plain);
  EXPECT_GT(std::abs(plain), 1e6);

  const int n = 100;
  const NewtonSystem s = diagonal_system(atan_residual, atan_tangent);
  NewtonOptions opt;
  Vector u = atan_start(n);
  const NewtonResult res = newton_solve(s, u, opt);
  EXPECT_TRUE(res.converged) << res.reason;
  // The root is 0: the residual tolerance 1e-10 * ||r0|| (r0 ~ 1.27 sqrt(n)) bounds |u| through
  // atan's unit slope at 0.
  for (double v : to_host(u)) EXPECT_LE(std::abs(v), 1e-9);
  // Monotone decrease is what the line search guarantees.
  for (size_t k = 1; k < res.residual_history.size(); ++k)
    EXPECT_LT(res.residual_history[k], res.residual_history[k - 1]);
  std::printf("[ measure  ] Newton atan, line search: %d iterations\n", res.iterations);

  opt.max_backtracks = 0;  // full steps only: the first one increases ||r||
  Vector u_full = atan_start(n);
  const NewtonResult full = newton_solve(s, u_full, opt);
  EXPECT_FALSE(full.converged);
  EXPECT_EQ(full.reason, "line search failed");
  EXPECT_EQ(full.iterations, 0);
}

TEST(Newton, NonFiniteTrialStepIsShortenedNotAccepted) {
  // sqrt(u) = 1/2 from u = 4: the full Newton step lands at u = -2 where the residual is NaN; the
  // line search must treat that as a failed trial and halve.
  const NewtonSystem s = diagonal_system(sqrt_residual, sqrt_tangent);
  Vector u("u", 10);
  fill(u, 4.0);
  const NewtonResult res = newton_solve(s, u, NewtonOptions{});
  EXPECT_TRUE(res.converged) << res.reason;
  // Root 1/4; residual slope there is 1, so |u - 1/4| ~ final residual (<= 1e-10 r0).
  for (double v : to_host(u)) EXPECT_NEAR(v, 0.25, 1e-9);
}

TEST(Newton, NonFiniteResidualIsReportedAsNaN) {
  NewtonSystem s;
  s.residual = [](ConstVector, Vector r) { fill(r, std::numeric_limits<Real>::quiet_NaN()); };
  s.tangent = [](ConstVector, ConstVector du, Vector y) { copy(du, y); };
  Vector u("u", 20);
  NewtonResult res;
  EXPECT_NO_THROW(res = newton_solve(s, u, NewtonOptions{}));
  EXPECT_FALSE(res.converged);
  EXPECT_EQ(res.reason, "NaN");
  EXPECT_EQ(res.iterations, 0);
  ASSERT_EQ(res.residual_history.size(), 1u);

  // A NaN from the tangent (inside the linear solve) is the same failure.
  const NewtonSystem atan_nan_tangent = [] {
    NewtonSystem t = diagonal_system(atan_residual, nullptr);
    t.tangent = [](ConstVector, ConstVector, Vector y) {
      fill(y, std::numeric_limits<Real>::quiet_NaN());
    };
    return t;
  }();
  Vector v = atan_start(20);
  EXPECT_NO_THROW(res = newton_solve(atan_nan_tangent, v, NewtonOptions{}));
  EXPECT_EQ(res.reason, "NaN");
}

TEST(Newton, LinearSolverWithoutProgressIsReported) {
  NewtonSystem s = diagonal_system(atan_residual, nullptr);
  // A zero tangent: no Krylov method can reduce the linear residual.
  s.tangent = [](ConstVector, ConstVector, Vector y) { fill(y, 0.0); };
  for (bool symmetric : {true, false}) {
    s.symmetric = symmetric;
    Vector u = atan_start(20);
    const NewtonResult res = newton_solve(s, u, NewtonOptions{});
    EXPECT_FALSE(res.converged);
    EXPECT_EQ(res.reason, "linear solver") << (symmetric ? "CG" : "FGMRES");
  }
}

TEST(Newton, StopsAtMaxIterations) {
  CubicProblem p(8, 2.0);
  NewtonOptions opt;
  opt.max_iterations = 1;
  Vector u("u", p.ah.n_rows);
  const NewtonResult res = newton_solve(p.system(), u, opt);
  EXPECT_FALSE(res.converged);
  EXPECT_EQ(res.reason, "max iterations");
  EXPECT_EQ(res.iterations, 1);
  EXPECT_EQ(res.residual_history.size(), 2u);
  EXPECT_GT(res.krylov_iterations, 0);
}

// ---- the optional pieces: blocks, admissible states, the energy line search, round-off floors
// ----

namespace {

// atan(u) = 0 with the second half of the residual scaled by 1e8: two "fields" in different units.
NewtonSystem two_unit_atan(int n) {
  NewtonSystem s = diagonal_system(atan_residual, atan_tangent);
  s.residual = [n](ConstVector u, Vector r) {
    atan_residual(u, r);
    scale(1e8, Kokkos::subview(r, std::make_pair(n / 2, n)));
  };
  s.tangent = [n](ConstVector u, ConstVector du, Vector y) {
    atan_tangent(u, du, y);
    scale(1e8, Kokkos::subview(y, std::make_pair(n / 2, n)));
  };
  // The exact inverse of the (diagonal) tangent at the linearisation point, as a field's
  // preconditioner would approximate it.
  auto at = std::make_shared<Vector>("test::linearisation_point", n);
  s.linearise = [at](ConstVector u) { copy(u, *at); };
  s.precondition = [at, n](ConstVector x, Vector z) {
    const Vector u = *at;
    Kokkos::parallel_for(
        "test::atan_inverse", Policy(0, n),
        KOKKOS_LAMBDA(int i) { z(i) = x(i) * (1 + u(i) * u(i)) * (i < n / 2 ? 1.0 : 1e-8); });
  };
  s.symmetric = false;
  s.blocks = {{0, n / 2}, {n / 2, n}};
  return s;
}

}  // namespace

TEST(Newton, EachBlockMeetsItsOwnTolerance) {
  // The first block starts at u = 1, the second, in units 1e8 times larger, nearer its root
  // (u = 0.1): one norm over both is the second block's, whose relative tolerance the first
  // block's residual meets long before it has converged (after two Newton steps, at u = 0.117).
  const int n = 40;
  auto start = [n] {
    std::vector<double> u(n, 1.0);
    for (int i = n / 2; i < n; ++i) u[i] = 0.1;
    return to_device(u, "u");
  };
  auto first_block_norm = [n](const Vector& u) {
    double sum = 0;
    const std::vector<double> h = to_host(u);
    for (int i = 0; i < n / 2; ++i) sum += std::pow(std::atan(h[i]), 2);
    return std::sqrt(sum);
  };
  NewtonOptions opt;
  opt.rel_tol = 1e-8;
  opt.abs_tol = 0;
  Vector u = start();
  const double first0 = first_block_norm(u);
  NewtonSystem one_norm = two_unit_atan(n);
  one_norm.blocks.clear();
  const NewtonResult plain = newton_solve(one_norm, u, opt);
  ASSERT_TRUE(plain.converged) << plain.reason;
  EXPECT_GT(first_block_norm(u), 100 * opt.rel_tol * first0);

  opt.line_search = LineSearch::BlockMerit;
  opt.scale_blocks = true;
  opt.tolerance_from_largest = true;
  Vector v = start();
  const NewtonResult res = newton_solve(two_unit_atan(n), v, opt);
  ASSERT_TRUE(res.converged) << res.reason;
  ASSERT_EQ(res.block_history.size(), res.residual_history.size());
  ASSERT_EQ(res.krylov_history.size(), size_t(res.iterations));
  for (int b = 0; b < 2; ++b) {
    double largest = 0;
    for (const auto& norms : res.block_history) largest = std::max(largest, norms[b]);
    EXPECT_LE(res.block_history.back()[b], opt.rel_tol * largest) << "block " << b;
  }
  EXPECT_LE(first_block_norm(v), opt.rel_tol * first0);
}

TEST(Newton, InadmissibleTrialsAreShortenedWithoutEvaluatingThere) {
  // sqrt(u) = 1/2 from u = 4: the full step lands at u = -2, outside the residual's domain. With
  // the domain declared, no line search evaluates the residual there.
  for (LineSearch search :
       {LineSearch::ResidualArmijo, LineSearch::EnergyRegulaFalsi, LineSearch::BlockMerit}) {
    auto outside = std::make_shared<int>(0);
    auto nonnegative = [](ConstVector u) {
      for (double v : to_host(u))
        if (v < 0) return false;
      return true;
    };
    NewtonSystem s = diagonal_system(sqrt_residual, sqrt_tangent);
    s.residual = [outside, nonnegative](ConstVector u, Vector r) {
      if (!nonnegative(u)) ++*outside;
      sqrt_residual(u, r);
    };
    s.admissible = nonnegative;
    NewtonOptions opt;
    opt.line_search = search;
    Vector u("u", 10);
    fill(u, 4.0);
    const NewtonResult res = newton_solve(s, u, opt);
    EXPECT_TRUE(res.converged) << res.reason;
    EXPECT_EQ(*outside, 0) << "line search " << int(search);
    for (double v : to_host(u)) EXPECT_NEAR(v, 0.25, 1e-9);
  }
}

TEST(Newton, EnergyLineSearchGlobalisesArctan) {
  // atan(u) is the gradient of the convex E(u) = u atan(u) - log(1 + u^2) / 2, so G(s) =
  // du . r(u + s du) is E's slope along the step: the regula falsi on it finds the minimum where
  // the full step (from u = 3) overshoots into plain Newton's divergence.
  NewtonOptions opt;
  opt.line_search = LineSearch::EnergyRegulaFalsi;
  Vector u = atan_start(100);
  const NewtonResult res = newton_solve(diagonal_system(atan_residual, atan_tangent), u, opt);
  EXPECT_TRUE(res.converged) << res.reason;
  for (double v : to_host(u)) EXPECT_LE(std::abs(v), 1e-9);
}

TEST(Newton, StopsAtTheRoundoffFloor) {
  // u^2 = 2 has no root among the doubles: the residual stagnates at ~4e-16 and a tolerance of
  // 1e-40 ||r0|| cannot be met. A floor declared at 1e-6 ||r0|| ends the solve there, converged.
  NewtonSystem s;
  s.residual = [](ConstVector u, Vector r) {
    Kokkos::parallel_for(
        "test::square_residual", Policy(0, u.extent(0)),
        KOKKOS_LAMBDA(int i) { r(i) = u(i) * u(i) - 2; });
  };
  s.tangent = [](ConstVector u, ConstVector du, Vector y) {
    Kokkos::parallel_for(
        "test::square_tangent", Policy(0, u.extent(0)),
        KOKKOS_LAMBDA(int i) { y(i) = 2 * u(i) * du(i); });
  };
  s.symmetric = true;
  NewtonOptions opt;
  opt.rel_tol = 1e-40;
  opt.abs_tol = 0;
  Vector u("u", 20);
  fill(u, 1.0);
  const NewtonResult without = newton_solve(s, u, opt);
  EXPECT_FALSE(without.converged);
  const double r0 = without.residual_history.front();
  s.roundoff_floors = [r0](ConstVector) { return std::vector<Real>{1e-6 * r0}; };
  Vector v("v", 20);
  fill(v, 1.0);
  const NewtonResult with = newton_solve(s, v, opt);
  EXPECT_TRUE(with.converged) << with.reason;
  EXPECT_LE(with.residual_history.back(), 1e-6 * r0);
  for (double x : to_host(v)) EXPECT_NEAR(x, std::sqrt(2.0), 1e-5);
}

namespace {

void multiply(ConstVector d, Vector x) {  // x *= d entry by entry
  Kokkos::parallel_for(
      "test::multiply", Policy(0, x.extent(0)), KOKKOS_LAMBDA(int i) { x(i) *= d(i); });
}

void reciprocal(Vector x) {
  Kokkos::parallel_for(
      "test::reciprocal", Policy(0, x.extent(0)), KOKKOS_LAMBDA(int i) { x(i) = 1 / x(i); });
}

}  // namespace

// The policy alone: the preconditioner serves while the last solve needed at most 1.5 times the
// Krylov iterations of the first solve after its set-up, plus 3, and at most a quarter of the
// limit; a change of its coefficients or an invalidation retires it.
TEST(PreconditionerReuse, ServesWhileTheKrylovCountStaysNearTheFirstSolvesAfterItsSetUp) {
  PreconditionerReuse reuse;
  reuse.require({0.5, 1.0});
  EXPECT_FALSE(reuse.still_serves(400));  // never set up
  reuse.record_setup();
  EXPECT_TRUE(reuse.still_serves(400));
  reuse.record_solve(10);  // the baseline
  reuse.record_solve(18);  // 1.5 * 10 + 3
  EXPECT_TRUE(reuse.still_serves(400));
  reuse.record_solve(19);
  EXPECT_FALSE(reuse.still_serves(400));
  reuse.record_solve(12);
  EXPECT_TRUE(reuse.still_serves(400));
  EXPECT_FALSE(reuse.still_serves(40));  // 12 > 40 / 4
  reuse.require({0.25, 1.0});            // a new time step size
  EXPECT_FALSE(reuse.still_serves(400));
  reuse.record_setup();
  EXPECT_TRUE(reuse.still_serves(400));
  reuse.invalidate();
  EXPECT_FALSE(reuse.still_serves(400));
  EXPECT_EQ(reuse.setups(), 2);
}

// Through Newton: on A u + c u^3 = f the AMG hierarchy of the first Jacobian serves the later
// ones (the cubic term changes the diagonal only), so the solve sets it up fewer times than it
// takes Newton steps and reaches the same solution (the bound of
// ConvergesQuadraticallyWithTightForcing: the error is at most 6 times the final residual).
TEST(Newton, AReusedPreconditionerSavesSetUpsAndReachesTheSameSolution) {
  CubicProblem fresh_problem(12, 2.0), reused_problem(12, 2.0);
  int fresh_setups = 0, reused_setups = 0;
  NewtonSystem fresh = fresh_problem.system(), reused = reused_problem.system();
  auto counted = [](NewtonSystem& s, int& count) {
    s.setup_preconditioner = [setup = s.setup_preconditioner, &count](ConstVector u) {
      setup(u);
      ++count;
    };
  };
  counted(fresh, fresh_setups);
  counted(reused, reused_setups);
  PreconditionerReuse age;
  reused.reuse = &age;
  Vector u1("u1", fresh_problem.ah.n_rows), u2("u2", reused_problem.ah.n_rows);
  const NewtonResult r_fresh = newton_solve(fresh, u1, NewtonOptions{});
  const NewtonResult r_reused = newton_solve(reused, u2, NewtonOptions{});
  ASSERT_TRUE(r_fresh.converged) << r_fresh.reason;
  ASSERT_TRUE(r_reused.converged) << r_reused.reason;
  std::printf(
      "[ measure  ] Newton cubic 12^3: set up every step %d Newton / %d Krylov / %d set-ups, "
      "reused %d / %d / %d (%d reuses)\n",
      r_fresh.iterations, r_fresh.krylov_iterations, fresh_setups, r_reused.iterations,
      r_reused.krylov_iterations, reused_setups, age.reuses());
  EXPECT_EQ(fresh_setups, r_fresh.iterations);
  EXPECT_LT(reused_setups, r_reused.iterations);
  EXPECT_EQ(age.setups(), reused_setups);
  EXPECT_EQ(age.reuses() + age.setups(), r_reused.iterations);
  EXPECT_LE(distance(to_host(u2), reused_problem.u_exact), 6 * r_reused.residual_history.back());
  EXPECT_LE(distance(to_host(u1), fresh_problem.u_exact), 6 * r_fresh.residual_history.back());
}

// A preconditioner gone stale between two solves (the operator changed in a way its coefficients
// do not show) stalls: the reused solve stops at a quarter of the Krylov limit and is repeated with
// a fresh one in the same Newton step. K u = f with K diagonal over six decades, preconditioned by
// the inverse diagonal taken at set-up: exact (1 CG iteration) for the K it was built for, and
// hopeless for the reversed K.
TEST(Newton, AStalePreconditionerIsSetUpAgainWithinTheNewtonStep) {
  const int n = 200;
  std::vector<double> k(n);
  for (int i = 0; i < n; ++i) k[i] = std::pow(10.0, 6.0 * i / (n - 1));
  Vector stiffness = to_device(k, "k"), f("f", n), inverse("inverse", n);
  fill(f, 1.0);
  NewtonSystem s;
  s.residual = [&](ConstVector u, Vector r) {
    copy(u, r);
    multiply(stiffness, r);
    axpy(-1.0, f, r);
  };
  s.tangent = [&](ConstVector, ConstVector du, Vector y) {
    copy(du, y);
    multiply(stiffness, y);
  };
  int setups = 0;
  s.setup_preconditioner = [&](ConstVector) {
    copy(stiffness, inverse);
    reciprocal(inverse);
    ++setups;
  };
  s.precondition = [&](ConstVector r, Vector z) {
    copy(r, z);
    multiply(inverse, z);
  };
  s.symmetric = true;
  PreconditionerReuse age;
  s.reuse = &age;
  NewtonOptions opt;
  opt.krylov.max_iterations = 40;
  Vector u("u", n);
  NewtonResult r = newton_solve(s, u, opt);
  ASSERT_TRUE(r.converged) << r.reason;
  EXPECT_EQ(setups, 1);
  std::reverse(k.begin(), k.end());
  stiffness = to_device(k, "k reversed");
  fill(u, 0.0);
  r = newton_solve(s, u, opt);
  ASSERT_TRUE(r.converged) << r.reason;
  ASSERT_FALSE(r.krylov_history.empty());
  std::printf("[ measure  ] stale preconditioner: first Newton step %d CG iterations, %d set-ups\n",
              r.krylov_history[0], setups);
  EXPECT_EQ(setups, 2);
  EXPECT_EQ(age.reuses(), 1);
  // 10 with the stale one (40 / 4), then 1 with the fresh one.
  EXPECT_EQ(r.krylov_history[0], 11);
}
