// Discrete balances of the scalar transport field: global mass balance of closed unsteady runs,
// conservation by pure diffusion, geometric conservation under prescribed mesh motion (ALE), and
// the consistent interface flux into the biofilm against the biofilm's consumption.
//
// Why these hold exactly (up to the algebraic solver): the shape functions sum to one, so summing
// the weak residual over all nodes removes every flux term (diffusion and SUPG) and leaves
//   (M_{n+1} - M_n)/dt + theta (R + C)_{n+1} + (1 - theta)(R + C)_n - S = sum_a r_a,
// with M = int phi, R = int R(phi), C = int c . grad phi, S = int s, all with the element
// quadrature. At a converged step sum_a r_a is bounded by sqrt(N) ||r|| (Cauchy-Schwarz), N nodes.
//
// Tolerances, and why:
//  * 1e-10 relative for balances (the requirement), relative to the consumption per step
//    dt (|theta R_{n+1}| + |(1 - theta) R_n|) or to M: Newton is run to 1e-12 relative, which
//    bounds the balance defect by ~1e-12 sqrt(N) of the residual scale; the measured defects and
//    the Cauchy-Schwarz bound are printed.
//  * 1e-12 relative for a constant under mesh motion (the round-off requirement): the
//    constant makes every term of the residual vanish identically, so only round-off remains.
//  * Interface flux against consumption: the Cauchy-Schwarz bound sqrt(N) ||r_final|| plus 1e-12
//    relative for summation order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "scalar/error_norms.hpp"
#include "scalar/scalar_test_support.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

constexpr double balance_tolerance = 1e-10;  // the requirement (see the header)

// int c_h . grad phi_h over the mesh with the kernels' 2x2x2 Gauss rule, evaluated here with the
// independent host quadrature (same rule, so the same number up to round-off).
double convective_integral(const Mesh& mesh, const std::vector<double>& phi,
                           const std::vector<Point>& c) {
  double s = 0;
  for_each_quadrature_point(mesh, 2, {}, [&](const QuadraturePoint& qp) {
    double cq[3] = {0, 0, 0}, g[3] = {0, 0, 0};
    for (int a = 0; a < 8; ++a) {
      const int n = mesh.conn[qp.element][a];
      for (int d = 0; d < 3; ++d) {
        cq[d] += qp.shape[a] * c[n][d];
        g[d] += qp.shape_gradient[a][d] * phi[n];
      }
    }
    s += qp.weight * (cq[0] * g[0] + cq[1] * g[1] + cq[2] * g[2]);
  });
  return s;
}

// Closed box (no boundary condition anywhere: zero flux), biofilm below y = 1/2 with Monod, fluid
// above; smooth non-uniform initial state.
struct ClosedRun {
  Mesh mesh;
  TransportSettings settings;
  ClosedRun(double theta, double k) {
    mesh = box_mesh(12, 1, 0.1, {{"biofilm", 0.0, 0.5, 6, 1.0}, {"fluid", 0.5, 1.0, 6, 1.0}});
    distort_smoothly(mesh);
    settings = tight_settings(theta);
    settings.coefficients.diffusivity[0] = 0.2;
    settings.coefficients.diffusivity[1] = 1.0;
    settings.coefficients.monod_rate[0] = k;
    settings.coefficients.monod_half_saturation[0] = 0.3;
  }
  static double initial(const Point& p, double) {
    return 1 + 0.5 * std::cos(pi * p[0]) * std::cos(pi * p[1]);
  }
};

// A solenoidal cellular flow, tangential to every wall: c . n = 0 on the box's sides.
Point cellular_flow(const Point& p) {
  return {0.5 * std::sin(pi * p[0]) * std::cos(pi * p[1]),
          -0.5 * std::cos(pi * p[0]) * std::sin(pi * p[1]), 0.0};
}

void check_closed_balance(double theta, bool convection) {
  ClosedRun run(theta, 2.0);
  TransportField field(run.mesh, run.settings, {});
  field.set_initial(ClosedRun::initial, 0.0);
  std::vector<Point> c(run.mesh.n_nodes(), Point{0, 0, 0});
  if (convection) {
    c = nodal_vectors(run.mesh, cellular_flow);
    field.set_convective_velocity(c);
  }
  const double dt = 0.05;
  double m = field.integral(), r = field.reaction_integral();
  double cv = convective_integral(run.mesh, field.solution_host(), c);
  double worst = 0, worst_bound = 0, max_conv = 0;
  for (int i = 0; i < 10; ++i) {
    const NewtonResult res = field.step(dt, "closed step " + std::to_string(i));
    ASSERT_TRUE(res.converged);
    const double m1 = field.integral(), r1 = field.reaction_integral();
    const double cv1 = convective_integral(run.mesh, field.solution_host(), c);
    const double defect = (m1 - m) + dt * (theta * (r1 + cv1) + (1 - theta) * (r + cv));
    const double scale = dt * (std::abs(theta * r1) + std::abs((1 - theta) * r));
    const double bound =
        dt * std::sqrt(static_cast<double>(run.mesh.n_nodes())) * res.residual_history.back();
    worst = std::max(worst, std::abs(defect) / scale);
    worst_bound = std::max(worst_bound, bound / scale);
    max_conv = std::max(max_conv, std::abs(cv1));
    EXPECT_LE(std::abs(defect), balance_tolerance * scale) << "step " << i;
    m = m1;
    r = r1;
    cv = cv1;
  }
  std::printf(
      "[ measured ] closed run, theta %.2f%s: max |balance defect| / (dt |R|) = %.2e "
      "(solver bound %.2e); max |int c.grad phi| = %.3e, final M = %.6f, R = %.6f\n",
      theta, convection ? ", cellular convection" : "", worst, worst_bound, max_conv, m, r);
}

}  // namespace

TEST(ScalarTransport, ClosedRunBalancesMassAgainstReactionIntegral) {
  check_closed_balance(0.66, false);
  check_closed_balance(0.5, false);
  check_closed_balance(1.0, false);
  // With convection the balance holds with the convective integral int c_h . grad phi_h, which
  // does not vanish: the convective (non-conservative) form conserves int phi only for a
  // discretely solenoidal c_h, and the nodal interpolant of a solenoidal field is not one.
  check_closed_balance(0.66, true);
}

TEST(ScalarTransport, PureDiffusionConservesMass) {
  ClosedRun run(0.66, 0.0);
  TransportField field(run.mesh, run.settings, {});
  field.set_initial(ClosedRun::initial, 0.0);
  const double m0 = field.integral();
  double worst = 0;
  for (int i = 0; i < 10; ++i) {
    ASSERT_TRUE(field.step(0.05, "diffusion step " + std::to_string(i)).converged);
    worst = std::max(worst, std::abs(field.integral() - m0) / std::abs(m0));
  }
  std::printf("[ measured ] pure diffusion: M_0 = %.15f, max |M_n - M_0| / M_0 = %.2e\n", m0,
              worst);
  EXPECT_LE(worst, balance_tolerance);
}

namespace {

// A smooth prescribed motion of every node, boundaries included, of amplitude up to ~4% of the
// box: x(t) = X + sin(2 pi t) d(X).
Point moved(const Point& X, double t) {
  const double a = 0.04 * std::sin(2 * pi * t);
  return {X[0] + a * std::sin(pi * X[1] + 0.3) * std::cos(pi * X[2]),
          X[1] + a * std::sin(pi * X[0]) * std::cos(2 * pi * X[2] + 0.5),
          X[2] + 0.5 * a * std::cos(pi * X[0]) * std::sin(pi * X[1])};
}

struct MotionRun {
  Mesh reference, current;
  explicit MotionRun(int n) {
    BoxSpec spec;
    spec.nx = spec.nz = n;
    spec.blocks = {{"biofilm", 0.0, 0.5, n / 2, 1.0}, {"fluid", 0.5, 1.0, n / 2, 1.0}};
    reference = make_box_mesh(spec);
    current = reference;
  }
  // Moves `current` to time t and returns c = -w = -(x_{n+1} - x_n) / dt per node.
  std::vector<Point> move_to(double t, double dt) {
    std::vector<Point> c(current.n_nodes());
    for (int n = 0; n < current.n_nodes(); ++n) {
      const Point x1 = moved(reference.x[n], t);
      for (int d = 0; d < 3; ++d) c[n][d] = -(x1[d] - current.x[n][d]) / dt;
      current.x[n] = x1;
    }
    return c;
  }
};

// No reaction anywhere; per-block diffusivities.
TransportSettings motion_settings(double theta, double d_biofilm, double d_fluid) {
  TransportSettings s = tight_settings(theta);
  s.coefficients.diffusivity[0] = d_biofilm;
  s.coefficients.diffusivity[1] = d_fluid;
  return s;
}

// Eight steps of 0.05 on the moving mesh: the largest |phi - exact| over the nodes and steps.
double largest_deviation_under_motion(MotionRun& run, TransportField& field,
                                      const SpaceTimeFunction& exact) {
  const double dt = 0.05;
  double worst = 0;
  for (int i = 0; i < 8; ++i) {
    const auto c = run.move_to(field.time() + dt, dt);
    field.update_coordinates(run.current);
    field.set_convective_velocity(c);
    EXPECT_TRUE(field.step(dt, "moving step " + std::to_string(i)).converged);
    const auto phi = field.solution_host();
    for (int n = 0; n < run.current.n_nodes(); ++n)
      worst = std::max(worst, std::abs(phi[n] - exact(run.current.x[n], 0.0)));
  }
  return worst;
}

}  // namespace

TEST(ScalarTransport, ConstantFieldStaysConstantUnderMeshMotion) {
  const double value = 0.7;
  MotionRun run(4);
  const SpaceTimeFunction constant = [value](const Point&, double) { return value; };
  TransportField field(run.current, motion_settings(0.66, 0.3, 1.0), {dirichlet("top", constant)});
  field.set_initial(constant, 0.0);
  const double worst = largest_deviation_under_motion(run, field, constant) / value;
  std::printf(
      "[ measured ] constant under mesh motion (8 steps, theta 0.66): max relative "
      "deviation %.2e\n",
      worst);
  EXPECT_LE(worst, 1e-12);
}

// A field linear in space and constant in time at each point is a + b.x at the moving nodes; the
// ALE convective velocity c = -w makes it an exact solution of the discrete equations when every
// term is evaluated on x_{n+1} (theta = 1). This checks the sign and the scaling of c. (One
// diffusivity for both blocks: with a jump in D a linear field has a flux jump at the interface
// and is no solution at all.)
double linear_field_error_under_motion(double theta) {
  MotionRun run(4);
  const SpaceTimeFunction linear = [](const Point& p, double) {
    return 1 + 0.5 * p[0] - 0.3 * p[1] + 0.2 * p[2];
  };
  TransportField field(run.current, motion_settings(theta, 0.3, 0.3),
                       dirichlet_on({"left", "right", "bottom", "top", "front", "back"}, linear));
  field.set_initial(linear, 0.0);
  return largest_deviation_under_motion(run, field, linear);
}

TEST(ScalarTransport, LinearFieldIsReproducedUnderMeshMotionWithBackwardEuler) {
  const double worst = linear_field_error_under_motion(1.0);
  // For information: with theta < 1 the (1 - theta) terms of phi_n are evaluated with the nodal
  // values of phi_n on the new coordinates x_{n+1}, where grad phi_n = b - dt grad(b . w_h), which
  // leaves an O((1 - theta) dt |w| |grad w|) consistency error per unit time.
  const double worst_066 = linear_field_error_under_motion(0.66);
  const double worst_05 = linear_field_error_under_motion(0.5);
  std::printf(
      "[ measured ] linear field under mesh motion (8 steps): max nodal error theta 1: "
      "%.2e; theta 0.66: %.2e; theta 0.5: %.2e\n",
      worst, worst_066, worst_05);
  // Newton to 1e-12 relative of an initial residual that is O(|b| |w| dt) per node: the nodal
  // error must be at round-off level, far below the ~1e-4 that a wrong sign or scaling of c or a
  // mesh velocity on the wrong configuration leaves (compare theta < 1 above).
  EXPECT_LE(worst, 1e-10);
}

TEST(ScalarTransport, InterfaceFluxEqualsBiofilmConsumptionAtSteadyState) {
  const int n = 16;
  Mesh mesh =
      box_mesh(n, 1, 0.1, {{"biofilm", 0.0, 0.5, n / 2, 1.0}, {"fluid", 0.5, 1.0, n / 2, 1.0}});
  distort_smoothly(mesh);
  const int biofilm = mesh.block_index("biofilm"), fluid = mesh.block_index("fluid");
  TransportSettings s = tight_settings();
  s.coefficients.diffusivity[biofilm] = 0.2;
  s.coefficients.monod_rate[biofilm] = 2.0;
  s.coefficients.monod_half_saturation[biofilm] = 0.3;
  s.coefficients.diffusivity[fluid] = 0.05;  // no reaction in the fluid
  const SpaceTimeFunction one = [](const Point&, double) { return 1.0; };
  TransportField field(mesh, s, {dirichlet("top", one)});
  field.set_initial(one, 0.0);
  // Shear flow over the film (zero on the interface nodes and in the biofilm) entering on the left
  // and leaving on the right (natural conditions there); every interface node is free.
  field.set_convective_velocity(nodal_vectors(mesh, [](const Point& p) {
    return Point{p[1] > 0.5 ? 2 * (p[1] - 0.5) : 0.0, 0.0, 0.0};
  }));
  const NewtonResult res = field.solve_steady("interface flux");
  ASSERT_TRUE(res.converged);

  const BoundaryFlux into_biofilm = field.boundary_flux("biofilm_fluid", biofilm);
  const BoundaryFlux into_fluid = field.boundary_flux("biofilm_fluid", fluid);
  const double consumption = field.reaction_integral();
  // Independent: int_biofilm R(phi_h) with the host 2x2x2 Gauss rule (the kernels' rule).
  const auto phi = field.solution_host();
  double host_consumption = 0;
  const double k = 2.0, K = 0.3;
  for_each_quadrature_point(field.mesh(), 2, field.mesh().elements_of_block(biofilm),
                            [&](const QuadraturePoint& qp) {
                              double u = 0;
                              for (int a = 0; a < 8; ++a)
                                u += qp.shape[a] * phi[field.mesh().conn[qp.element][a]];
                              host_consumption += qp.weight * k * u / (K + std::abs(u));
                            });
  const double bound =
      std::sqrt(static_cast<double>(mesh.n_nodes())) * res.residual_history.back() +
      1e-12 * consumption;
  std::printf(
      "[ measured ] interface flux into biofilm %.12e, into fluid %.12e, biofilm "
      "consumption %.12e (host quadrature %.12e); |flux - consumption| = %.2e, solver "
      "bound %.2e\n",
      into_biofilm.total, into_fluid.total, consumption, host_consumption,
      std::abs(into_biofilm.total - consumption), bound);
  EXPECT_GT(consumption, 0.0);
  EXPECT_NEAR(host_consumption, consumption, 1e-12 * consumption);
  EXPECT_NEAR(into_biofilm.total, consumption, bound);
  // Equal flux on both sides: the full residual vanishes at the (free) interface nodes.
  EXPECT_NEAR(into_fluid.total, -into_biofilm.total, bound);
}

// The Phi div w term of a deforming biofilm (paper eq. 9): under a uniform dilation
// w = eps (x, y, z) (div w = 3 eps) a spatially uniform Phi with no-flux boundaries obeys
// dPhi/dt = -3 eps Phi, Phi(T) = Phi_0 exp(-3 eps T). The one-step-theta scheme is second order
// for theta = 0.5 and first order for theta = 1; the observed order from dt/2 to dt/4 must be
// within 0.1 of those (the error is purely temporal: the field stays uniform to round-off, which
// the test also checks).
double dilation_error(double theta, int steps) {
  const Mesh mesh = box_mesh(2, 1, 0.5, {{"biofilm", 0.0, 1.0, 2, 1.0}});
  TransportSettings s = tight_settings(theta);
  s.coefficients.diffusivity[0] = 0.1;
  s.coefficients.material_motion[0] = 1;
  TransportField field(mesh, s, {});
  const double phi0 = 2.0, eps = 0.5, T = 1.0, dt = T / steps;
  field.set_initial([phi0](const Point&, double) { return phi0; }, 0.0);
  std::vector<Point> w(mesh.n_nodes());
  for (int n = 0; n < mesh.n_nodes(); ++n)
    for (int d = 0; d < 3; ++d) w[n][d] = eps * mesh.x[n][d];
  field.set_material_velocity(w);
  for (int i = 0; i < steps; ++i)
    EXPECT_TRUE(field.step(dt, "dilation step " + std::to_string(i)).converged);
  const auto phi = field.solution_host();
  const auto [lo, hi] = std::minmax_element(phi.begin(), phi.end());
  EXPECT_LT(*hi - *lo, 1e-10 * phi0) << "the field must stay uniform";
  return std::abs(phi[0] - phi0 * std::exp(-3 * eps * T));
}

TEST(ScalarTransport, MaterialDilationTermConvergesAtTheSchemeOrder) {
  for (double theta : {0.5, 1.0}) {
    const double e1 = dilation_error(theta, 5), e2 = dilation_error(theta, 10),
                 e4 = dilation_error(theta, 20);
    const double o1 = std::log2(e1 / e2), o2 = std::log2(e2 / e4);
    std::printf("[ measured ] Phi div w, theta %.1f: errors %.3e %.3e %.3e, orders %.3f %.3f\n",
                theta, e1, e2, e4, o1, o2);
    const double expected = theta == 0.5 ? 2.0 : 1.0;
    EXPECT_NEAR(o2, expected, 0.1);
  }
}
