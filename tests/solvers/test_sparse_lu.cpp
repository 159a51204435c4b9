// SparseLu (src/solvers): solves a nonsymmetric sparse system to round-off, refactors new values
// on a kept pattern and re-analyses a new pattern, pivots where the diagonal is zero, makes FGMRES
// converge in one iteration as a preconditioner, and reports a singular matrix.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "solvers/solvers.hpp"
#include "test_matrices.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

// ||x - x_exact|| / ||x_exact|| for x = LU^-1 (A x_exact) with the factors of a.
double solve_error(const SparseLu& lu, const HostCsr& ah) {
  const auto x_exact = manufactured(ah.n_rows);
  const Vector b = to_device(ah.multiply(x_exact), "b");
  Vector x("x", ah.n_rows);
  lu.apply(b, x);
  return distance(to_host(x), x_exact) / norm(x_exact);
}

// Convection-dominated, so far from symmetric; 10^3 unknowns.
HostCsr nonsymmetric() { return convection_diffusion(10, {4.0, 2.0, 1.0}); }

}  // namespace

// 1e-11: the condition number of these matrices is below 1e3, so a backward-stable LU leaves an
// error of a few 1e-13 at most.
TEST(SparseLu, SolvesANonsymmetricSystemToRoundOff) {
  const HostCsr a = nonsymmetric();
  SparseLu lu;
  lu.setup(to_device(a));
  EXPECT_LT(solve_error(lu, a), 1e-11);
  EXPECT_GE(lu.factor_nonzeros(), static_cast<long>(a.val.size()));
}

TEST(SparseLu, RefactorsNewValuesAndReanalysesANewPattern) {
  SparseLu lu;
  HostCsr a = nonsymmetric();
  lu.setup(to_device(a));
  // Same pattern, other values: the kept analysis must be applied to the new numbers.
  for (size_t k = 0; k < a.val.size(); ++k) a.val[k] *= 1.0 + 0.3 * std::sin(0.7 * k);
  lu.setup(to_device(a));
  EXPECT_LT(solve_error(lu, a), 1e-11);
  // Another size and pattern.
  const HostCsr b = convection_diffusion(7, {0.5, 0.0, 3.0});
  lu.setup(to_device(b));
  EXPECT_LT(solve_error(lu, b), 1e-11);
}

// The saddle-point structure of the fluid's Jacobian: an unstabilised pressure row has a zero
// diagonal, which elimination without row pivoting cannot take.
TEST(SparseLu, PivotsWhereTheDiagonalIsZero) {
  // [A G; G^T 0] with A the 1-D Laplacian on n nodes and G = e_0 + e_{n-1}.
  const int n = 20;
  HostCsr a;
  for (int r = 0; r < n; ++r) {
    if (r > 0) a.add(r - 1, -1.0);
    a.add(r, 2.0);
    if (r < n - 1) a.add(r + 1, -1.0);
    if (r == 0 || r == n - 1) a.add(n, 1.0);
    a.end_row();
  }
  a.add(0, 1.0);  // the last row: no diagonal entry at all
  a.add(n - 1, 1.0);
  a.end_row();
  SparseLu lu;
  lu.setup(to_device(a));
  EXPECT_LT(solve_error(lu, a), 1e-11);
}

TEST(SparseLu, AsAPreconditionerFgmresConvergesInOneIteration) {
  const HostCsr ah = nonsymmetric();
  const CsrMatrix a = to_device(ah);
  SparseLu lu;
  lu.setup(a);
  const Vector b = to_device(ah.multiply(manufactured(ah.n_rows)), "b");
  Vector x("x", ah.n_rows);
  KrylovOptions opt;
  opt.rel_tol = 1e-10;
  const KrylovResult r = fgmres(
      matrix_operator(a), [&lu](ConstVector v, Vector z) { lu.apply(v, z); }, b, x, opt);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.iterations, 1);
}

TEST(SparseLu, ReportsASingularMatrix) {
  HostCsr a = nonsymmetric();
  // Zero the last row: the matrix is numerically singular.
  for (int k = a.row_ptr[a.n_rows - 1]; k < a.row_ptr[a.n_rows]; ++k) a.val[k] = 0;
  SparseLu lu;
  EXPECT_THROW(lu.setup(to_device(a)), std::runtime_error);
  // The solver is usable again afterwards.
  const HostCsr b = nonsymmetric();
  lu.setup(to_device(b));
  EXPECT_LT(solve_error(lu, b), 1e-11);
}
