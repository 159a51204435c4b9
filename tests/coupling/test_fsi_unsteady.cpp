// Turek & Hron (2006) FSI2 and FSI3: the elastic flag behind the cylinder oscillating in the flow
// it sheds (fsi_benchmarks.hpp), run from rest to a periodic state and compared with the
// benchmark's mean, amplitude and frequency of u_x(A), u_y(A), drag and lift. Label long: on the
// development machine these take several hours each on one thread (what they measured so far:
// README, "Known limits").
//
// Environment, for studies (defaults in brackets): BIOFSI_FSI_REFINE [1], BIOFSI_FSI_DT [FSI2
// 0.02, FSI3 0.01], BIOFSI_FSI_T_END [FSI2 15, FSI3 8], BIOFSI_FSI_RAMP [0.5], BIOFSI_FSI_KICK
// [FSI2 4, FSI3 0: the peak of the transverse seeding pulse on the flag, m/s^2], BIOFSI_FSI_SIMPLE
// [0: the fluid block preconditioned by SIMPLEC; 1: SIMPLE], BIOFSI_FSI_SERIES (a folder: the time
// series is written there as fsi<k>_series.csv after every step), BIOFSI_FSI_FROM_SERIES (such a
// file: analyse it instead of running, e.g. a run stopped early; pick the case with
// --gtest_filter).
//
// How the numbers are taken: as the benchmark does, over the last full period of each signal
// (oscillation.hpp, tested in the default suite).
//
// The start differs from the benchmark's on purpose: the inflow is ramped over BIOFSI_FSI_RAMP
// seconds instead of 2, to reach the periodic state in fewer steps; the periodic state does not
// depend on how it was reached. For the same reason FSI2's flag gets a transverse push when the
// ramp ends (a body force rho_s a(t) on the flag, a(t) = kick sin^2(pi (t - t0) / 0.25 s) for a
// quarter second, half the expected period): from rest its swing grows out of round-off by only
// ~1.35x per 0.5 s (7e-3 at t = 4 s, 0.03 at 7 s against the periodic 0.081), so the unseeded run
// spends most of its steps reaching the state the benchmark measures. Estimated effect of 4 m/s^2
// (impulse over flag plus broadside added mass, at 2 Hz): a tip swing of ~0.015.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "ale/mesh_motion.hpp"
#include "coupling/fsi_benchmarks.hpp"
#include "coupling/oscillation.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

double env_or(const char* name, double fallback) {
  const char* v = std::getenv(name);
  if (!v || !*v) return fallback;
  char* end = nullptr;
  const double x = std::strtod(v, &end);
  if (end == v || *end != '\0' || !std::isfinite(x)) {
    ADD_FAILURE() << "environment variable " << name << " = '" << v << "': expected a number";
    return fallback;
  }
  return x;
}

// A published row: mean ± amplitude [frequency].
struct Reference {
  double mean, amplitude, frequency;
};

struct Series {
  std::vector<double> t, ux, uy, drag, lift;
};

struct UnsteadyCase {
  int number;  // 2 or 3
  FsiCase parameters;
  double dt, t_end;
  double kick = 0;  // peak transverse acceleration of the seeding pulse [m/s^2]
  // Turek & Hron (2006), Tables 12 and 13 ("FSI2", "FSI3"), finest level.
  Reference ux, uy, drag, lift;
};

UnsteadyCase fsi2() {
  UnsteadyCase c;
  c.number = 2;
  c.parameters.solid_density = 10000;
  c.parameters.solid_shear_modulus = 0.5e6;
  c.parameters.u_mean = 1;
  c.dt = 0.02;  // 25 steps per lift period
  c.t_end = 15;
  c.kick = 4;
  c.ux = {-1.4580e-2, 1.2440e-2, 3.8};
  c.uy = {1.2300e-3, 8.0600e-2, 2.0};
  c.drag = {2.0883e2, 7.3750e1, 3.8};
  c.lift = {8.8000e-1, 2.3420e2, 2.0};
  return c;
}

UnsteadyCase fsi3() {
  UnsteadyCase c;
  c.number = 3;
  c.parameters.solid_density = 1000;
  c.parameters.solid_shear_modulus = 2e6;
  c.parameters.u_mean = 2;
  c.dt = 0.01;  // 19 steps per lift period
  c.t_end = 8;
  c.ux = {-2.6900e-3, 2.5300e-3, 10.9};
  c.uy = {1.4800e-3, 3.4380e-2, 5.3};
  c.drag = {4.5700e2, 2.2660e1, 10.9};
  c.lift = {2.2000e0, 1.4936e2, 5.3};
  return c;
}

// Appends the series' newest row (and the header with the first), so a run stopped at any
// point leaves every finished step on disk without rewriting the file each step.
void append_last_row(const std::string& folder, int number, const Series& s) {
  const std::string path = folder + "/fsi" + std::to_string(number) + "_series.csv";
  std::ofstream out(path, s.t.size() == 1 ? std::ios::trunc : std::ios::app);
  if (s.t.size() == 1) out << "t,ux,uy,drag,lift\n";
  out.precision(10);
  const size_t i = s.t.size() - 1;
  out << s.t[i] << ',' << s.ux[i] << ',' << s.uy[i] << ',' << s.drag[i] << ',' << s.lift[i] << '\n';
}

Series run(const UnsteadyCase& c) {
  const int refine = static_cast<int>(env_or("BIOFSI_FSI_REFINE", 1));
  const double dt = env_or("BIOFSI_FSI_DT", c.dt), t_end = env_or("BIOFSI_FSI_T_END", c.t_end);
  const double ramp_time = env_or("BIOFSI_FSI_RAMP", 0.5);
  const char* folder = std::getenv("BIOFSI_FSI_SERIES");
  auto th = make_turek_hron(
      "turek_hron_r" + std::to_string(refine), c.parameters, false, 0.5,
      ShapeDerivatives::FiniteDifference,
      [](FsiSettings& s) {
        // Every field to 1e-6 of its largest residual in the step: the step's own
        // discretisation error is far larger.
        s.rel_tol = 1e-6;
        s.inner_tolerance = 1e-2;
        // The flag's swing (FSI2: 0.08 at the tip) squeezes the fluid cells around it. A
        // prescribed bending shape moved the refine-1 mesh to a minimum scaled Jacobian of
        // 0.58 / 0.28 / 0.008 at tip 0.05 / 0.07 / 0.09 with the default (1/det J)^1
        // stiffening, 0.66 / 0.64 / 0.56 with the square.
        s.mesh_motion.stiffening = 2;
      },
      [](FluidSettings& f) {
        // SIMPLEC: at FSI3's Re 200 and CFL ~6 the fluid block needed ~12 inner
        // iterations per outer one where SIMPLE needed 30-40 (diag(A) no longer
        // stands for a convection-dominated A; its row sums do better).
        f.preconditioner = env_or("BIOFSI_FSI_SIMPLE", 0) != 0 ? FluidPreconditioner::Simple
                                                               : FluidPreconditioner::SimpleC;
      });
  th->ramp = [ramp_time](double t) {
    return t < ramp_time ? 0.5 * (1 - std::cos(M_PI * t / ramp_time)) : 1.0;
  };
  const double kick = env_or("BIOFSI_FSI_KICK", c.kick);
  if (kick != 0) {
    const double force = c.parameters.solid_density * kick, t0 = ramp_time, width = 0.25;
    const SpaceTimeFunction zero = [](const Point&, double) { return 0.0; };
    th->structure->set_body_force({zero,
                                   [=](const Point&, double t) {
                                     if (t <= t0 || t >= t0 + width) return 0.0;
                                     const double s = std::sin(M_PI * (t - t0) / width);
                                     return force * s * s;
                                   },
                                   zero});
  }
  Series s;
  const int steps = static_cast<int>(std::lround(t_end / dt));
  for (int i = 1; i <= steps; ++i) {
    const auto start = std::chrono::steady_clock::now();
    const NewtonResult r =
        th->fsi->step(dt, "FSI" + std::to_string(c.number) + " step " + std::to_string(i));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const Point f = th->force();
    // The fields do not check the deformed mesh (the scene driver does): stop here, with the
    // step named, rather than integrate on an inverted element.
    for (const QualityRange& q : mesh_quality_by_block(th->fsi->current_mesh()))
      if (!(q.min > 0)) {
        ADD_FAILURE() << "FSI" << c.number << " step " << i << " (t = " << i * dt << "): element "
                      << q.worst_element << " inverted (scaled Jacobian " << q.min << ")";
        return s;
      }
    s.t.push_back(i * dt);
    s.ux.push_back(th->tip_displacement(0));
    s.uy.push_back(th->tip_displacement(1));
    s.drag.push_back(f[0]);
    s.lift.push_back(f[1]);
    std::printf(
        "FSI%d t %.4f: %d Newton, %d Krylov, %.1f s; u_x %.4e u_y %.4e drag %.2f lift %.2f\n",
        c.number, i * dt, r.iterations, r.krylov_iterations, seconds, s.ux.back(), s.uy.back(),
        s.drag.back(), s.lift.back());
    std::fflush(stdout);
    if (folder) append_last_row(folder, c.number, s);
  }
  return s;
}

void compare(const char* name, const Oscillation& o, const Reference& r) {
  std::printf(
      "[ measured ] %s: %.4e +- %.4e [%.2f Hz] (reference %.4e +- %.4e [%.1f]); "
      "amplitude %+.1f%%, frequency %+.1f%%; amplitude change over the last period %+.1f%%\n",
      name, o.mean, o.amplitude, o.frequency, r.mean, r.amplitude, r.frequency,
      100 * (o.amplitude - r.amplitude) / r.amplitude,
      100 * (o.frequency - r.frequency) / r.frequency, 100 * o.amplitude_change);
}

// A series written by an earlier run (BIOFSI_FSI_SERIES), for analysing a run stopped early.
Series read_series(const std::string& path) {
  std::ifstream in(path);
  Series s;
  if (!in) {
    ADD_FAILURE() << "BIOFSI_FSI_FROM_SERIES = '" << path << "': cannot open the file";
    return s;
  }
  std::string line;
  std::getline(in, line);  // header t,ux,uy,drag,lift
  double v[5];
  char comma;
  while (in >> v[0] >> comma >> v[1] >> comma >> v[2] >> comma >> v[3] >> comma >> v[4]) {
    s.t.push_back(v[0]);
    s.ux.push_back(v[1]);
    s.uy.push_back(v[2]);
    s.drag.push_back(v[3]);
    s.lift.push_back(v[4]);
  }
  if (s.t.empty())
    ADD_FAILURE() << "BIOFSI_FSI_FROM_SERIES = '" << path << "': no rows t,ux,uy,drag,lift";
  return s;
}

void check(const UnsteadyCase& c) {
  const char* from = std::getenv("BIOFSI_FSI_FROM_SERIES");
  const Series s = from ? read_series(from) : run(c);
  ASSERT_FALSE(s.t.empty());
  // The last third of the run: past the ramp and the growth of the oscillation.
  const double t_from = s.t.back() * 2.0 / 3.0;
  const Oscillation ux = analyse(s.t, s.ux, t_from, 4), uy = analyse(s.t, s.uy, t_from, 4);
  const Oscillation drag = analyse(s.t, s.drag, t_from, 4), lift = analyse(s.t, s.lift, t_from, 4);
  compare("u_x(A)", ux, c.ux);
  compare("u_y(A)", uy, c.uy);
  compare("drag", drag, c.drag);
  compare("lift", lift, c.lift);
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
  EXPECT_NEAR(uy.frequency, c.uy.frequency, 0.05 * c.uy.frequency);
  EXPECT_NEAR(lift.frequency, c.lift.frequency, 0.05 * c.lift.frequency);
  EXPECT_NEAR(ux.frequency, c.ux.frequency, 0.05 * c.ux.frequency);
  EXPECT_NEAR(uy.amplitude, c.uy.amplitude, 0.15 * c.uy.amplitude);
  EXPECT_NEAR(ux.amplitude, c.ux.amplitude, 0.15 * c.ux.amplitude);
  EXPECT_NEAR(lift.amplitude, c.lift.amplitude, 0.15 * c.lift.amplitude);
  EXPECT_NEAR(drag.amplitude, c.drag.amplitude, 0.15 * c.drag.amplitude);
  EXPECT_NEAR(drag.mean, c.drag.mean, 0.05 * c.drag.mean);
}

}  // namespace

TEST(FsiUnsteadyLong, TurekHronFsi2) { check(fsi2()); }

TEST(FsiUnsteadyLong, TurekHronFsi3) { check(fsi3()); }
