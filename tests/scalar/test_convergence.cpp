// Verification of the scalar transport field (src/scalar/transport.*) by manufactured solutions:
// observed orders of convergence in space on smoothly distorted meshes for steady
// diffusion-reaction (Monod, per-block coefficients), steady convection-diffusion with SUPG and
// the unsteady problem, and observed orders in time of the one-step-theta scheme.
//
// Errors are measured by the independent host quadrature of scalar/error_norms.hpp (3x3x3 Gauss,
// trilinear shape functions on the current coordinates). Meshes are pseudo-2-D (one element
// through a thin z-layer; the solutions do not depend on z, so the natural condition on the front
// and back faces is exact).
//
// Tolerances, and why:
//  * Orders within 0.1 of theory (Q1: L2 order 2, H1-seminorm order 1; theta = 1/2: order 2 in
//    time, theta = 1: order 1), observed between the last two refinements: the issue's
//    requirement. The solutions are smooth and the distortion map is fixed, so the runs are in the
//    asymptotic range and the observed orders are within a few hundredths of theory; a wrong
//    quadrature weight, a dropped metric term or an inconsistent source evaluation time shows up
//    as an order loss of 0.5 or more.
//  * Newton is run to 1e-12 relative (tight_settings), so that the algebraic error is at least
//    four orders below the finest discretisation error measured here.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "scalar/error_norms.hpp"
#include "scalar/scalar_test_support.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

constexpr double order_tolerance = 0.1;  // the requirement (see the header)

void print_study(const char* name, const std::vector<int>& n, const std::vector<ErrorNorms>& e) {
  std::printf("[ measured ] %s\n", name);
  for (size_t i = 0; i < n.size(); ++i) {
    std::printf("[ measured ]   n = %3d  L2 = %.4e  H1 = %.4e", n[i], e[i].l2, e[i].h1);
    if (i > 0)
      std::printf("  order L2 = %.3f  H1 = %.3f", observed_order(e[i - 1].l2, e[i].l2),
                  observed_order(e[i - 1].h1, e[i].h1));
    std::printf("\n");
  }
}

void expect_optimal_orders(const std::vector<ErrorNorms>& e) {
  const size_t f = e.size() - 1;
  EXPECT_NEAR(observed_order(e[f - 1].l2, e[f].l2), 2.0, order_tolerance);
  EXPECT_NEAR(observed_order(e[f - 1].h1, e[f].h1), 1.0, order_tolerance);
}

// ---- (a) steady diffusion-reaction, Monod, two blocks with their own coefficients ----
//
// Blocks "biofilm" (y < 1/2) and "fluid" (y > 1/2) with D_b, k_b, K_b. The exact solution
//   u = 2 + X(x) Y_b(y) / 2,  X = cos(2x - 1/2),  Y_b = cos(2(y - 1/2)) + sin(2(y - 1/2)) / D_b
// is continuous with continuous flux D_b du/dy across y = 1/2 (D_b Y_b'(1/2) = 2 on both sides),
// satisfies -D_b lap u = 4 D_b X Y_b, and stays in [0.5, 3.5] (Monod away from its kink at 0).
struct BlockCoefficients {
  double D, k, K;
};
constexpr double interface_y = 0.5;
constexpr BlockCoefficients block_coef[2] = {{0.5, 2.0, 0.5}, {1.0, 1.0, 2.0}};

struct DiffusionReaction {
  static int block(double y) { return y < interface_y ? 0 : 1; }
  static double X(double x) { return std::cos(2 * x - 0.5); }
  static double dX(double x) { return -2 * std::sin(2 * x - 0.5); }
  static double Y(int b, double y) {
    const double s = 2 * (y - interface_y);
    return std::cos(s) + std::sin(s) / block_coef[b].D;
  }
  static double dY(int b, double y) {
    const double s = 2 * (y - interface_y);
    return -2 * std::sin(s) + 2 * std::cos(s) / block_coef[b].D;
  }
  static double u(const Point& p) { return 2 + 0.5 * X(p[0]) * Y(block(p[1]), p[1]); }
  static Gradient grad(const Point& p) {
    const int b = block(p[1]);
    return {0.5 * dX(p[0]) * Y(b, p[1]), 0.5 * X(p[0]) * dY(b, p[1]), 0.0};
  }
  static double source_in_block(int b, const Point& p) {
    const BlockCoefficients& c = block_coef[b];
    const double uu = 2 + 0.5 * X(p[0]) * Y(b, p[1]);
    return 4 * c.D * X(p[0]) * Y(b, p[1]) + c.k * uu / (c.K + uu);
  }
  // The source is a nodal field, so an interface node carries one value for two different
  // one-sided sources. The mean of the two makes the interpolation errors of the two adjacent
  // element layers cancel to O(h^2) (a one-sided value would leave an O(h) source error on an
  // O(h) strip, i.e. an O(h) error in L2).
  static double source(const Point& p) {
    if (std::abs(p[1] - interface_y) < 1e-12)
      return 0.5 * (source_in_block(0, p) + source_in_block(1, p));
    return source_in_block(block(p[1]), p);
  }
};

ErrorNorms solve_diffusion_reaction(int n) {
  Mesh mesh = box_mesh(
      n, 1, 0.1,
      {{"biofilm", 0.0, interface_y, n / 2, 1.0}, {"fluid", interface_y, 1.0, n / 2, 1.0}});
  distort_smoothly(mesh);
  TransportSettings s = tight_settings();
  for (int b = 0; b < 2; ++b) {
    s.coefficients.diffusivity[b] = block_coef[b].D;
    s.coefficients.monod_rate[b] = block_coef[b].k;
    s.coefficients.monod_half_saturation[b] = block_coef[b].K;
  }
  const SpaceTimeFunction exact = [](const Point& p, double) { return DiffusionReaction::u(p); };
  TransportField field(mesh, s, dirichlet_on({"left", "right", "bottom", "top"}, exact));
  field.set_initial([](const Point&, double) { return 1.0; }, 0.0);
  field.set_source([](const Point& p, double) { return DiffusionReaction::source(p); });
  const NewtonResult r = field.solve_steady("diffusion-reaction n=" + std::to_string(n));
  EXPECT_TRUE(r.converged);
  return error_norms(field.mesh(), field.solution_host(), DiffusionReaction::u,
                     DiffusionReaction::grad);
}

// ---- (b) steady convection-diffusion with SUPG ----
//
// u = sin(2x + 1) cos(1.5y) + xy with the smooth convective velocity
// c = (1 + 0.3 sin 3y, 0.5 cos 2x, 0) and D = 0.05: global Peclet |c| L / D ~ 25, element Peclet
// |c| h / 2D from ~0.8 (n = 16) to ~0.2 (n = 64), i.e. SUPG is active (tau ~ h^2 / 12D
// asymptotically, which keeps the scheme second order in L2).
constexpr double cd_diffusivity = 0.05;

struct ConvectionDiffusion {
  static double u(const Point& p) {
    return std::sin(2 * p[0] + 1) * std::cos(1.5 * p[1]) + p[0] * p[1];
  }
  static Gradient grad(const Point& p) {
    return {2 * std::cos(2 * p[0] + 1) * std::cos(1.5 * p[1]) + p[1],
            -1.5 * std::sin(2 * p[0] + 1) * std::sin(1.5 * p[1]) + p[0], 0.0};
  }
  static double laplacian(const Point& p) {
    return -6.25 * std::sin(2 * p[0] + 1) * std::cos(1.5 * p[1]);
  }
  static Point velocity(const Point& p) {
    return {1 + 0.3 * std::sin(3 * p[1]), 0.5 * std::cos(2 * p[0]), 0.0};
  }
  // -D lap u + c . grad u
  static double operator_of_u(const Point& p) {
    const Gradient g = grad(p);
    const Point c = velocity(p);
    return -cd_diffusivity * laplacian(p) + c[0] * g[0] + c[1] * g[1];
  }
};

ErrorNorms solve_convection_diffusion(int n) {
  Mesh mesh = box_mesh(n, 1, 0.1, {{"fluid", 0.0, 1.0, n, 1.0}});
  distort_smoothly(mesh);
  TransportSettings s = tight_settings();
  s.coefficients.diffusivity[0] = cd_diffusivity;
  const SpaceTimeFunction exact = [](const Point& p, double) { return ConvectionDiffusion::u(p); };
  TransportField field(mesh, s, dirichlet_on({"left", "right", "bottom", "top"}, exact));
  field.set_initial([](const Point&, double) { return 0.0; }, 0.0);
  field.set_convective_velocity(nodal_vectors(mesh, ConvectionDiffusion::velocity));
  field.set_source([](const Point& p, double) { return ConvectionDiffusion::operator_of_u(p); });
  const NewtonResult r = field.solve_steady("convection-diffusion n=" + std::to_string(n));
  EXPECT_TRUE(r.converged);
  return error_norms(field.mesh(), field.solution_host(), ConvectionDiffusion::u,
                     ConvectionDiffusion::grad);
}

// ---- (c) the unsteady problem in space ----
//
// u(x, t) = (1 + t) U(x) with U the convection-diffusion solution above: linear in time, so the
// one-step-theta scheme (any theta, source at t_{n+theta}) has no time truncation error and the
// error at the final time is the spatial error of the transient scheme (SUPG with its transient
// tau included). theta = 0.66 as in the paper.
constexpr double unsteady_dt = 0.05;
constexpr int unsteady_steps = 4;

struct UnsteadyRun {
  std::vector<double> solution;
  TransportStats stats;
};

ErrorNorms solve_unsteady(int n, ScalarPreconditioner preconditioner = ScalarPreconditioner::Amg,
                          UnsteadyRun* run = nullptr) {
  Mesh mesh = box_mesh(n, 1, 0.1, {{"fluid", 0.0, 1.0, n, 1.0}});
  distort_smoothly(mesh);
  TransportSettings s = tight_settings(0.66);
  s.preconditioner = preconditioner;
  s.coefficients.diffusivity[0] = cd_diffusivity;
  const SpaceTimeFunction exact = [](const Point& p, double t) {
    return (1 + t) * ConvectionDiffusion::u(p);
  };
  TransportField field(mesh, s, dirichlet_on({"left", "right", "bottom", "top"}, exact));
  field.set_initial(exact, 0.0);
  field.set_convective_velocity(nodal_vectors(mesh, ConvectionDiffusion::velocity));
  // du/dt + c . grad u - D lap u = U + (1 + t) (c . grad U - D lap U)
  field.set_source([](const Point& p, double t) {
    return ConvectionDiffusion::u(p) + (1 + t) * ConvectionDiffusion::operator_of_u(p);
  });
  for (int i = 0; i < unsteady_steps; ++i) {
    const NewtonResult r = field.step(unsteady_dt, "unsteady step " + std::to_string(i));
    EXPECT_TRUE(r.converged);
  }
  const double t = field.time();
  EXPECT_NEAR(t, unsteady_steps * unsteady_dt, 1e-14);
  if (run) *run = {field.solution_host(), field.stats()};
  return error_norms(
      field.mesh(), field.solution_host(),
      [t](const Point& p) { return (1 + t) * ConvectionDiffusion::u(p); },
      [t](const Point& p) {
        Gradient g = ConvectionDiffusion::grad(p);
        for (double& v : g) v *= 1 + t;
        return g;
      });
}

template <class Solve>
std::vector<ErrorNorms> study(const std::vector<int>& n, Solve solve) {
  std::vector<ErrorNorms> e;
  for (int ni : n) e.push_back(solve(ni));
  return e;
}

// ---- time order ----
//
// (i) A PDE whose solution is linear in space, u = (1 + x/2 - 3y/10) g(t), g = 1 + sin(3t)/2,
// with constant convection and diffusion on a distorted 4x4 mesh: trilinear elements reproduce
// it exactly, so the error at t = 1 is the time error alone (Dirichlet data on all sides, the
// time-dependent source and the SUPG residual all enter).
// (ii) The nonlinear Monod reaction: a closed box (no boundary conditions) with a uniform state
// u(t) = 1 + sin(2t)/2, so that every node follows the theta scheme applied to
// u' = -k u/(K + u) + s(t).
constexpr double time_c[3] = {0.4, 0.2, 0.0};
constexpr double time_D = 0.1;

double time_error_linear_in_space(double theta, int steps) {
  Mesh mesh = box_mesh(4, 1, 0.25, {{"fluid", 0.0, 1.0, 4, 1.0}});
  distort_smoothly(mesh);
  TransportSettings s = tight_settings(theta);
  s.coefficients.diffusivity[0] = time_D;
  auto L = [](const Point& p) { return 1 + 0.5 * p[0] - 0.3 * p[1]; };
  auto g = [](double t) { return 1 + 0.5 * std::sin(3 * t); };
  auto dg = [](double t) { return 1.5 * std::cos(3 * t); };
  const SpaceTimeFunction exact = [=](const Point& p, double t) { return L(p) * g(t); };
  TransportField field(mesh, s, dirichlet_on({"left", "right", "bottom", "top"}, exact));
  field.set_initial(exact, 0.0);
  field.set_convective_velocity(nodal_vectors(mesh, [](const Point&) {
    return Point{time_c[0], time_c[1], time_c[2]};
  }));
  // du/dt + c . grad u (lap u = 0)
  field.set_source([=](const Point& p, double t) {
    return L(p) * dg(t) + g(t) * (0.5 * time_c[0] - 0.3 * time_c[1]);
  });
  const double dt = 1.0 / steps;
  for (int i = 0; i < steps; ++i) field.step(dt, "linear-in-space step " + std::to_string(i));
  const auto u = field.solution_host();
  double e = 0;
  for (int n = 0; n < mesh.n_nodes(); ++n)
    e = std::max(e, std::abs(u[n] - exact(field.mesh().x[n], field.time())));
  return e;
}

double time_error_monod_ode(double theta, int steps) {
  const double k = 2.0, K = 0.5;
  Mesh mesh = box_mesh(2, 1, 0.5, {{"biofilm", 0.0, 1.0, 2, 1.0}});
  distort_smoothly(mesh);
  TransportSettings s = tight_settings(theta);
  s.coefficients.diffusivity[0] = 1.0;
  s.coefficients.monod_rate[0] = k;
  s.coefficients.monod_half_saturation[0] = K;
  auto u = [](double t) { return 1 + 0.5 * std::sin(2 * t); };
  TransportField field(mesh, s, {});
  field.set_initial([=](const Point&, double t) { return u(t); }, 0.0);
  field.set_source([=](const Point&, double t) {
    return std::cos(2 * t) + k * u(t) / (K + u(t));  // u' + R(u)
  });
  const double dt = 1.0 / steps;
  for (int i = 0; i < steps; ++i) field.step(dt, "Monod ODE step " + std::to_string(i));
  const auto uh = field.solution_host();
  double e = 0;
  for (double v : uh) e = std::max(e, std::abs(v - u(field.time())));
  return e;
}

void time_study(const char* name, double theta, double expected,
                double (*error)(double theta, int steps)) {
  const std::vector<int> steps = {10, 20, 40, 80};
  std::vector<double> e;
  std::printf("[ measured ] %s, theta = %.2f\n", name, theta);
  for (size_t i = 0; i < steps.size(); ++i) {
    e.push_back(error(theta, steps[i]));
    std::printf("[ measured ]   steps = %3d  max nodal error at t = 1: %.4e", steps[i], e[i]);
    if (i > 0) std::printf("  order %.3f", observed_order(e[i - 1], e[i]));
    std::printf("\n");
  }
  EXPECT_NEAR(observed_order(e[e.size() - 2], e.back()), expected, order_tolerance);
}

}  // namespace

TEST(ScalarTransport, DiffusionReactionConvergesAtSecondOrderInL2AndFirstInH1OnDistortedMesh) {
  const std::vector<int> n = {8, 16, 32};
  const auto e = study(n, solve_diffusion_reaction);
  print_study("steady diffusion + Monod, two blocks, distorted mesh", n, e);
  expect_optimal_orders(e);
}

TEST(ScalarTransport, ConvectionDiffusionWithSupgConvergesAtSecondOrderInL2AndFirstInH1) {
  const std::vector<int> n = {16, 32, 64};
  const auto e = study(n, solve_convection_diffusion);
  print_study("steady convection-diffusion, SUPG, distorted mesh", n, e);
  expect_optimal_orders(e);
}

TEST(ScalarTransport, UnsteadyConvectionDiffusionConvergesAtSecondOrderInL2AndFirstInH1) {
  const std::vector<int> n = {8, 16, 32};
  const auto e = study(n, [](int k) { return solve_unsteady(k); });
  print_study("unsteady convection-diffusion (theta 0.66), SUPG, distorted mesh", n, e);
  expect_optimal_orders(e);
}

// The sparse LU preconditioner (fields.scalar.preconditioner: direct) changes the Krylov path,
// not the solution: both runs solve Newton to 1e-12 relative, so their nodal values agree to
// ~1e-12 of the solution's size; 1e-9 leaves room for the conditioning. The LU of the exact
// Jacobian, kept across Newton and time steps like the AMG hierarchy, needs at most 3 Krylov
// iterations per Newton step (1 where it is fresh), and fewer in all than AMG.
TEST(ScalarTransport, DirectPreconditionerGivesTheAmgSolutionInFewerKrylovIterations) {
  UnsteadyRun amg, direct;
  solve_unsteady(16, ScalarPreconditioner::Amg, &amg);
  solve_unsteady(16, ScalarPreconditioner::Direct, &direct);
  double diff = 0, size = 0;
  for (size_t i = 0; i < amg.solution.size(); ++i) {
    diff = std::max(diff, std::abs(amg.solution[i] - direct.solution[i]));
    size = std::max(size, std::abs(amg.solution[i]));
  }
  std::printf(
      "[ measured ] max nodal difference %.3e (max |u| %.3f); Krylov per Newton step: "
      "AMG %d / %d, direct %d / %d\n",
      diff, size, amg.stats.krylov_iterations, amg.stats.newton_iterations,
      direct.stats.krylov_iterations, direct.stats.newton_iterations);
  EXPECT_LT(diff, 1e-9 * size);
  EXPECT_LT(direct.stats.krylov_iterations, amg.stats.krylov_iterations);
  EXPECT_LE(direct.stats.krylov_iterations, 3 * direct.stats.newton_iterations);
}

TEST(ScalarTransport, ThetaHalfIsSecondOrderAndThetaOneFirstOrderInTime) {
  time_study("linear-in-space convection-diffusion", 0.5, 2.0, time_error_linear_in_space);
  time_study("linear-in-space convection-diffusion", 1.0, 1.0, time_error_linear_in_space);
  time_study("uniform state with Monod consumption", 0.5, 2.0, time_error_monod_ode);
  time_study("uniform state with Monod consumption", 1.0, 1.0, time_error_monod_ode);
}
