// The fluid field at the extremes (the list): the Stokes limit (Re 1e-3) and the steady
// laminar limit of the lid-driven cavity (Re 1000), tiny and huge time steps, and failures that
// must stop with a clear message and leave a finite state (never NaN). Aspect-ratio-100 elements:
// test_fluid_verification.cpp (Poiseuille).
//
// Tolerances, and why:
//  * huge dt (1e9) against the steady solution: 1e-6 relative, with theta = 1 (backward Euler):
//    the step then differs from the steady problem only by the storage term and the (2/dt)^2 in
//    tau, both O(1/dt) = 1e-9, plus the algebraic error (Newton to 1e-10 relative). With
//    theta < 1 the steady state is a fixed point of the scheme, but one step from rest is not the
//    steady state (the continuity and grad-div terms are not scaled by theta).
//  * tiny dt (1e-9): a step from rest moves the velocity by O(dt) = O(1e-9) away from the
//    boundary data; we check it stays below 1e-6 of the lid speed and is finite.
#include <gtest/gtest.h>

#include <limits>

#include "fluid/fluid_test_support.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

struct Cavity {
  Mesh mesh;
  std::vector<FluidBoundaryCondition> bcs;
  explicit Cavity(int n, FluidFunction lid = constant(1.0)) {
    mesh = box_mesh(n, 1, 0.05, {{"fluid", 0.0, 1.0, n, 1.0}});
    mesh.node_sets["pin"] = nodes_at(mesh, 0.5, 0.0);
    bcs = {fluid_no_slip("left"), fluid_no_slip("right"), fluid_no_slip("bottom"),
           fluid_velocity("top", std::move(lid), constant(0.0), constant(0.0)),
           fluid_pressure("pin", constant(0.0))};
  }
};

bool all_finite_host(const std::vector<double>& v) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

double max_abs_velocity(const std::vector<double>& s) {
  double m = 0;
  for (size_t i = 0; i < s.size(); ++i)
    if (i % 4 != 3) m = std::max(m, std::abs(s[i]));
  return m;
}

}  // namespace

TEST(FluidExtremes, StokesLimitConverges) {
  Cavity c(16);
  FluidSettings s = tight_fluid_settings(1.0, 1e3);  // Re = U L rho / mu = 1e-3
  s.newton_options.rel_tol = 1e-10;
  FluidField field(c.mesh, s, c.bcs);
  field.set_initial(nullptr, nullptr, 0.0);
  const NewtonResult r = field.solve_steady("Stokes limit");
  std::printf("[ measured ] cavity Re 1e-3: %d Newton iterations, %d Krylov\n", r.iterations,
              r.krylov_iterations);
  EXPECT_TRUE(r.converged);
  // Nearly linear: Newton needs no more than a few iterations.
  EXPECT_LE(r.iterations, 3);
  EXPECT_TRUE(all_finite_host(field.solution_host()));
}

TEST(FluidExtremes, LaminarLimitOfCavityConverges) {
  Cavity c(24);
  FluidSettings s = tight_fluid_settings(1.0, 1e-3);  // Re = 1000
  s.newton_options.rel_tol = 1e-10;
  FluidField field(c.mesh, s, c.bcs);
  field.set_initial(nullptr, nullptr, 0.0);
  const NewtonResult r = field.solve_steady("cavity Re 1000");
  std::printf(
      "[ measured ] cavity Re 1000: converged %d, %d Newton iterations (%d pseudo-time "
      "steps), %d Krylov\n",
      r.converged, field.stats().newton_iterations, field.stats().pseudo_steps,
      field.stats().krylov_iterations);
  EXPECT_TRUE(r.converged);
  EXPECT_TRUE(all_finite_host(field.solution_host()));
}

TEST(FluidExtremes, HugeTimeStepGivesTheSteadyVelocity) {
  Cavity c(12);
  FluidSettings s = tight_fluid_settings(1.0, 1e-2);  // Re = 100
  s.newton_options.rel_tol = 1e-10;
  s.theta = 1.0;
  FluidField steady(c.mesh, s, c.bcs);
  steady.set_initial(nullptr, nullptr, 0.0);
  ASSERT_TRUE(steady.solve_steady("steady").converged);
  FluidField stepped(c.mesh, s, c.bcs);
  stepped.set_initial(nullptr, nullptr, 0.0);
  ASSERT_TRUE(stepped.step(1e9, "huge step").converged);
  const auto a = steady.solution_host(), b = stepped.solution_host();
  double du = 0, dp = 0, pmax = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    if (i % 4 == 3) {
      dp = std::max(dp, std::abs(a[i] - b[i]));
      pmax = std::max(pmax, std::abs(a[i]));
    } else {
      du = std::max(du, std::abs(a[i] - b[i]));
    }
  }
  std::printf(
      "[ measured ] dt = 1e9 vs steady: max |du| = %.2e, max |dp| / |p| = "
      "%.2e\n",
      du, dp / pmax);
  EXPECT_LT(du, 1e-6);
  EXPECT_LT(dp / pmax, 1e-6);
}

TEST(FluidExtremes, TinyTimeStepStaysFiniteAndSmall) {
  Cavity c(12, [](const Point&, double t) { return std::min(t, 1.0); });  // lid starts at rest
  FluidSettings s = tight_fluid_settings(1.0, 1e-2);
  FluidField field(c.mesh, s, c.bcs);
  field.set_initial(nullptr, nullptr, 0.0);
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(field.step(1e-9, "tiny step").converged);
  const auto st = field.solution_host();
  std::printf("[ measured ] three steps of dt = 1e-9: max |u| = %.2e (lid %.1e)\n",
              max_abs_velocity(st), 3e-9);
  EXPECT_TRUE(all_finite_host(st));
  EXPECT_LT(max_abs_velocity(st), 1e-6);
}

TEST(FluidExtremes, FailuresStopWithAClearMessageAndAFiniteState) {
  // Boundary data that turn NaN: the solve must stop, name the field and the step, and keep the
  // last valid state.
  Cavity c(8, [](const Point&, double t) {
    return t > 0.5 ? std::numeric_limits<double>::quiet_NaN() : 1.0;
  });
  FluidSettings s = tight_fluid_settings(1.0, 1e-2);
  s.max_step_cuts = 1;
  FluidField field(c.mesh, s, c.bcs);
  field.set_initial(nullptr, nullptr, 0.0);
  ASSERT_TRUE(field.step(0.25, "step 1").converged);
  const auto before = field.solution_host();
  try {
    field.step(0.5, "step 2");
    FAIL() << "a NaN boundary value was accepted";
  } catch (const SolveError& e) {
    std::printf("[ measured ] message: %s\n", std::string(e.what()).substr(0, 160).c_str());
    EXPECT_EQ(e.field(), "fluid");
    EXPECT_NE(std::string(e.what()).find("step 2"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("NaN"), std::string::npos);
  }
  const auto after = field.solution_host();
  EXPECT_TRUE(all_finite_host(after));
  EXPECT_EQ(before, after);

  // A Newton budget too small to converge: "diverged", the state left finite.
  Cavity c2(8);
  FluidSettings s2 = tight_fluid_settings(1.0, 1e-3);
  s2.newton_options.max_iterations = 1;
  s2.max_step_cuts = 0;
  s2.pseudo_transient_steps = 0;
  FluidField f2(c2.mesh, s2, c2.bcs);
  f2.set_initial(nullptr, nullptr, 0.0);
  try {
    f2.solve_steady("budget");
    FAIL() << "an unconverged solve was accepted";
  } catch (const SolveError& e) {
    EXPECT_NE(std::string(e.what()).find("diverged"), std::string::npos);
  }
  EXPECT_TRUE(all_finite_host(f2.solution_host()));

  // Bad input is refused before any solve.
  FluidSettings bad = s;
  bad.viscosity = -1;
  EXPECT_THROW(FluidField(c.mesh, bad, c.bcs), std::invalid_argument);
  EXPECT_THROW(FluidField(c.mesh, s, {fluid_no_slip("no such set")}), std::invalid_argument);
  // Slip is for walls normal to a coordinate axis: a rotated wall is refused.
  Mesh rotated = c.mesh;
  distort(rotated, [](const Point& p) {
    return Point{0.98 * p[0] - 0.2 * p[1], 0.2 * p[0] + 0.98 * p[1], p[2]};
  });
  EXPECT_THROW(FluidField(rotated, s, {fluid_slip("left")}), std::invalid_argument);
  EXPECT_NO_THROW(FluidField(c.mesh, s, {fluid_slip("left")}));
}
