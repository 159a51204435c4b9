// Turek & Hron (2006) CSM3: cases/turek_hron/csm3.yaml — the CSM1 flag (test_csm1.cpp) released
// under gravity 2 m/s^2 at t = 0 and left to swing, undamped — run through the driver, and the
// tip's series (series.csv) analysed. Reference (the benchmark's finest level, dt = 0.005), mean
// +- amplitude [frequency] of the tip point A: u_x = -14.305e-3 +- 14.305e-3 m [1.0995 Hz],
// u_y = -63.607e-3 +- 65.160e-3 m [1.0995 Hz].
//
// Why it is here: FSI2 and FSI3 (tests/coupling/test_fsi_unsteady.cpp) depend on the flag's
// stiffness and inertia; CSM3 measures the structure's share of their error (its mesh and its
// time integrator) without the fluid.
//
// Tolerances, and why: Q1 overestimates the bending stiffness at O(h^2) (CSM1: u_y -7.9% at refine
// 1, -2.1% at refine 2), which raises the frequency by about half that and lowers the amplitude by
// about it; the trapezoidal rule's period error (w dt)^2 / 12 is 0.1% at dt = 0.005. So on the
// scene's refine 2 (label long): frequency within 2%, u_y amplitude and mean within 4%; the
// measured numbers are printed for the record. Studies of mesh and step run the scene with --set
// (mesh.parameters.refine, time.dt, time.steps) and analyse its series the same way.
//
// Measured (dt 0.005, 1000 steps; ~35 s at refine 1, ~2.5 min at refine 2 on 2 threads):
//   refine 1: u_y -6.00e-2 +- 6.00e-2 [1.139 Hz] (mean -5.6%, amplitude -7.9%, frequency +3.6%)
//   refine 2: u_y -6.33e-2 +- 6.36e-2 [1.106 Hz] (mean -0.4%, amplitude -2.4%, frequency +0.6%),
//             u_x amplitude -2.2%, frequency +0.6%
// So the structure alone errs on the stiff, fast side at refine 1; FSI3's mesh (turek_hron_flag)
// therefore carries refine 2's flag.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "coupling/oscillation.hpp"
#include "scene_run.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

constexpr Reference ref_ux{-14.305e-3, 14.305e-3, 1.0995}, ref_uy{-63.607e-3, 65.160e-3, 1.0995};

}  // namespace

TEST(StructureCsm3Long, TipOscillationMatchesTurekHron) {
  const auto out = scratch_dir("csm3");
  const RunOutput r = run_quietly(case_run("turek_hron/csm3.yaml", out));
  ASSERT_EQ(r.rc, 0) << r.err << r.out;
  auto s = read_series(out / "series.csv");
  ASSERT_EQ(s["time"].size(), 1001u);  // steps 0 to 1000
  EXPECT_NEAR(s["time"].back(), 5.0, 1e-9);
  // Undamped from rest: every period is the same, so the last four of five seconds are measured.
  const Oscillation ux = analyse(s["time"], s["A_displacement_x"], 1.0, 4),
                    uy = analyse(s["time"], s["A_displacement_y"], 1.0, 4);
  std::printf("[ measured ] CSM3 (cases/turek_hron/csm3.yaml):\n");
  report_against("CSM3 u_x(A)", ux, ref_ux);
  report_against("CSM3 u_y(A)", uy, ref_uy);
  EXPECT_NEAR(uy.frequency, ref_uy.frequency, 0.02 * ref_uy.frequency);
  EXPECT_NEAR(uy.amplitude, ref_uy.amplitude, 0.04 * ref_uy.amplitude);
  EXPECT_NEAR(uy.mean, ref_uy.mean, 0.04 * std::abs(ref_uy.mean));
  EXPECT_NEAR(ux.frequency, ref_ux.frequency, 0.02 * ref_ux.frequency);
}
