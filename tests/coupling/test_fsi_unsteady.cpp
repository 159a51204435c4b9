// Turek & Hron (2006) FSI2 and FSI3: cases/turek_hron/fsi2.yaml and fsi3.yaml, the elastic flag
// behind the cylinder oscillating in the flow it sheds, run through the driver from rest to a
// periodic state; their series.csv (the tip A's displacement, the forces on the cylinder, the flag
// and both) is compared with the benchmark's mean, amplitude and frequency of u_x(A), u_y(A), drag
// and lift. Label long: on the development machine FSI2 takes ~3 h on 2 threads (440 steps on
// turek_hron_wake, the refine-1 body with a finer wake on which CFD3 passes) and FSI3 ~9 h on one
// thread (490 steps, 35-110 s a step on turek_hron_flag, that mesh with refine 2's flag).
//
// Each scene runs in time stages: a start-up with a large step (and for FSI2 theta 0.52, which
// damps the swing but survives its growth), then the periodic state measured with Crank-Nicolson
// and a smaller step, each stage continuing from the state the last reached. Studies of mesh,
// step and tolerances run the scenes with --set and analyse their series the same way.
//
// Measured with the default stages from rest (docs/validation.md has the full tables):
//   FSI2 to t = 6.6 s (no cut step): u_y(A) amplitude -3.4%, lift -6.2%, drag amplitude -6.6%,
//   the rest within 5.3% (fsi2() lists everything).
//   FSI3 to t = 3.4 s (no cut step), against the benchmark authors' finest row (fsi3() gives the
//   source): u_y(A) amplitude -1.1% at -2.3% frequency, u_x(A) mean -0.7% and amplitude -3.6%,
//   drag 460.2 +- 26.9 (mean -0.06%, amplitude -3.1%), lift +-159.8 (+3.8%), all frequencies
//   within 2.3%. Against the 2006 proposal's summary row, reported beside it, the drag amplitude
//   is +18.6% and the lift +6.7%: that row's drag amplitude, 22.66, is 18% below the finer row's
//   27.74. The drag amplitude is not mesh-converged: the t = 3.4 s state moved onto the 1.5x
//   refinement of turek_hron_flag (43086 nodes) and run to t = 3.69 s (~1.3 swings after the
//   transfer) gives u_y(A) 1.42e-3 +- 3.521e-2 at 5.48 Hz, u_x(A) +-2.71e-3 and lift +-155.6, all
//   within ~1% of the finer row, but drag 426.6-491.0 (+-32.2, +16%) (docs/known-limits.md).
//
// Why FSI3 runs on turek_hron_flag: refine 1's flag is too stiff (CSM3 on it: frequency +3.6%,
// amplitude -7.9%; on refine 2's flag +0.6%, -2.4%), and with refine 2's flag the lift per unit
// swing is 11-13% lower than on turek_hron_wake, where the same stages give lift +-173 (the finer
// row: 153.91); the drag's 10.8 Hz oscillation is the same on both meshes (+-27, of which +-25 on
// the flag). An FSI3 step costs ~2.1x the wake mesh's. The lift is an interference sum: the
// flag's part leads u_y(A) by ~150 degrees (inertia-dominated, as a flag driven at 5.4 Hz, above
// its in-vacuo first mode at ~2 Hz, must be), the cylinder's by 30-45, so a 15-degree phase error
// of the shedding against the swing moves the total by ~30 N/m. The fluid alone on these meshes
// sheds 7-14% weak (tests/fluid/test_fluid_unsteady.cpp).
//
// How the numbers are taken: as the benchmark does, over the last full period of each signal
// (oscillation.hpp, tested in the default suite).
//
// Neither case can pass on refine 1 (turek_hron_r1), where the fluid alone does not shed as the
// benchmark does (CFD3's lift amplitude is a third of the reference's there).
//
// The start differs from the benchmark's on purpose: the inflow is ramped over 0.5 s instead
// of 2, to reach the periodic state in fewer steps; the periodic state does not
// depend on how it was reached. For the same reason FSI2's flag gets a transverse push when the
// ramp ends (a body force rho_s a(t) on the flag, a(t) = kick sin^2(pi (t - t0) / 0.25 s) for a
// quarter second, half the expected period): from rest its swing would have to grow out of
// round-off, and the unseeded run would spend most of its steps reaching the state the benchmark
// measures. Estimated effect of 4 m/s^2 (impulse over flag plus broadside added mass, at 2 Hz): a
// tip swing of ~0.015, which then grows to the periodic +-0.078.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "coupling/oscillation.hpp"
#include "scene_run.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

// A published result: mean +- amplitude [frequency] of each quantity the benchmark reports.
struct BenchmarkRow {
  Reference ux, uy, drag, lift;
};

struct UnsteadyCase {
  int number;  // 2 or 3
  // The row the test checks (each case says which), and Turek & Hron (2006)'s summary row where
  // that is not the checked one: reported beside it.
  BenchmarkRow reference;
  std::optional<BenchmarkRow> row_2006;
};

UnsteadyCase fsi2() {
  UnsteadyCase c;
  c.number = 2;
  // The scene's start-up: the ramp, the push and the growth of the swing with theta a little above
  // Crank-Nicolson and 25 steps per lift period; from t = 4.4 s Crank-Nicolson with 50 steps per
  // period, the periodic state that is measured. Why not 0.5 throughout: with dt 0.02 it cuts
  // steps at the extreme swings (in 10 of 21 steps, the lift jumping by ~100 from step to step).
  // Why not 0.52 throughout: it damps the periodic swing (u_y(A) by ~18%, the lift by ~25%). The
  // fluid mesh's stiffening is 3 from rest: with 2 the fluid cell beside the tip inverts at the
  // extreme swing (t ~ 3.14 s: minimum scaled Jacobian 0.59, 0.30, 0.06 over the three steps
  // before, then no line-search step without an inverted element); with 3 the first step from
  // rest takes 3 Newton and 20 Krylov iterations, as with 2.
  // Measured (these stages from rest, 440 steps, no cut step, 22-24 s a step on 2 threads): the
  // fluid mesh's smallest scaled Jacobian 0.308 (t = 5.95 s; >= 0.44 through the extreme swings at
  // t = 3.0-3.5 s); 2.9 Newton and 35 Krylov a step before 4.4 s, 3.2 and 44 after, 4.5 and 98
  // over t = 6.0-6.6 s, where the Newton count alternates 4/6 from step to step (the lift carries
  // a step-to-step zigzag of ~2, 1% of its amplitude). At t = 6.6 s: u_y(A) 1.26e-3 +- 7.78e-2
  // (-3.4%, amplitude change over the last period 0.00%) at 1.964 Hz (-1.8%), u_x(A) -1.38e-2 +-
  // 1.20e-2 (mean -5.3%, amplitude -3.5%) at 3.93 Hz (+3.4%), drag 206.4 +- 68.9 (mean -1.2%,
  // amplitude -6.6%) at 3.93 Hz (+3.5%), lift 0.64 +- 219.7 (-6.2%) at 1.969 Hz (-1.6%). The
  // lift's half-period peaks vary between 210 and 228 over t = 4.6-6.6 s, so one period's lift
  // amplitude moves by a few per cent with the end of the run. Flag/cylinder: lift +-244.0 /
  // +-61.4, partly out of phase; drag 57.6 +- 66.2 / 148.4 +- 3.7.
  // Checked against Turek & Hron (2006)'s FSI2 summary row (as nutils' examples/turek.py also
  // quotes it); unlike FSI3's, no finer row of the authors' is at hand here.
  c.reference = {{-1.4580e-2, 1.2440e-2, 3.8},
                 {1.2300e-3, 8.0600e-2, 2.0},
                 {2.0883e2, 7.3750e1, 3.8},
                 {8.8000e-1, 2.3420e2, 2.0}};
  return c;
}

UnsteadyCase fsi3() {
  UnsteadyCase c;
  c.number = 3;
  // On turek_hron_flag (refine 2's flag in the wake mesh; why: the header). Start-up with 19
  // steps per lift period, measured with 76: the swing grows from t ~ 1.7 s (u_y 0.039 at 2.54 s
  // in the dt 0.01 stage), and the 0.5 s at dt 0.0025 reach the periodic state (from t ~ 3.1 s)
  // and two periods in it. These stages from rest (490 steps) measured the header's numbers.
  // fsi.rel_tol 1e-4: against 1e-6 from rest to t = 1.37 s the largest differences are 4e-6 of
  // u_y(A)'s and 1.3e-4 of the lift's largest value, and in the periodic state the lift and drag
  // amplitudes of the two differ by less than either's spread from period to period; it saves a
  // quarter of the time. Checked against the benchmark authors' finest FSI3 result: Featflow, level
  // 4+0, dt = 0.00025 s, the row of the reference time history published with the benchmark
  // (Featflow FSI benchmark reference page, TU Dortmund; Turek, Hron, Madlik, Razzaq, Wobker &
  // Acker 2010, Fluid Structure Interaction II, LNCSE 73). The 2006 proposal's summary row (as
  // quoted by nutils' examples/turek.py and solids4foam), reported beside it, differs from it most
  // in the drag amplitude, 22.66 against 27.74 (-18%): this run's drag amplitude is +18.6% against
  // the 2006 row and -3.1% against this one (on a finer mesh it rises; see the header). Checks on
  // the finer row: the published history itself (t = 5.0455-5.228 s, one swing, read from
  // solids4foam's copy, tutorials/fluidSolidInteraction/HronTurekFsi3/verification/reference)
  // gives drag 460.1 +- 28.3, u_y 1.57e-3 +- 3.481e-2, u_x -2.87e-3 +- 2.72e-3; solids4foam's own
  // FSI3 study (finite volumes, partitioned, 2x mesh) measured drag 459.3 +- 28.06 against it.
  c.reference = {{-2.8800e-3, 2.7200e-3, 10.93},
                 {1.4700e-3, 3.4990e-2, 5.46},
                 {4.6050e2, 2.7740e1, 10.93},
                 {2.5000e0, 1.5391e2, 5.46}};
  c.row_2006 = BenchmarkRow{{-2.6900e-3, 2.5300e-3, 10.9},
                            {1.4800e-3, 3.4380e-2, 5.3},
                            {4.5730e2, 2.2660e1, 10.9},
                            {2.2200e0, 1.4978e2, 5.3}};
  return c;
}

// The series of a case's scene, per unit depth (the scenes' thickness 0.05).
struct Series {
  std::vector<double> t, ux, uy, drag, lift, drag_flag, lift_flag;
};

Series run(const UnsteadyCase& c) {
  const std::string name = "fsi" + std::to_string(c.number);
  const auto out = scratch_dir(name);
  const RunOutput r = run_quietly(case_run("turek_hron/" + name + ".yaml", out));
  EXPECT_EQ(r.rc, 0) << r.err << r.out;
  auto columns = read_series(out / "series.csv");
  const double depth = 0.05;
  Series s;
  s.t = columns["time"];
  s.ux = columns["A_displacement_x"];
  s.uy = columns["A_displacement_y"];
  for (size_t i = 0; i < s.t.size(); ++i) {
    // body: the cylinder and the flag, the flag's root corners once.
    s.drag.push_back(columns["force_body_x"][i] / depth);
    s.lift.push_back(columns["force_body_y"][i] / depth);
    s.drag_flag.push_back(columns["force_fsi_x"][i] / depth);
    s.lift_flag.push_back(columns["force_fsi_y"][i] / depth);
  }
  return s;
}

void check(const UnsteadyCase& c) {
  const Series s = run(c);
  ASSERT_FALSE(s.t.empty());
  // The last third of the run: past the ramp and the growth of the oscillation.
  const double t_from = s.t.back() * 2.0 / 3.0;
  const Oscillation ux = analyse(s.t, s.ux, t_from, 4), uy = analyse(s.t, s.uy, t_from, 4);
  const Oscillation drag = analyse(s.t, s.drag, t_from, 4), lift = analyse(s.t, s.lift, t_from, 4);
  auto report_row = [&](const BenchmarkRow& row, const std::string& which) {
    report_against(("u_x(A)" + which).c_str(), ux, row.ux);
    report_against(("u_y(A)" + which).c_str(), uy, row.uy);
    report_against(("drag" + which).c_str(), drag, row.drag);
    report_against(("lift" + which).c_str(), lift, row.lift);
  };
  report_row(c.reference, "");
  if (c.row_2006) report_row(*c.row_2006, ", against the 2006 summary");
  // Which body carries the forces' error: the flag's part is tied to the flag's own motion, the
  // cylinder's is the wake's (the cylinder's = body's less the flag's; the root corners count in
  // the flag's).
  std::vector<double> drag_cylinder(s.t.size()), lift_cylinder(s.t.size());
  for (size_t i = 0; i < s.t.size(); ++i) {
    drag_cylinder[i] = s.drag[i] - s.drag_flag[i];
    lift_cylinder[i] = s.lift[i] - s.lift_flag[i];
  }
  report("drag on the flag", analyse(s.t, s.drag_flag, t_from, 4));
  report("drag on the cylinder", analyse(s.t, drag_cylinder, t_from, 4));
  report("lift on the flag", analyse(s.t, s.lift_flag, t_from, 4));
  report("lift on the cylinder", analyse(s.t, lift_cylinder, t_from, 4));
  ASSERT_GE(uy.periods, 3) << "no periodic oscillation in the analysed window";
  // A swing still growing (or decaying) is not the periodic state the benchmark reports: the
  // last two periods' amplitudes within 3% (the growth seen on the way was 10-70% per period;
  // Crank-Nicolson's step-to-step jitter moves a sampled extreme by ~1%).
  EXPECT_LT(std::abs(uy.amplitude_change), 0.03) << "u_y(A) not yet periodic";
  // Tolerances, and why: the frequency is what a coarse mesh and ~20 steps per period keep best
  // (Crank-Nicolson's phase error at omega dt = 0.33 is ~1%, the flag's stiffness on 4 elements
  // through its thickness ~3% as in FSI1); 5%. The amplitudes carry the mesh's error in the
  // wake and the flag's bending: 15%. The means of u_y and lift are small differences of large
  // swings (the reference's own levels disagree in that digit), so only drag's mean, 5%.
  const BenchmarkRow& r = c.reference;
  EXPECT_NEAR(uy.frequency, r.uy.frequency, 0.05 * r.uy.frequency);
  EXPECT_NEAR(lift.frequency, r.lift.frequency, 0.05 * r.lift.frequency);
  EXPECT_NEAR(ux.frequency, r.ux.frequency, 0.05 * r.ux.frequency);
  EXPECT_NEAR(uy.amplitude, r.uy.amplitude, 0.15 * r.uy.amplitude);
  EXPECT_NEAR(ux.amplitude, r.ux.amplitude, 0.15 * r.ux.amplitude);
  EXPECT_NEAR(lift.amplitude, r.lift.amplitude, 0.15 * r.lift.amplitude);
  EXPECT_NEAR(drag.amplitude, r.drag.amplitude, 0.15 * r.drag.amplitude);
  EXPECT_NEAR(drag.mean, r.drag.mean, 0.05 * r.drag.mean);
}

}  // namespace

TEST(FsiUnsteadyLong, TurekHronFsi2) { check(fsi2()); }

TEST(FsiUnsteadyLong, TurekHronFsi3) { check(fsi3()); }
