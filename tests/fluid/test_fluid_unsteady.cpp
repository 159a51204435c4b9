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
// The start: the inflow is ramped over BIOFSI_UNSTEADY_RAMP [0.5] s (the benchmark's 2 s is not
// needed for a periodic state), and a transverse pulse of body force (BIOFSI_UNSTEADY_KICK [CFD3
// 30, DFG 5] m/s^2 peak, sin^2 over 0.1 s after the ramp, on the fluid behind the body) breaks the
// near-symmetry from which shedding would otherwise grow out of round-off (on refine 1 a 2 m/s^2
// pulse left CFD3's oscillation at +-4 at t = 4 s).
//
// Tolerances, and why: the DFG participants' converged results spread by +-1.7% in St and +-1% in
// c_L max; a Q1 mesh of a few thousand nodes is allowed about twice that in frequency (3%) and ten
// times in lift amplitude (10%); and the state must be periodic (lift amplitude change < 3% over
// the last period), not still growing.
//
// Measured (one thread, dt 0.01, theta 0.5, the midpoint form of kernels/fluid/pointwise.hpp):
//   DFG 2D-2 refine 1 (6 min): c_L +-1.028 (+2.8%), St -2.45%, c_D max 3.2224 (-0.24%),
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
//   CFD3 on turek_hron_wake with BIOFSI_UNSTEADY_DT=0.0025 (FSI3's measuring step; 90 min) to
//     t = 5 s: lift -23.8 +- 376.7 (-14.0%) at 4.373 Hz (-0.5%), amplitude change -1.2%, drag
//     mean 439.4 (-0.01%): fails on the lift. The midpoint rule is second order, so dt 0.0025
//     leaves ~1/16 of dt 0.01's time error: on this mesh the shedding is ~14% weak in space, and
//     part of dt 0.01's pass is its time error.
//   CFD3 on refine 1 (BIOFSI_UNSTEADY_MESH=turek_hron_r1 BIOFSI_UNSTEADY_T_END=10, 10 min): lift
//     -44 +- 141 (-68%) at 4.10 Hz (-6.8%), still growing 2.1% a period at t = 10 s: refine 1's
//     wake is too coarse for CFD3's shedding, and with it for FSI3's flow, so CFD3 runs on the
//     wake mesh.
//   So on meshes of 7-11 thousand nodes per layer the shedding is 7-14% weak, and refining one
//   region does not move it monotonically toward the reference.
// Environment: BIOFSI_UNSTEADY_MESH [CFD3 turek_hron_wake, DFG dfg_2d1_r1: a mesh of the build,
// e.g. turek_hron_r2, or the path of a .msh of the same geometry made with other gmsh parameters],
// BIOFSI_UNSTEADY_DT [0.01], BIOFSI_UNSTEADY_T_END [CFD3 5, DFG 6], BIOFSI_UNSTEADY_THETA [0.5],
// BIOFSI_UNSTEADY_GRAD_DIV [1], BIOFSI_UNSTEADY_SERIES (a file: t, drag, lift per step),
// BIOFSI_UNSTEADY_FROM_SERIES (such a file: analyse it instead of running; pick the case with
// --gtest_filter).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>

#include "coupling/oscillation.hpp"
#include "environment.hpp"
#include "fluid/fluid_benchmarks.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

struct SheddingCase {
  const char* name = "";
  std::string mesh;  // of the build's mesh folder (fluid_benchmarks.hpp's mesh_file)
  bool fluid_block_only = false;
  std::vector<std::string> body_sets;
  double density = 1, viscosity = 1, u_mean = 1, kick = 0, t_end = 1;
  double force_scale = 1;  // forces per unit depth -> the reported quantity (1, or 2/(rho U^2 D))
  Reference lift{}, drag{};
  double drag_max = 0;  // DFG reports the maximum of c_D instead of mean and amplitude (0: none)
};

SheddingCase cfd3() {
  SheddingCase c;
  c.name = "CFD3";
  // Refine 1's body with a finer wake (tests/CMakeLists.txt): refine 1 itself damps the shedding
  // to a third (measured above).
  c.mesh = "turek_hron_wake";
  c.fluid_block_only = true;
  c.body_sets = {"cylinder", "fsi"};
  c.density = 1000;
  c.viscosity = 1;
  c.u_mean = 2;
  c.kick = 30;
  c.t_end = 5;  // periodic from ~4.7 s on the wake mesh
  c.lift = {-11.893, 437.81, 4.3956};
  c.drag = {439.45, 5.6183, 8.7912};
  return c;
}

SheddingCase dfg2d2() {
  SheddingCase c;
  c.name = "DFG 2D-2";
  c.mesh = "dfg_2d1_r1";
  c.body_sets = {"cylinder"};
  c.density = 1;
  c.viscosity = 1e-3;
  c.u_mean = 1;
  c.kick = 5;
  c.t_end = 6;
  // Lift and drag as c_L, c_D = 2 F / (rho U_mean^2 D); the drag oscillates at twice the
  // shedding frequency, its mean is not published.
  c.force_scale = 2 / (1.0 * 1.0 * 1.0 * 0.1);
  c.lift = {0.0, 1.0, 3.0};
  c.drag = {0.0, 0.0, 6.0};
  c.drag_max = 3.23;
  return c;
}

std::string mesh_name(const SheddingCase& c) { return env_or("BIOFSI_UNSTEADY_MESH", c.mesh); }

Mesh shedding_mesh(const SheddingCase& c) {
  Mesh mesh = read_gmsh(mesh_file(mesh_name(c)), benchmark_thickness);
  if (c.fluid_block_only) mesh = submesh(mesh, {"fluid"});
  add_union_set(mesh, c.body_sets, "body");
  return mesh;
}

struct ForceSeries {
  std::vector<double> t, drag, lift;
};

ForceSeries run(const SheddingCase& c, double dt, double t_end) {
  const Mesh mesh = shedding_mesh(c);
  const double ramp = env_or("BIOFSI_UNSTEADY_RAMP", 0.5);
  const double kick = env_or("BIOFSI_UNSTEADY_KICK", c.kick);
  FluidSettings s = tight_fluid_settings(c.density, c.viscosity);
  s.symmetric_viscous = false;  // the benchmarks' do-nothing outflow
  s.theta = env_or("BIOFSI_UNSTEADY_THETA", 0.5);
  s.grad_div = env_or("BIOFSI_UNSTEADY_GRAD_DIV", 1) != 0;
  // SIMPLEC, as in the FSI runs: with SIMPLE the Krylov solves stalled once CFD3's wake formed
  // (refine 1, dt 0.01, t = 0.42 s).
  s.preconditioner = FluidPreconditioner::SimpleC;
  s.newton_options.rel_tol = 1e-8;
  s.newton_options.abs_tol = 1e-10;
  const double h = 0.41, u_max = 1.5 * c.u_mean;
  const FluidFunction inflow = [h, u_max, ramp](const Point& x, double t) {
    const double r = t < ramp ? 0.5 * (1 - std::cos(M_PI * t / ramp)) : 1.0;
    return r * 4 * u_max * x[1] * (h - x[1]) / (h * h);
  };
  FluidField field(mesh, s,
                   {fluid_no_slip("walls"), fluid_no_slip("body"),
                    fluid_velocity("inflow", inflow, constant(0.0), constant(0.0)),
                    fluid_do_nothing("outflow")});
  field.set_initial(nullptr, nullptr, 0.0);
  const double width = 0.1;
  field.set_body_force([ramp, kick, width](const Point& x, double t) -> Point {
    const bool behind = x[0] > 0.25 && x[0] < 0.7 && x[1] > 0.1 && x[1] < 0.3;
    if (!behind || t < ramp || t > ramp + width) return {0, 0, 0};
    const double a = std::sin(M_PI * (t - ramp) / width);
    return {0, kick * a * a, 0};
  });
  std::ofstream out;
  if (const char* file = std::getenv("BIOFSI_UNSTEADY_SERIES")) out.open(file);
  ForceSeries r;
  const int steps = static_cast<int>(std::lround(t_end / dt));
  for (int i = 1; i <= steps; ++i) {
    const int krylov_before = field.stats().krylov_iterations;
    const NewtonResult nr = field.step(dt, std::string(c.name) + " step " + std::to_string(i));
    const Point f = field.force("body");
    r.t.push_back(i * dt);
    r.drag.push_back(c.force_scale * f[0] / benchmark_thickness);
    r.lift.push_back(c.force_scale * f[1] / benchmark_thickness);
    std::printf("%s t %.4f drag %.4g lift %.4g", c.name, r.t.back(), r.drag.back(), r.lift.back());
    // Each body's part (CFD3: the cylinder and the flag). The sets share the flag's root corners,
    // so the parts do not add up exactly to the total; the drag's split also moves with the
    // pressure level (TurekHronFsi::ForceParts, tests/coupling/fsi_benchmarks.hpp).
    if (c.body_sets.size() > 1)
      for (const std::string& set : c.body_sets) {
        const Point part = field.force(set);
        std::printf(" (%s %.4g, %.4g)", set.c_str(), c.force_scale * part[0] / benchmark_thickness,
                    c.force_scale * part[1] / benchmark_thickness);
      }
    std::printf(": %d Newton, %d Krylov, %d cut steps so far\n", nr.iterations,
                field.stats().krylov_iterations - krylov_before, field.stats().cut_steps);
    std::fflush(stdout);
    if (out)
      out << r.t.back() << ' ' << r.drag.back() << ' ' << r.lift.back() << '\n' << std::flush;
  }
  return r;
}

// A series written by BIOFSI_UNSTEADY_SERIES, e.g. of a run stopped early.
ForceSeries read_series(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("BIOFSI_UNSTEADY_FROM_SERIES: cannot read '" + path + "'");
  ForceSeries s;
  double t, drag, lift;
  while (in >> t >> drag >> lift) {
    s.t.push_back(t);
    s.drag.push_back(drag);
    s.lift.push_back(lift);
  }
  if (s.t.empty()) throw std::runtime_error("BIOFSI_UNSTEADY_FROM_SERIES: '" + path + "' is empty");
  return s;
}

void check_shedding(const SheddingCase& c) {
  const double dt = env_or("BIOFSI_UNSTEADY_DT", 0.01);
  const char* from = std::getenv("BIOFSI_UNSTEADY_FROM_SERIES");
  const ForceSeries s =
      from && *from ? read_series(from) : run(c, dt, env_or("BIOFSI_UNSTEADY_T_END", c.t_end));
  const double t_end = s.t.back();
  const double window = t_end - 1.0;
  const Oscillation drag = analyse(s.t, s.drag, window, 8), lift = analyse(s.t, s.lift, window, 4);
  if (from && *from)
    std::printf("[ measured ] %s, the series in %s, to t = %g:\n", c.name, from, t_end);
  else
    std::printf("[ measured ] %s on %s, dt %g, to t = %g:\n", c.name, mesh_name(c).c_str(), dt,
                t_end);
  report_against("drag", drag, c.drag);
  report_against("lift", lift, c.lift);
  EXPECT_LT(std::abs(lift.amplitude_change), 0.03);  // a periodic state, not a growing one
  EXPECT_NEAR(lift.frequency, c.lift.frequency, 0.03 * c.lift.frequency);
  EXPECT_NEAR(lift.amplitude, c.lift.amplitude, 0.10 * c.lift.amplitude);
  if (c.drag_max > 0) {
    const double drag_max = drag.mean + drag.amplitude;
    std::printf("[ measured ] drag maximum %.4f (%+.2f%%; reference 3.22-3.24)\n", drag_max,
                percent_off(drag_max, c.drag_max));
    EXPECT_NEAR(drag_max, c.drag_max, 0.01 * c.drag_max);  // twice the participants' spread
  }
}

}  // namespace

TEST(FluidUnsteadyLong, TurekHronCfd3) { check_shedding(cfd3()); }

TEST(FluidUnsteadyLong, Dfg2d2) { check_shedding(dfg2d2()); }
