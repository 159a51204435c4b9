// The condensed monolithic FSI operator (src/coupling): its matrix-free Jacobian action against
// central finite differences of its residual, at a state where every field and the fluid mesh
// move, with and without the shape derivatives.
//
// Tolerances, and why: the central difference with step 1e-6 of the state's scale carries a
// truncation error ~1e-12 relative and a round-off ~eps/1e-6 ~ 1e-10; the shape derivative inside
// the action is itself a one-sided difference (nodes moved by 1e-7 of the smallest element), good
// to ~1e-7 relative of that term. So the full action must match to 1e-5 of its norm (measured:
// 4e-12). Without the shape derivative the action must miss the difference by orders of magnitude
// more (measured 1.1e-4 at this slow, nearly undeformed state, where the shape term is small): the
// mesh motion's effect on the fluid is then genuinely left out, which is what
// ShapeDerivatives::None claims, and the finite-difference version does capture it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "coupling/fsi_test_support.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

// A state with flow, a deformed layer and a moved fluid mesh: smooth functions of position so the
// mesh stays valid, plus small random noise, added to the step's predictor on the free dofs only
// (constrained and condensed entries keep their values, as in a Newton iteration).
std::vector<double> moving_state(const Mesh& mesh, const std::vector<double>& predictor,
                                 const std::vector<char>& free, unsigned seed) {
  const int nn = mesh.n_nodes();
  std::vector<double> x(10 * nn, 0.0);
  const auto noise = random_values(10 * nn, -1, 1, seed);
  for (int n = 0; n < nn; ++n) {
    const double px = mesh.x[n][0], py = mesh.x[n][1];
    const double bump = std::sin(3.14159 * px) * std::sin(3.14159 * py);
    x[3 * n] = 0.01 * bump + 1e-3 * noise[3 * n];
    x[3 * n + 1] = 0.02 * bump + 1e-3 * noise[3 * n + 1];
    x[3 * nn + 4 * n] = (py - 0.25) + 0.1 * noise[3 * nn + 4 * n];
    x[3 * nn + 4 * n + 1] = 0.05 * bump + 0.1 * noise[3 * nn + 4 * n + 1];
    x[3 * nn + 4 * n + 3] = 0.3 * px + 0.1 * noise[3 * nn + 4 * n + 3];
    x[7 * nn + 3 * n] = 0.01 * bump + 1e-3 * noise[7 * nn + 3 * n];
    x[7 * nn + 3 * n + 1] = 0.015 * bump + 1e-3 * noise[7 * nn + 3 * n + 1];
  }
  for (int i = 0; i < 10 * nn; ++i) x[i] = predictor[i] + (free[i] ? x[i] : 0.0);
  return x;
}

// Relative mismatch ||J dx - (R(x + h dx) - R(x - h dx)) / 2h|| / ||J dx||.
double jacobian_mismatch(ShapeDerivatives shape) {
  LayerParameters p;
  p.shape = shape;
  LayerProblem lp = make_layer_problem(p);
  lp.fsi->prepare_step(0.05);
  const int n = lp.fsi->n_dofs();
  const std::vector<char> free = lp.fsi->free_dofs();
  const Vector x = device_vector(moving_state(lp.mesh, host_vector(lp.fsi->state()), free, 7));
  std::vector<double> direction = random_values(n, -1, 1, 11);
  for (int i = 0; i < n; ++i) direction[i] *= free[i];
  const Vector dx = device_vector(direction);
  Vector jdx("jdx", n), rp("rp", n), rm("rm", n), xp("xp", n);
  lp.fsi->tangent(x, dx, jdx);
  const double h = 1e-6;
  copy(x, xp);
  axpy(h, dx, xp);
  lp.fsi->residual(xp, rp);
  copy(x, xp);
  axpy(-h, dx, xp);
  lp.fsi->residual(xp, rm);
  axpy(-1.0, rm, rp);
  scale(1.0 / (2 * h), rp);
  axpy(-1.0, jdx, rp);
  return norm2(rp) / norm2(jdx);
}

}  // namespace

TEST(FsiOperator, JacobianMatchesFiniteDifferencesWithShapeDerivatives) {
  const double e = jacobian_mismatch(ShapeDerivatives::FiniteDifference);
  std::printf("[ measured ] |J dx - FD| / |J dx| with shape derivatives: %.3e\n", e);
  EXPECT_LT(e, 1e-5);
}

TEST(FsiOperator, JacobianWithoutShapeDerivativesMissesTheMeshMotion) {
  const double e_none = jacobian_mismatch(ShapeDerivatives::None);
  const double e_fd = jacobian_mismatch(ShapeDerivatives::FiniteDifference);
  std::printf("[ measured ] |J dx - FD| / |J dx| without shape derivatives: %.3e\n", e_none);
  EXPECT_GT(e_none, 1e-6);
  EXPECT_GT(e_none, 1e3 * e_fd);
}
