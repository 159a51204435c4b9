// DFG 2D-1 and Turek-Hron CFD1 (../shared/reference/benchmarks.md) on the Gmsh mesh family of
// cases/meshes (refine 2 here, in CI time); the refinement studies (refine 1, 2, 4) are in
// test_fluid_long (BIOFSI_FLUID_LONG, label long).
//
// The meshes are block-structured (transfinite patches, an O-grid ring round the cylinder).
// Measured (velocity strong threshold 0.7, SIMPLE), deviation from the reference:
//   DFG  refine 1 (3800 nodes):  drag +0.23%, lift -4.49%, dp +1.15%
//   DFG  refine 2 (14752 nodes): drag +0.05%, lift -1.14%, dp +0.69%
//   CFD1 refine 1 (5788 nodes):  drag +0.90%, lift +1.38%
//   CFD1 refine 2 (22360 nodes): drag +0.29%, lift +0.50%
//   DFG  refine 4 (58112 nodes): drag +0.01%, lift -0.27%, dp +0.37% (long; 256 s)
//   CFD1 refine 4 (87856 nodes): drag +0.11%, lift +0.21% (long; 744 s)
// (Unstructured meshes give lift +26% (DFG) and +7.8% (CFD1) at refine 2: lift is a small
// difference of large pressure forces, c_L / c_D ~ 2e-3 for DFG, and irregular cells at the
// cylinder dominate it.)
// Tolerances, and why: drag 1% and lift 5% are the requirements, asserted on the CI mesh
// and the finer ones. Delta p (DFG) within 2%: the issue asks for none; the band is twice the
// coarse-mesh error, to catch a pressure-scaling error.
#include <gtest/gtest.h>

#include "fluid/fluid_benchmarks.hpp"

using namespace biofsi;
using namespace biofsi::test;

#ifndef BIOFSI_FLUID_LONG

TEST(FluidBenchmarks, Dfg2d1DragAndLiftMatchReference) {
  const int refine = 2;
  const BenchmarkResult r = run_dfg(refine);
  print_benchmark("DFG 2D-1 c_D/c_L", refine, r, DfgReference::c_d, DfgReference::c_l);
  EXPECT_NEAR(r.drag, DfgReference::c_d, 0.01 * DfgReference::c_d);
  EXPECT_NEAR(r.lift, DfgReference::c_l, 0.05 * DfgReference::c_l);
  EXPECT_NEAR(r.dp, DfgReference::dp, 0.02 * DfgReference::dp);
}

TEST(FluidBenchmarks, TurekHronCfd1DragAndLiftMatchReference) {
  const int refine = 2;
  const BenchmarkResult r = run_cfd1(refine);
  print_benchmark("Turek-Hron CFD1 drag/lift [N/m]", refine, r, Cfd1Reference::drag,
                  Cfd1Reference::lift);
  EXPECT_NEAR(r.drag, Cfd1Reference::drag, 0.01 * Cfd1Reference::drag);
  EXPECT_NEAR(r.lift, Cfd1Reference::lift, 0.05 * Cfd1Reference::lift);
}

#else

TEST(FluidBenchmarks, Dfg2d1RefinementStudy) {
  for (int refine : {1, 2, 4}) {
    const BenchmarkResult r = run_dfg(refine);
    print_benchmark("DFG 2D-1 c_D/c_L", refine, r, DfgReference::c_d, DfgReference::c_l);
    if (refine >= 2) {
      EXPECT_NEAR(r.drag, DfgReference::c_d, 0.01 * DfgReference::c_d);
      EXPECT_NEAR(r.lift, DfgReference::c_l, 0.05 * DfgReference::c_l);
    }
  }
}

TEST(FluidBenchmarks, TurekHronCfd1RefinementStudy) {
  for (int refine : {1, 2, 4}) {
    const BenchmarkResult r = run_cfd1(refine);
    print_benchmark("Turek-Hron CFD1 drag/lift [N/m]", refine, r, Cfd1Reference::drag,
                    Cfd1Reference::lift);
    if (refine >= 2) {
      EXPECT_NEAR(r.drag, Cfd1Reference::drag, 0.01 * Cfd1Reference::drag);
      EXPECT_NEAR(r.lift, Cfd1Reference::lift, 0.05 * Cfd1Reference::lift);
    }
  }
}

#endif
