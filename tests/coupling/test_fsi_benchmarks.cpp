// Turek & Hron (2006) FSI1 (../shared/reference/benchmarks.md): the steady coupled problem of the
// elastic flag behind the cylinder at Re 20, on the Gmsh mesh family of cases/meshes/turek_hron.geo
// (fsi_benchmarks.hpp). CI runs refine 2 (the CI mesh); test_fsi_long (BIOFSI_FSI_LONG, label
// long) runs the refinement study, refine 1 and 2.
//
// Measured (shape derivatives on, inner block tolerance 3e-4), deviation from the reference:
//   refine 1 (6076 nodes):  u_x(A) +3.31%, u_y(A) -2.90%, drag +0.89%, lift +3.23%;
//                           7 Newton (quadratic), 45 outer FGMRES iterations
//                           (3 6 6 6 13 8 3), 53 s on 1 thread (fluid block SIMPLE)
//   refine 2 (23704 nodes): u_x(A) +1.16%, u_y(A) -0.51%, drag +0.28%, lift +0.94%;
//                           7 Newton, 34 outer FGMRES (1 3 3 4 6 12 5), 40 s on 2 threads with
//                           the fluid block's sparse LU (run_fsi1; SIMPLE: 141 s, the same
//                           results; at the scenes' inner tolerance 1e-2 SIMPLE took 313 outer
//                           iterations and 1191 s; FsiSettings::inner_tolerance has the table).
// Tolerances, and why: the 2% for every quantity, on the CI mesh. Refine 1 (4 elements
// through the flag) is not fine enough for 2%: u_x and lift are 3.3% off. Cheaper CI meshes
// measured: refine 1 with only the flag (and the fluid rows along it) at refine 2, 9348 nodes:
// u_y -0.45% but u_x +3.59%, drag +0.98%, lift +2.18%; and refine 1 with one family of
// divisions raised at a time (the .geo's c_* overrides, 1 thread):
//   c_flag 60 (7156 nodes): u_x +3.33%, u_y -2.40%, drag +0.91%, lift +3.07%, 98 s
//   c_side 9  (7264 nodes): u_x +2.62%, u_y -2.08%, drag +0.78%, lift +3.32%, 190 s
//   c_ring 12 (6444 nodes): u_x +3.37%, u_y -2.44%, drag +0.79%, lift +2.85%, 70 s
// No single region carries the error, so CI pays for refine 2. The long study asserts that every
// error shrinks from refine 1 to 2.
#include <gtest/gtest.h>

#include <cmath>

#include "coupling/fsi_benchmarks.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

double relative_error(double value, double reference) {
  return std::abs(value - reference) / std::abs(reference);
}

struct Errors {
  double ux, uy, drag, lift;
};

Errors errors_of(const FsiBenchmarkResult& r) {
  using R = Fsi1Reference;
  return {relative_error(r.ux, R::ux), relative_error(r.uy, R::uy), relative_error(r.drag, R::drag),
          relative_error(r.lift, R::lift)};
}

}  // namespace

#ifndef BIOFSI_FSI_LONG

TEST(FsiBenchmarks, TurekHronFsi1OnTheCiMesh) {
  const FsiBenchmarkResult r = run_fsi1("turek_hron_r2");
  print_fsi1("turek_hron_r2", r);
  const Errors e = errors_of(r);
  EXPECT_LT(e.ux, 0.02);
  EXPECT_LT(e.uy, 0.02);
  EXPECT_LT(e.drag, 0.02);
  EXPECT_LT(e.lift, 0.02);
  // Newton on the exact Jacobian: measured 7 iterations from rest.
  EXPECT_LE(r.newton, 10);
}

#else

TEST(FsiBenchmarksLong, TurekHronFsi1RefinementStudy) {
  const FsiBenchmarkResult r1 = run_fsi1("turek_hron_r1");
  print_fsi1("turek_hron_r1", r1);
  const FsiBenchmarkResult r2 = run_fsi1("turek_hron_r2");
  print_fsi1("turek_hron_r2", r2);
  const Errors e1 = errors_of(r1), e2 = errors_of(r2);
  // The 2% on the finer mesh, and every error shrinking with h.
  EXPECT_LT(e2.ux, 0.02);
  EXPECT_LT(e2.uy, 0.02);
  EXPECT_LT(e2.drag, 0.02);
  EXPECT_LT(e2.lift, 0.02);
  EXPECT_LT(e2.ux, e1.ux);
  EXPECT_LT(e2.uy, e1.uy);
  EXPECT_LT(e2.drag, e1.drag);
  EXPECT_LT(e2.lift, e1.lift);
}

#endif
