// Diagnostics, disabled by default (run with --gtest_also_run_disabled_tests): the steady
// manufactured-solution solve at one size with a chosen preconditioner (env N, SIMPLE=0/1, BF=1
// for a body force), and DFG 2D-1 at one refinement with a chosen preconditioner and grad-div
// switch (env R = 1/2/4, PC = 0 monolithic AMG / 1 SIMPLE / 2 SIMPLEC, NOGD=1: no grad-div,
// LIN = 0 full / 1 lagged tau / 2 Picard), as
// used for the preconditioner and stabilisation measurements in the fluid report.
#include <gtest/gtest.h>

#include <chrono>

#include "fluid/fluid_test_support.hpp"

using namespace biofsi;
using namespace biofsi::test;

TEST(FluidScratch, DISABLED_Diagnose) {
  const int n = std::getenv("N") ? std::atoi(std::getenv("N")) : 8;
  const bool simple = std::getenv("SIMPLE") && std::atoi(std::getenv("SIMPLE"));
  Mesh mesh = box_mesh(n, 1, 0.1, {{"fluid", 0.0, 1.0, n, 1.0}});
  distort_smoothly(mesh);
  mesh.node_sets["pin"] = nodes_at(mesh, 0.0, 0.0);
  FluidSettings s = tight_fluid_settings(1.0, 0.05);
  s.preconditioner = simple ? FluidPreconditioner::Simple : FluidPreconditioner::MonolithicAmg;
  s.newton_options.krylov.max_iterations = 300;
  s.newton_options.max_iterations = 8;
  s.pseudo_transient_steps = 0;
  const FluidFunction ux = [](const Point& x, double) {
    return std::sin(pi * x[0]) * std::cos(pi * x[1]);
  };
  const FluidFunction uy = [](const Point& x, double) {
    return -std::cos(pi * x[0]) * std::sin(pi * x[1]);
  };
  const auto bcs = driven_walls(ux, uy, constant(0.0));
  FluidField field(mesh, s, bcs);
  field.set_initial(nullptr, nullptr, 0.0);
  if (std::getenv("BF"))
    field.set_body_force([](const Point& x, double) {
      return Point{std::cos(pi * x[0] + 0.5) * std::cos(pi * x[1]) * pi,
                   -pi * std::sin(pi * x[0] + 0.5) * std::sin(pi * x[1]), 0.0};
    });
  try {
    const NewtonResult r = field.solve_steady("diag");
    std::printf("converged %d iterations %d krylov %d\n", r.converged, r.iterations,
                r.krylov_iterations);
    for (double v : r.residual_history) std::printf(" %.2e", v);
    std::printf("\n");
  } catch (const std::exception& e) {
    std::printf("error: %s\n", e.what());
  }
}

#include "fluid/fluid_benchmarks.hpp"

TEST(FluidScratch, DISABLED_Dfg) {
  const int refine = std::getenv("R") ? std::atoi(std::getenv("R")) : 2;
  const int pc = std::getenv("PC") ? std::atoi(std::getenv("PC")) : 1;
  const bool gd = !std::getenv("NOGD");
  const int lin = std::getenv("LIN") ? std::atoi(std::getenv("LIN")) : 0;
  const BenchmarkResult r =
      run_dfg(refine, static_cast<FluidPreconditioner>(pc), [gd, lin](FluidSettings& s) {
        s.grad_div = gd;
        s.linearisation = static_cast<FluidLinearisation>(lin);
        s.newton_options.max_iterations = 60;
      });
  print_benchmark("DFG", refine, r, DfgReference::c_d, DfgReference::c_l);
}
