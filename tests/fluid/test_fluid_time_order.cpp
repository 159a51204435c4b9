// Temporal order of the fluid's one-step-theta (src/fluid, kernels/fluid) on a fixed and on a
// moving (ALE) mesh, by self-convergence: one 16 x 16 mesh and one set of data run with 10, 20,
// 40 and 80 steps to t = 0.4, the order read from the max-norm velocity differences of successive
// runs. The flow: the unit square driven through its walls by the Taylor-Green velocity scaled by
// sin(2 pi t / 0.8), nu = 0.01 (Re ~ 100, element Peclet ~ 3: SUPG, PSPG and grad-div active);
// the moving mesh's interior swings by up to 8% of the box, its walls stay put.
//
// What it measured (stop 16; the differences 10 -> 20, 20 -> 40, 40 -> 80 steps, the order of the
// last two):
//   steady tau_M (FluidSettings::transient_tau = false):
//     theta 1,   fixed  1.89e-2 9.60e-3 4.84e-3, order 0.99;  moving 2.48e-2 1.21e-2 5.95e-3, 1.02
//     theta 0.5, fixed  1.66e-3 5.89e-4 2.70e-4, order 1.12;  moving 3.30e-3 2.11e-3 1.16e-3, 0.86
//     (with 160 steps more: 1.07 and 0.93)
//   transient tau_M (the default), theta 0.5 fixed: 2.26e-3 4.07e-3 4.84e-3 4.68e-3 (no
//     convergence); theta 1: orders 0.86, 0.88, 0.51.
// So Crank-Nicolson is not second order here: first order with a constant 20x (fixed mesh) and
// 5x (moving) below backward Euler's. With nu = 0.1 the same (orders 1.87, 1.68, 1.34, 1.07,
// 1.03 from 20 to 640 steps; also without SUPG and grad-div), so the first-order term is not SUPG's
// and not the mesh motion's. PSPG's time levels (momentum residual at t_{n+theta}, the continuity
// it stabilises at t_{n+1}) are part of it at most: continuity at t_{n+theta} as well gave
// 1.70e-3 3.88e-4 1.62e-4 (orders 2.13, 1.26) on the fixed mesh (tried, not kept). With the
// transient tau_M, whose (2/dt)^2 term makes the stabilised operator itself depend on dt, the
// differences do not fall at all over dt = 0.04 ... 0.0025: a time-step study of a
// convection-dominated flow with the default settings measures that operator's change as much as
// the time error (README, "Known limits").
//
// Tolerances, and why: backward Euler's order within 0.15 of 1 (the order tolerance);
// theta 0.5 at least 0.7 (first order; the moving mesh's 0.86 is still on its way to 0.93) and its
// difference at most 0.3 of backward Euler's (measured 0.05 and 0.19), so a change that costs
// Crank-Nicolson its accuracy fails here. Newton to 1e-12 relative: algebraic errors ~1e-12 are
// far below the 1e-4 differences measured.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "fluid/fluid_test_support.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

constexpr double t_end = 0.4, viscosity = 0.01, swing = 0.08;

// Zero at t = 0, so the fluid at rest is a consistent start.
double wall_speed(double t) { return std::sin(2 * pi * t / 0.8); }

Point moved(const Point& X, double t, double amplitude) {
  const double a = amplitude * std::sin(2 * pi * t / 0.5);
  const double sy = std::sin(pi * X[1]);
  return {X[0] + a * std::sin(pi * X[0]) * sy, X[1] + 0.5 * a * std::sin(2 * pi * X[0]) * sy, X[2]};
}

struct Variant {
  double theta;
  bool moving, transient_tau;
};

std::vector<double> solve(const Variant& v, int steps) {
  Mesh reference = box_mesh(16, 1, 0.1, {{"fluid", 0.0, 1.0, 16, 1.0}});
  reference.node_sets["pin"] = nodes_at(reference, 0.0, 0.0);
  FluidSettings s = tight_fluid_settings(1.0, viscosity);
  s.theta = v.theta;
  s.transient_tau = v.transient_tau;
  const FluidFunction ux = [](const Point& x, double t) {
    return wall_speed(t) * std::sin(pi * x[0]) * std::cos(pi * x[1]);
  };
  const FluidFunction uy = [](const Point& x, double t) {
    return -wall_speed(t) * std::cos(pi * x[0]) * std::sin(pi * x[1]);
  };
  const auto bcs = driven_walls(ux, uy, constant(0.0));
  FluidField field(reference, s, bcs);
  field.set_initial(nullptr, nullptr, 0.0);
  const double dt = t_end / steps;
  Mesh mesh = reference;
  for (int i = 0; i < steps; ++i) {
    if (v.moving) {
      for (int k = 0; k < mesh.n_nodes(); ++k)
        mesh.x[k] = moved(reference.x[k], (i + 1) * dt, swing);
      field.update_coordinates(mesh, dt);
    }
    EXPECT_TRUE(field.step(dt, "step " + std::to_string(i)).converged);
  }
  return field.solution_host();
}

double velocity_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0;
  for (size_t i = 0; i < a.size(); i += 4)
    for (int c = 0; c < 2; ++c) d = std::max(d, std::abs(a[i + c] - b[i + c]));
  return d;
}

struct Study {
  double finest = 0, order = 0;  // the last difference and the order of the last pair
};

Study study(const Variant& v) {
  std::vector<double> previous = solve(v, 10), differences;
  for (int steps : {20, 40, 80}) {
    const std::vector<double> next = solve(v, steps);
    differences.push_back(velocity_difference(previous, next));
    previous = next;
  }
  Study s;
  s.finest = differences.back();
  s.order = std::log2(differences[differences.size() - 2] / differences.back());
  std::printf(
      "[ measured ] theta %.1f, %s mesh, %s tau_M: differences %.2e %.2e %.2e, order %.2f\n",
      v.theta, v.moving ? "moving" : "fixed", v.transient_tau ? "transient" : "steady",
      differences[0], differences[1], differences[2], s.order);
  return s;
}

void check_orders(bool moving) {
  const Study euler = study({1.0, moving, false});
  const Study crank_nicolson = study({0.5, moving, false});
  EXPECT_NEAR(euler.order, 1.0, 0.15);
  EXPECT_GE(crank_nicolson.order, 0.7);
  EXPECT_LT(crank_nicolson.finest, 0.3 * euler.finest);
}

}  // namespace

TEST(FluidTimeOrder, OneStepThetaOnFixedMesh) { check_orders(false); }

TEST(FluidTimeOrder, OneStepThetaOnMovingMesh) { check_orders(true); }
