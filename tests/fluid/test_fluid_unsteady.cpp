// Vortex shedding behind a rigid body, fluid alone, in time: Turek & Hron (2006) CFD3 (the CFD1
// channel of fluid_benchmarks.hpp, cylinder and flag held rigid, U_mean = 2, Re = 200) and
// Schaefer & Turek (1996) DFG 2D-2 (the 2D-1 channel, cylinder only, U_mean = 1, Re = 100).
// References, mean +- amplitude [frequency] per unit depth:
//   CFD3 (Turek & Hron 2006, finest level): drag 439.45 +- 5.6183 N/m [8.7912 Hz, twice the
//        shedding frequency], lift -11.893 +- 437.81 N/m [4.3956 Hz].
//   DFG 2D-2 (Schaefer & Turek 1996, the bounds of the participants' converged results): c_L max
//        0.99-1.01 (taken as amplitude 1.0), Strouhal number 0.295-0.305 (f = St U_mean / D =
//        3.0 Hz), c_D max 3.22-3.24.
//
// Why they are here: FSI2 and FSI3 (tests/coupling/test_fsi_unsteady.cpp) are driven by this
// shedding; these measure the fluid's share of their errors on the same meshes, without the
// flag's motion (CSM3, tests/structure/test_csm3.cpp, measures the flag's share).
//
// The scenes: cases/turek_hron/cfd3.yaml and cases/dfg/dfg_2d2.yaml, run through the driver; the
// forces on the body are read from their series.csv. The start: the inflow is ramped over 0.5 s
// (the benchmark's 2 s is not needed for a periodic state), and a transverse pulse of body force
// (CFD3 30, DFG 5 m/s^2 peak, sin^2 over 0.1 s after the ramp, on the fluid behind the body)
// breaks the near-symmetry from which shedding would otherwise grow out of round-off (on refine 1
// a 2 m/s^2 pulse left CFD3's oscillation at +-4 at t = 4 s).
//
// Tolerances, and why: the DFG participants' converged results spread by +-1.7% in St and +-1% in
// c_L max; a Q1 mesh of a few thousand nodes is allowed about twice that in frequency (3%) and ten
// times in lift amplitude (10%); and the state must be periodic (lift amplitude change < 3% over
// the last period), not still growing.
//
// Measured (one thread, dt 0.01, theta 0.5, the midpoint form of kernels/fluid/pointwise.hpp):
//   DFG 2D-2 refine 1 (2 min): c_L +-1.028 (+2.8%), St -2.45%, c_D max 3.2224 (-0.24%),
//     amplitude change 0.01%: passes.
//   CFD3 on turek_hron_wake (refine 1's body with a finer wake: gmsh -setnumber c_side 12
//     -setnumber g_side 1.1 -setnumber c_wake 100 -setnumber c_wall 8; to t = 5 s, 42 min): lift
//     -22.4 +- 395.7 (-9.6%) at 4.355 Hz (-0.9%), amplitude change -1.3%, drag mean +1.6%:
//     passes, with little room in the lift amplitude.
//   CFD3 on turek_hron_flag (the wake mesh with refine 2's flag; 45 min): lift -21.4 +- 405.4
//     (-7.4%) at 4.349 Hz (-1.1%), drag mean +1.6%: passes.
//   CFD3 on turek_hron_flag with the body's region doubled (its gmsh arguments plus -setnumber
//     c_box 20 -setnumber c_ring 16: the cylinder's O-grid and the patches beside it; 10868 nodes
//     per layer; 58 min): lift -19.8 +- 385.7 (-11.9%) at 4.332 Hz (-1.4%), drag mean 439.1
//     (-0.1%), amplitude change -1.2%: the lift amplitude fails.
//   CFD3 on turek_hron_wake with dt 0.0025 (FSI3's measuring step; 90 min) to
//     t = 5 s: lift -23.8 +- 376.7 (-14.0%) at 4.373 Hz (-0.5%), amplitude change -1.2%, drag
//     mean 439.4 (-0.01%): fails on the lift. The midpoint rule is second order, so dt 0.0025
//     leaves ~1/16 of dt 0.01's time error: on this mesh the shedding is ~14% weak in space, and
//     part of dt 0.01's pass is its time error.
//   CFD3 on refine 1 (to t = 10 s, 10 min): lift
//     -44 +- 141 (-68%) at 4.10 Hz (-6.8%), still growing 2.1% a period at t = 10 s: refine 1's
//     wake is too coarse for CFD3's shedding, and with it for FSI3's flow, so CFD3 runs on the
//     wake mesh.
//   So on meshes of 7-11 thousand nodes per layer the shedding is 7-14% weak, and refining one
//   region does not move it monotonically toward the reference.
// These were measured on the same meshes, steps and pulses with the fluid's Newton at 1e-8
// relative; the scenes use the field's default, 1e-10. Studies of mesh, step and
// theta run the scene with --set (mesh.parameters.*, time.dt, time.steps, time.theta) and
// analyse its series the same way.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "coupling/oscillation.hpp"
#include "scene_run.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

struct SheddingCase {
  const char* name = "";
  std::string scene;  // under cases/
  std::string body;   // the force boundary of the body
  double thickness = 0.05;
  double force_scale = 1;  // forces per unit depth -> the reported quantity (1, or 2/(rho U^2 D))
  Reference lift{}, drag{};
  double drag_max = 0;  // DFG reports the maximum of c_D instead of mean and amplitude (0: none)
};

SheddingCase cfd3() {
  SheddingCase c;
  c.name = "CFD3";
  c.scene = "turek_hron/cfd3.yaml";
  c.body = "body";  // the cylinder and the flag, their shared corners once
  c.lift = {-11.893, 437.81, 4.3956};
  c.drag = {439.45, 5.6183, 8.7912};
  return c;
}

SheddingCase dfg2d2() {
  SheddingCase c;
  c.name = "DFG 2D-2";
  c.scene = "dfg/dfg_2d2.yaml";
  c.body = "cylinder";
  // Lift and drag as c_L, c_D = 2 F / (rho U_mean^2 D); the drag oscillates at twice the
  // shedding frequency, its mean is not published.
  c.force_scale = 2 / (1.0 * 1.0 * 1.0 * 0.1);
  c.lift = {0.0, 1.0, 3.0};
  c.drag = {0.0, 0.0, 6.0};
  c.drag_max = 3.23;
  return c;
}

void check_shedding(const SheddingCase& c) {
  const auto out = scratch_dir("shedding_" + c.body);
  const RunOutput r = run_quietly(case_run(c.scene, out));
  ASSERT_EQ(r.rc, 0) << r.err << r.out;
  auto s = read_series(out / "series.csv");
  std::vector<double> drag, lift;
  for (size_t i = 0; i < s["time"].size(); ++i) {
    drag.push_back(c.force_scale * s["force_" + c.body + "_x"][i] / c.thickness);
    lift.push_back(c.force_scale * s["force_" + c.body + "_y"][i] / c.thickness);
  }
  const std::vector<double>& t = s["time"];
  const double window = t.back() - 1.0;
  const Oscillation d = analyse(t, drag, window, 8), l = analyse(t, lift, window, 4);
  std::printf("[ measured ] %s (cases/%s) to t = %g:\n", c.name, c.scene.c_str(), t.back());
  report_against("drag", d, c.drag);
  report_against("lift", l, c.lift);
  EXPECT_LT(std::abs(l.amplitude_change), 0.03);  // a periodic state, not a growing one
  EXPECT_NEAR(l.frequency, c.lift.frequency, 0.03 * c.lift.frequency);
  EXPECT_NEAR(l.amplitude, c.lift.amplitude, 0.10 * c.lift.amplitude);
  if (c.drag_max > 0) {
    const double drag_max = d.mean + d.amplitude;
    std::printf("[ measured ] drag maximum %.4f (%+.2f%%; reference 3.22-3.24)\n", drag_max,
                percent_off(drag_max, c.drag_max));
    EXPECT_NEAR(drag_max, c.drag_max, 0.01 * c.drag_max);  // twice the participants' spread
  }
}

}  // namespace

TEST(FluidUnsteadyLong, TurekHronCfd3) { check_shedding(cfd3()); }

TEST(FluidUnsteadyLong, Dfg2d2) { check_shedding(dfg2d2()); }
