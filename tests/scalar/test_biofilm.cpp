// The 1-D biofilm diffusion-reaction solutions of reference/benchmarks.md ("1-D biofilm
// diffusion-reaction (analytic)") reproduced by the scalar transport field on pseudo-1-D meshes:
// one element across x and z, the film along y on an impermeable wall y = 0 (no condition: the
// natural zero flux) with the surface concentration S_s prescribed on top. The substrate flux J
// into the film is read as the consistent nodal reaction flux on the top face
// (TransportField::boundary_flux), the way the growth model reads it, divided by the face area.
//
// Geometry from the paper's biofilm (thickness L_f = 2 mm) on a 0.2 mm x 0.2 mm column; D_f and
// the kinetics are chosen for the regimes of interest (a Thiele modulus of 2; a Monod film with
// partial and with deep penetration), not as material data. Units mm, ms.
//
// Tolerances, and why:
//  * Fluxes within 0.5% of the analytic value (the requirement for a modest mesh of 50
//    elements): the consistent flux of linear elements converges at O(h^2) with a constant of
//    order (phi h / L)^2 / 12 ~ 1e-4 here, so 0.5% is met with a wide margin and still catches a
//    flux read off a differentiated gradient (O(h), ~2% here) or a wrong face area.
//  * First-order profile: max nodal error <= 1e-3 S_s, about ten times the O((phi h/L)^2 / 12)
//    nodal error of linear elements with consistent reaction on this mesh (1.3e-4).
//  * First-order kinetics are Monod with K = 1e8 S_s: R = (k/K) S (1 - S/K + ...) differs from the
//    linear law by a relative 1e-8, far below every tolerance here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "scalar/scalar_test_support.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

constexpr double film_thickness = 2.0;    // mm
constexpr double column_width = 0.2;      // mm, in x and in z
constexpr double film_diffusivity = 0.1;  // mm^2/ms
constexpr double surface_value = 1.0;     // normalised concentration
constexpr int film_elements = 50;

Mesh film_mesh(int ny) {
  BoxSpec spec;
  spec.x1 = spec.z1 = column_width;
  spec.nx = spec.nz = 1;
  spec.blocks = {{"biofilm", 0.0, film_thickness, ny, 1.0}};
  return make_box_mesh(spec);
}

struct FilmResult {
  std::vector<double> phi;      // nodal values
  std::vector<double> y;        // nodal heights
  double flux = 0;              // consistent flux into the film per unit area
  double min_flux_density = 0;  // nodal densities on the top face
  double max_flux_density = 0;
  double s_min = 0;  // value at the wall y = 0
  double min_value = 0;
  NewtonResult newton;
};

// The film's settings: `base` with its diffusivity and Monod constants.
TransportSettings film_settings(double k, double K, TransportSettings base = {}) {
  base.coefficients.diffusivity[0] = film_diffusivity;
  base.coefficients.monod_rate[0] = k;
  base.coefficients.monod_half_saturation[0] = K;
  return base;
}

// S = S_s on the film's top, the only boundary condition.
std::vector<ScalarBoundaryCondition> surface_condition() {
  return {dirichlet("top", [](const Point&, double) { return surface_value; })};
}

FilmResult solve_film(double k, double K, const TransportSettings& base, int ny = film_elements) {
  const Mesh mesh = film_mesh(ny);
  TransportField field(mesh, film_settings(k, K, base), surface_condition());
  field.set_initial([](const Point&, double) { return surface_value; }, 0.0);
  FilmResult out;
  out.newton = field.solve_steady("1-D film");
  out.phi = field.solution_host();
  for (const auto& p : mesh.x) out.y.push_back(p[1]);
  const BoundaryFlux f = field.boundary_flux("top", -1);
  out.flux = f.total / (column_width * column_width);
  out.min_flux_density = *std::min_element(f.density.begin(), f.density.end());
  out.max_flux_density = *std::max_element(f.density.begin(), f.density.end());
  out.s_min = std::numeric_limits<double>::max();
  for (int n : mesh.node_sets.at("bottom")) out.s_min = std::min(out.s_min, out.phi[n]);
  out.min_value = *std::min_element(out.phi.begin(), out.phi.end());
  return out;
}

// J = sqrt(2 D k [(S_s - S_min) - K ln((K + S_s)/(K + S_min))]) (benchmarks.md, Monod).
double monod_first_integral_flux(double k, double K, double s_min) {
  return std::sqrt(2 * film_diffusivity * k *
                   ((surface_value - s_min) - K * std::log((K + surface_value) / (K + s_min))));
}

}  // namespace

TEST(ScalarTransport, FirstOrderBiofilmMatchesCoshProfileAndTanhFlux) {
  const double thiele = 2.0;
  const double k1 = thiele * thiele * film_diffusivity / (film_thickness * film_thickness);
  const double K = 1e8 * surface_value;  // first order: see the header
  const FilmResult r = solve_film(k1 * K, K, tight_settings());
  ASSERT_TRUE(r.newton.converged);

  double profile_error = 0;
  for (size_t n = 0; n < r.phi.size(); ++n) {
    const double exact =
        surface_value * std::cosh(thiele * r.y[n] / film_thickness) / std::cosh(thiele);
    profile_error = std::max(profile_error, std::abs(r.phi[n] - exact));
  }
  const double j_exact = k1 * film_thickness * surface_value * std::tanh(thiele) / thiele;
  std::printf(
      "[ measured ] first order, Thiele %.1f, %d elements: flux %.8e, exact %.8e, "
      "relative error %.2e; densities [%.8e, %.8e]; max nodal profile error %.2e\n",
      thiele, film_elements, r.flux, j_exact, r.flux / j_exact - 1, r.min_flux_density,
      r.max_flux_density, profile_error);
  EXPECT_NEAR(r.flux / j_exact, 1.0, 5e-3);
  EXPECT_NEAR(r.min_flux_density / j_exact, 1.0, 5e-3);
  EXPECT_NEAR(r.max_flux_density / j_exact, 1.0, 5e-3);
  EXPECT_LE(profile_error, 1e-3 * surface_value);
}

TEST(ScalarTransport, MonodBiofilmFluxMatchesExactFirstIntegral) {
  struct Case {
    const char* name;
    double k, K;
  };
  // Partial penetration (S_min ~ 0.3 S_s) and a film much thicker than the penetration depth
  // (S_min ~ 1e-3 S_s), both with saturation (S_s / K = 2 and 10).
  const Case cases[] = {{"partially penetrated", 0.05, 0.5}, {"deep", 0.6, 0.1}};
  for (const Case& c : cases) {
    const FilmResult r = solve_film(c.k, c.K, tight_settings());
    ASSERT_TRUE(r.newton.converged) << c.name;
    const double j_exact = monod_first_integral_flux(c.k, c.K, r.s_min);
    std::printf(
        "[ measured ] Monod %s (k %.3g, K %.3g), %d elements: S_min %.6e, flux %.8e, "
        "first integral %.8e, relative error %.2e\n",
        c.name, c.k, c.K, film_elements, r.s_min, r.flux, j_exact, r.flux / j_exact - 1);
    EXPECT_NEAR(r.flux / j_exact, 1.0, 5e-3) << c.name;
    EXPECT_NEAR(r.min_flux_density / j_exact, 1.0, 5e-3) << c.name;
    EXPECT_NEAR(r.max_flux_density / j_exact, 1.0, 5e-3) << c.name;
  }
}

// Penetration depth of the zero-order limit sqrt(2 D S_s / k) = L_f / 10: nine tenths of the film
// see (almost) no substrate. With K -> 0 the rate k S/(K + |S|) tends to k sign(S), a jump at
// S = 0 across which Newton has to find the front.
double deep_film_rate() {
  return 2 * film_diffusivity * surface_value / std::pow(0.1 * film_thickness, 2);
}

TEST(ScalarTransport, MonodWithVanishingHalfSaturationConvergesWithoutUndershoot) {
  // K from 1e-2 down to 1e-12 S_s, each steady solve starting from the previous one's solution
  // (continuation in K; the first from the uniform state S_s), with the library's default Newton
  // settings as a user would run them.
  const double k = deep_film_rate();
  const double j_zero_order = std::sqrt(2 * film_diffusivity * k * surface_value);
  const TransportSettings s;
  std::vector<double> previous;
  for (double K : {1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12}) {
    const Mesh mesh = film_mesh(film_elements);
    TransportField field(mesh, film_settings(k, K, s), surface_condition());
    field.set_initial([](const Point&, double) { return surface_value; }, 0.0);
    if (!previous.empty()) field.set_solution(previous);
    NewtonResult r;
    ASSERT_NO_THROW(r = field.solve_steady("1-D film, K continuation")) << "K = " << K;
    previous = field.solution_host();
    for (double v : previous) ASSERT_TRUE(std::isfinite(v)) << "K = " << K;
    const double min_value = *std::min_element(previous.begin(), previous.end());
    double s_min = std::numeric_limits<double>::max();
    for (int n : mesh.node_sets.at("bottom")) s_min = std::min(s_min, previous[n]);
    const double flux = field.boundary_flux("top", -1).total / (column_width * column_width);
    const double j_exact = monod_first_integral_flux(k, K, std::max(s_min, 0.0));
    std::printf(
        "[ measured ] K = %.0e: Newton %d iterations (%d Krylov), min phi %.3e S_s, "
        "S_min %.3e, flux %.6e, first integral %.6e (relative %.2e), zero order %.6e\n",
        K, r.iterations, r.krylov_iterations, min_value / surface_value, s_min, flux, j_exact,
        flux / j_exact - 1, j_zero_order);
    EXPECT_TRUE(r.converged) << "K = " << K;
    // The bound on the undershoot of a Q1 solution at a reaction front.
    EXPECT_GE(min_value, -0.01 * surface_value) << "K = " << K;
    // Same flux requirement as for the resolved Monod film above.
    EXPECT_NEAR(flux / j_exact, 1.0, 5e-3) << "K = " << K;
  }
}

// The same deep film as a run meets it, in time: 100 steps of 0.01 ms (the diffusion time
// L_f^2 / D is 40 ms) from the uniform state S_s:
// the deep film is consumed at the zero-order rate k and reaches S = 0 at t = S_s / k = 0.2 ms,
// where a front forms and moves up. Newton alone crosses it for K = 1e-4; for K <= 1e-8 the steps
// at the front need the field's continuation in K (TransportStats::continued_steps), and they must
// converge for K down to 1e-12 with the default settings. Checks, and why:
//  * no undershoot below -0.01 S_s: the bound (as in the steady tests);
//  * the solutions for K = 1e-8 and 1e-10 differ from K = 1e-12's by at most 10 K S_s: where
//    S >> K the rate differs from the zero-order one by O(K / S), and in the dead zone S itself is
//    O(K), so the K-dependence of the discrete solution is O(K) (measured: printed below);
//  * the substrate balance of every step not cut into sub-steps: the change of the amount equals
//    what entered through the top (the consistent boundary flux) less what was consumed, to 1e-9
//    of the step's consumption (measured ~1e-12: Newton's tolerance; a dropped or misplaced
//    reaction term at the front would show at the 1e-2 level).
TEST(ScalarTransport, MonodTimeStepsThroughAFormingFrontConvergeForKDownTo1e12) {
  const double k = deep_film_rate();
  std::vector<double> smallest_k;  // the solution for K = 1e-12
  for (double K : {1e-12, 1e-10, 1e-8, 1e-4}) {
    const Mesh mesh = film_mesh(film_elements);
    TransportSettings backward_euler;
    backward_euler.theta = 1.0;
    TransportField field(mesh, film_settings(k, K, backward_euler), surface_condition());
    field.set_initial([](const Point&, double) { return surface_value; }, 0.0);
    double worst_balance = 0;
    for (int i = 0; i < 100; ++i) {
      const double before = field.integral();
      const int cuts = field.stats().cut_steps;
      try {
        field.step(0.01, "step " + std::to_string(i));
      } catch (const SolveError& e) {
        FAIL() << "time step " << i << " (t = " << field.time() << " ms), K = " << K << ": "
               << e.what();
      }
      // Backward Euler: the step's flux and consumption at its end (a step cut into sub-steps
      // balances over its sub-steps, which the test does not see).
      if (field.stats().cut_steps != cuts) continue;
      const double consumed = 0.01 * field.reaction_integral();
      const double entered = 0.01 * field.boundary_flux("top", -1).total;
      worst_balance = std::max(worst_balance,
                               std::abs(field.integral() - before - entered + consumed) / consumed);
    }
    const std::vector<double> phi = field.solution_host();
    const double min_value = *std::min_element(phi.begin(), phi.end());
    double from_smallest_k = 0;
    if (smallest_k.empty()) smallest_k = phi;
    for (size_t n = 0; n < phi.size(); ++n)
      from_smallest_k = std::max(from_smallest_k, std::abs(phi[n] - smallest_k[n]));
    std::printf(
        "[ measured ] K = %.0e: %d steps solved by continuation in K, %d cut into "
        "sub-steps, %d Newton iterations, min phi %.3e S_s, largest difference from "
        "K = 1e-12 %.3e S_s, worst step balance %.2e\n",
        K, field.stats().continued_steps, field.stats().cut_steps, field.stats().newton_iterations,
        min_value / surface_value, from_smallest_k / surface_value, worst_balance);
    EXPECT_GE(min_value, -0.01 * surface_value) << "K = " << K;
    EXPECT_LT(worst_balance, 1e-9) << "K = " << K;
    if (K <= 1e-8) {
      EXPECT_GT(field.stats().continued_steps, 0) << "K = " << K;
      EXPECT_LE(from_smallest_k, 10 * K * surface_value) << "K = " << K;
    }
  }
}

// The same deep film's steady problem straight from the uniform state S_s, with the default
// settings. Newton (Armijo backtracking on ||r||, at most 20 halvings) has to cross the near-jump
// of width ~K of the rate at S = 0 and fails for small K; the field falls back to
// pseudo-transient continuation, whose pseudo-time steps fall back to continuation in K where
// Newton fails at the front (as the time steps above), down to K = 1e-12.
TEST(ScalarTransport, MonodWithVanishingHalfSaturationConvergesFromUniformState) {
  const double k = deep_film_rate();
  for (double K : {1e-4, 1e-8, 1e-10, 1e-12}) {
    FilmResult r;
    try {
      r = solve_film(k, K, TransportSettings{});
    } catch (const SolveError& e) {
      ADD_FAILURE() << "steady solve from S_s, K = " << K << ": " << e.what();
      continue;
    }
    const double j_exact = monod_first_integral_flux(k, K, std::max(r.s_min, 0.0));
    std::printf(
        "[ measured ] steady from S_s, K = %.0e: Newton %d iterations, min phi %.3e, "
        "flux relative to the first integral %.2e\n",
        K, r.newton.iterations, r.min_value, r.flux / j_exact - 1);
    EXPECT_GE(r.min_value, -0.01 * surface_value) << "K = " << K;
    // Same flux requirement as for the resolved Monod film above.
    EXPECT_NEAR(r.flux / j_exact, 1.0, 5e-3) << "K = " << K;
  }
}
