// The scalar transport field at the extremes (DESIGN.md section 6): convection-dominated boundary
// layers up to Peclet 1e8 with SUPG, and single backward-Euler steps from 1e-9 to 1e9 ms. (Monod
// with a vanishing half-saturation constant is in test_biofilm.cpp.)
//
// Tolerances, and why:
//  * Boundary layer: nodal error <= 1e-8 (the "~1e-8"): SUPG with
//    tau = (h/2a)(coth Pe - 1/Pe) is nodally exact for linear elements on a flow-aligned mesh, also
//    for non-uniform element sizes (benchmarks.md, "Convection-dominated transport"); what remains
//    is the algebraic error of a Newton solve to 1e-12 relative. Bounds [-5%, 105%]: the issue's
//    limit on overshoot.
//  * Time-step sweep: the distance to the steady solution must decrease strictly from each decade
//    of dt to the next (the backward-Euler step damps every mode by 1/(1 + dt lambda), monotone in
//    dt), and the 1e9 step must match the steady solve to 1e-6 relative (the number; the
//    expected deviation is ~1/(dt lambda_min) ~ 1e-9 plus the solver tolerance).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "scalar/scalar_test_support.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

// -eps u'' + a u' = 0 on [0, 1], u = 0 at the inflow, u = 1 at the outflow, as a function of the
// distance s from the outflow, written so that it does not overflow:
// u = (exp(-a s/eps) - exp(-a/eps)) / (1 - exp(-a/eps)).
double boundary_layer(double s, double a, double eps) {
  const double e = std::exp(-a / eps);
  return (std::exp(-a * s / eps) - e) / (1 - e);
}

struct LayerResult {
  double nodal_error = 0, min = 0, max = 0;
  NewtonResult newton;
};

// A column of one element across x and z, n elements along y, with the flow c = (0, -a, 0)
// entering at the top (u = 0) and leaving at the bottom (u = 1), where the layer forms: the layer
// sits at y ~ 0, so that elements as thin as 1e-9 are not rounded away against coordinates of
// size 1. `grading` = last/first element height (> 1: refined towards the layer). Newton starts
// from u = 1 - y, so that it has work to do even where the exact nodal values are 0 and 1.
LayerResult solve_boundary_layer(double peclet, int n, double grading) {
  BoxSpec spec;
  spec.x1 = spec.z1 = 0.1;
  spec.blocks = {{"fluid", 0.0, 1.0, n, grading}};
  const Mesh mesh = make_box_mesh(spec);
  const double a = 1.0, eps = a / peclet;
  TransportSettings s = tight_settings();
  s.coefficients.diffusivity[0] = eps;
  TransportField field(mesh, s,
                       {dirichlet("bottom", [](const Point&, double) { return 1.0; }),
                        dirichlet("top", [](const Point&, double) { return 0.0; })});
  field.set_initial([](const Point& p, double) { return 1 - p[1]; }, 0.0);
  field.set_convective_velocity(nodal_vectors(mesh, [a](const Point&) { return Point{0, -a, 0}; }));
  LayerResult r;
  r.newton = field.solve_steady("boundary layer");
  const auto u = field.solution_host();
  r.min = *std::min_element(u.begin(), u.end());
  r.max = *std::max_element(u.begin(), u.end());
  for (int i = 0; i < mesh.n_nodes(); ++i)
    r.nodal_error = std::max(r.nodal_error, std::abs(u[i] - boundary_layer(mesh.x[i][1], a, eps)));
  return r;
}

}  // namespace

TEST(ScalarTransport, SupgBoundaryLayerIsNodallyExactWithoutOvershootUpToPeclet1e8) {
  struct MeshCase {
    int n;
    bool graded;
  };
  // 20 uniform elements (the layer lies inside the last element for Pe >= 1e3), and 40 elements
  // graded by Pe, which resolves the layer (element Peclet from ~Pe/5 at the inflow down to
  // ~0.05-0.2 in the layer), so that the coth and the Pe > 50 branches of tau are both used.
  for (const MeshCase m : {MeshCase{20, false}, MeshCase{40, true}}) {
    for (double peclet : {1e2, 1e4, 1e6, 1e8}) {
      const double grading = m.graded ? peclet : 1.0;
      const LayerResult r = solve_boundary_layer(peclet, m.n, grading);
      std::printf(
          "[ measured ] boundary layer Pe %.0e, %d elements, grading %.0e: nodal error "
          "%.2e, range [%.3e, %.15f], Newton %d iterations (%d Krylov)\n",
          peclet, m.n, grading, r.nodal_error, r.min, r.max, r.newton.iterations,
          r.newton.krylov_iterations);
      EXPECT_TRUE(r.newton.converged);
      EXPECT_GE(r.min, -0.05) << "Pe " << peclet;
      EXPECT_LE(r.max, 1.05) << "Pe " << peclet;
      EXPECT_LE(r.nodal_error, 1e-8) << "Pe " << peclet << ", grading " << grading;
    }
  }
}

namespace {

// Biofilm (Monod) below y = 1/2, fluid with a shear flow above, on a distorted pseudo-2-D mesh;
// S = 1 on top and at the fluid inflow.
struct SweepProblem {
  Mesh mesh;
  TransportSettings settings;
  std::vector<ScalarBoundaryCondition> conditions;
  std::vector<Point> velocity;
  SweepProblem() {
    mesh = box_mesh(16, 1, 0.1, {{"biofilm", 0.0, 0.5, 8, 1.0}, {"fluid", 0.5, 1.0, 8, 1.0}});
    distort_smoothly(mesh);
    // Backward Euler (the steady state is its dt -> inf limit) with the library's default Newton
    // tolerances, as a run would use them.
    settings.theta = 1.0;
    settings.coefficients.diffusivity[0] = 0.2;
    settings.coefficients.monod_rate[0] = 2.0;
    settings.coefficients.monod_half_saturation[0] = 0.3;
    settings.coefficients.diffusivity[1] = 0.05;
    const SpaceTimeFunction one = [](const Point&, double) { return 1.0; };
    conditions = {dirichlet("top", one), dirichlet("fluid_left", one)};
    velocity = nodal_vectors(mesh, [](const Point& p) {
      return Point{p[1] > 0.5 ? 2 * (p[1] - 0.5) : 0.0, 0.0, 0.0};
    });
  }
};

double relative_distance(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0, n = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    d += (a[i] - b[i]) * (a[i] - b[i]);
    n += b[i] * b[i];
  }
  return std::sqrt(d / n);
}

}  // namespace

TEST(ScalarTransport, SingleBackwardEulerStepApproachesSteadyStateMonotonicallyInTimeStep) {
  SweepProblem p;
  TransportField steady(p.mesh, p.settings, p.conditions);
  steady.set_initial([](const Point&, double) { return 1.0; }, 0.0);
  steady.set_convective_velocity(p.velocity);
  ASSERT_TRUE(steady.solve_steady("steady").converged);
  const auto phi_steady = steady.solution_host();

  TransportField field(p.mesh, p.settings, p.conditions);
  field.set_convective_velocity(p.velocity);
  const std::vector<double> phi0(p.mesh.n_nodes(), 1.0);  // satisfies the boundary conditions
  const double d0 = relative_distance(phi0, phi_steady);
  std::printf("[ measured ] initial state: relative distance to steady %.6e\n", d0);
  double previous = d0;
  for (int e = -9; e <= 9; ++e) {
    const double dt = std::pow(10.0, e);
    field.set_solution(phi0);
    NewtonResult r;
    try {
      r = field.step(dt, "dt 1e" + std::to_string(e));
    } catch (const SolveError& error) {
      ADD_FAILURE() << "dt = " << dt << ": " << error.what();
      continue;
    }
    const auto phi = field.solution_host();
    for (double v : phi) ASSERT_TRUE(std::isfinite(v)) << "dt = " << dt;
    const double d = relative_distance(phi, phi_steady);
    std::printf(
        "[ measured ] dt = 1e%+d: relative distance to steady %.6e (decrease %.3e), "
        "Newton %d iterations\n",
        e, d, previous - d, r.iterations);
    EXPECT_LT(d, previous) << "dt = " << dt;
    previous = d;
  }
  EXPECT_LE(previous, 1e-6);
}
