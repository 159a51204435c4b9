// Vector operations against host loops, and CG / FGMRES on model finite-difference matrices with
// manufactured exact discrete solutions (b = A x_exact), so that the error is known exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "solvers/solvers.hpp"
#include "test_matrices.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

std::vector<double> random_vector(int n, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> dist(-1.0, 1.0);
  std::vector<double> x(n);
  for (auto& v : x) v = dist(gen);
  return x;
}

void set_entry(Vector x, int i, Real value) {
  Kokkos::parallel_for(
      "test::set_entry", Kokkos::RangePolicy<ExecSpace>(i, i + 1),
      KOKKOS_LAMBDA(int k) { x(k) = value; });
}

// An operator that poisons its output: solvers must report it, not throw or loop.
void nan_operator(ConstVector, Vector y) { fill(y, std::numeric_limits<Real>::quiet_NaN()); }

}  // namespace

TEST(VectorOps, AgreeWithHostComputations) {
  const int n = 10007;  // odd, so that no reduction splits evenly
  const auto xh = random_vector(n, 1), yh = random_vector(n, 2);
  const Vector x = to_device(xh, "x");
  double dot_ref = 0, xx_ref = 0;
  for (int i = 0; i < n; ++i) {
    dot_ref += xh[i] * yh[i];
    xx_ref += xh[i] * xh[i];
  }
  // Reductions sum in a different order than the host loop: n * eps relative covers any order.
  const double sum_tol = n * std::numeric_limits<double>::epsilon();
  EXPECT_NEAR(dot(x, to_device(yh, "y")), dot_ref, sum_tol * std::sqrt(xx_ref) * norm(yh));
  EXPECT_NEAR(norm2(x), std::sqrt(xx_ref), sum_tol * std::sqrt(xx_ref));

  // Element-wise operations do the same floating-point operations as the host: exact equality.
  {
    Vector y = to_device(yh, "y");
    axpy(0.3, x, y);
    const auto got = to_host(y);
    for (int i = 0; i < n; ++i) ASSERT_EQ(got[i], yh[i] + 0.3 * xh[i]);
  }
  {
    Vector y = to_device(yh, "y");
    axpby(-1.5, x, 0.25, y);
    const auto got = to_host(y);
    for (int i = 0; i < n; ++i) ASSERT_EQ(got[i], -1.5 * xh[i] + 0.25 * yh[i]);
  }
  {
    // beta = 0 must overwrite, not multiply: NaN in y would otherwise survive as 0 * NaN.
    Vector y("y", n);
    fill(y, std::numeric_limits<Real>::quiet_NaN());
    axpby(2.0, x, 0.0, y);
    const auto got = to_host(y);
    for (int i = 0; i < n; ++i) ASSERT_EQ(got[i], 2.0 * xh[i]);
  }
  {
    Vector y = to_device(xh, "y");
    scale(-0.7, y);
    const auto got = to_host(y);
    for (int i = 0; i < n; ++i) ASSERT_EQ(got[i], -0.7 * xh[i]);
  }
  {
    Vector y("y", n);
    fill(y, 4.25);
    for (double v : to_host(y)) ASSERT_EQ(v, 4.25);
    copy(x, y);
    EXPECT_EQ(to_host(y), xh);
  }
  {
    Vector y = to_device(xh, "y");
    EXPECT_TRUE(all_finite(y));
    set_entry(y, n / 2, std::numeric_limits<Real>::quiet_NaN());
    EXPECT_FALSE(all_finite(y));
    Vector z = to_device(xh, "z");
    set_entry(z, n - 1, -std::numeric_limits<Real>::infinity());
    EXPECT_FALSE(all_finite(z));
    set_entry(z, n - 1, std::numeric_limits<Real>::max());
    EXPECT_TRUE(all_finite(z));
  }
}

TEST(ConjugateGradient, ReachesToleranceAndManufacturedSolutionOnPoisson) {
  const int m = 20;
  const HostCsr ah = poisson(m);
  const auto x_exact = manufactured(ah.n_rows);
  const auto bh = ah.multiply(x_exact);
  const CsrMatrix a = to_device(ah);
  const Vector b = to_device(bh, "b");
  Vector x("x", ah.n_rows);

  KrylovOptions opt;
  opt.rel_tol = 1e-10;
  const KrylovResult res = cg(matrix_operator(a), {}, b, x, opt);
  EXPECT_TRUE(res.converged) << res.reason;
  EXPECT_EQ(res.reason, "converged");
  EXPECT_NEAR(res.initial_residual, norm(bh), 1e-12 * norm(bh));  // x0 = 0: r0 = b
  EXPECT_LE(res.final_residual, 1e-10 * norm(bh));
  // The final residual is the true one, not the recurrence's: recompute it independently.
  const auto xh = to_host(x);
  const auto axh = ah.multiply(xh);
  EXPECT_NEAR(res.final_residual, distance(axh, bh), 1e-3 * res.final_residual);
  // Error <= cond(A) * relative residual; cond(A) = cot^2(pi / (2 (m + 1))) ~ 180 for m = 20.
  EXPECT_LE(distance(xh, x_exact) / norm(x_exact), 180 * 1e-10);
  // Unpreconditioned CG needs O(sqrt(cond)) iterations: about 5 * 13 here, well below n.
  EXPECT_LE(res.iterations, 150);
  std::printf("[ measure  ] CG Poisson %d^3: %d iterations, relative error %.2e\n", m,
              res.iterations, distance(xh, x_exact) / norm(x_exact));
}

TEST(ConjugateGradient, StartsFromTheGivenGuessAndStopsAtMaxIterations) {
  const HostCsr ah = poisson(10);
  const CsrMatrix a = to_device(ah);
  const auto bh = ah.multiply(manufactured(ah.n_rows));
  const Vector b = to_device(bh, "b");
  const auto x0 = random_vector(ah.n_rows, 3);
  Vector x = to_device(x0, "x");
  KrylovOptions opt;
  opt.max_iterations = 3;
  const KrylovResult res = cg(matrix_operator(a), {}, b, x, opt);
  EXPECT_FALSE(res.converged);
  EXPECT_EQ(res.reason, "max iterations");
  EXPECT_EQ(res.iterations, 3);
  // Residuals of the given x0 and of the returned x, recomputed on the host (summation order
  // differs from the device's: 1e-12 relative).
  const auto r0 = ah.multiply(x0);
  const auto r_end = ah.multiply(to_host(x));
  EXPECT_NEAR(res.initial_residual, distance(r0, bh), 1e-12 * norm(bh));
  EXPECT_NEAR(res.final_residual, distance(r_end, bh), 1e-12 * norm(bh));
  EXPECT_LT(res.final_residual, res.initial_residual);
}

TEST(Krylov, ZeroRightHandSideGivesZeroSolutionImmediately) {
  const HostCsr ah = poisson(6);
  const CsrMatrix a = to_device(ah);
  Vector b("b", ah.n_rows);
  for (auto* method : {&cg, &fgmres}) {
    Vector x = to_device(random_vector(ah.n_rows, 4), "x");
    const KrylovResult res = (*method)(matrix_operator(a), {}, b, x, KrylovOptions{});
    EXPECT_TRUE(res.converged);
    EXPECT_EQ(res.iterations, 0);
    EXPECT_EQ(res.final_residual, 0.0);
    for (double v : to_host(x)) ASSERT_EQ(v, 0.0);
  }
}

TEST(Krylov, NonFiniteOperatorIsReportedAsNaN) {
  const int n = 50;
  Vector b("b", n);
  fill(b, 1.0);
  for (auto* method : {&cg, &fgmres}) {
    Vector x("x", n);
    KrylovResult res;
    EXPECT_NO_THROW(res = (*method)(nan_operator, {}, b, x, KrylovOptions{}));
    EXPECT_FALSE(res.converged);
    EXPECT_EQ(res.reason, "NaN");
  }
}

TEST(Fgmres, RestartedAndFullGmresSolveNonsymmetricConvectionDiffusion) {
  const int m = 12;
  // Cell Peclet numbers up to 4: strongly nonsymmetric, still an M-matrix thanks to upwinding.
  const HostCsr ah = convection_diffusion(m, {4.0, 2.0, 1.0});
  const auto x_exact = manufactured(ah.n_rows);
  const auto bh = ah.multiply(x_exact);
  const CsrMatrix a = to_device(ah);
  const Vector b = to_device(bh, "b");

  KrylovOptions opt;
  opt.rel_tol = 1e-10;
  opt.max_iterations = 2000;
  opt.restart = 200;
  Vector x_full("x_full", ah.n_rows);
  const KrylovResult full = fgmres(matrix_operator(a), {}, b, x_full, opt);
  opt.restart = 5;
  Vector x_restarted("x_restarted", ah.n_rows);
  const KrylovResult restarted = fgmres(matrix_operator(a), {}, b, x_restarted, opt);

  for (const auto* res : {&full, &restarted}) {
    EXPECT_TRUE(res->converged) << res->reason;
    EXPECT_LE(res->final_residual, 1e-10 * norm(bh));
  }
  // Full GMRES minimises the residual over the whole Krylov space, so it never needs more steps
  // than a restarted run; the full run must not have restarted, the restarted one must have.
  EXPECT_LT(full.iterations, 200);
  EXPECT_LE(full.iterations, restarted.iterations);
  EXPECT_GT(restarted.iterations, 2 * opt.restart);
  // The upwind operator is well conditioned (diagonally dominant): error ~ residual, 1e-8 is 100x
  // the relative tolerance.
  const double err_full = distance(to_host(x_full), x_exact) / norm(x_exact);
  const double err_restarted = distance(to_host(x_restarted), x_exact) / norm(x_exact);
  EXPECT_LE(err_full, 1e-8);
  EXPECT_LE(err_restarted, 1e-8);
  std::printf(
      "[ measure  ] FGMRES convection-diffusion %d^3 unpreconditioned: full %d, GMRES(5) %d "
      "iterations, relative errors %.1e, %.1e\n",
      m, full.iterations, restarted.iterations, err_full, err_restarted);
}
