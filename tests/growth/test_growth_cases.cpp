// The paper's cases (a), (b) and (c) end to end through the driver (run_scene), at a reduced mesh
// resolution so that 60 growth steps fit the default test run: uniform rise in (a), symmetry and
// a central bump in (b), downstream-upstream asymmetry under flow in (c), mesh validity, restart,
// the stop at an aggressive growth rate, and readable files after a killed run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>

#include "app/run.hpp"
#include "io/output.hpp"
#include "io/scene.hpp"
#include "scene_run.hpp"
#include "scratch_dir.hpp"

using namespace biofsi;
namespace fs = std::filesystem;

namespace {

const std::string source_dir = BIOFSI_SOURCE_DIR;

fs::path fresh_dir(const std::string& name) { return test::scratch_dir("growth_" + name); }

// Coarse copies of the cases: 20 x (4 + 16) elements, every growth step written.
std::vector<std::string> coarse(std::vector<std::string> more = {}) {
  std::vector<std::string> o = {"mesh.nx=20",
                                "mesh.blocks.0.ny=4",
                                "mesh.blocks.1.ny=16",
                                "growth.output_every=1",
                                "solver.newton.rel_tol=1e-12",
                                "solver.newton.abs_tol=1e-15",
                                "solver.linear.rel_tol=1e-10"};
  o.insert(o.end(), more.begin(), more.end());
  return o;
}

using Captured = test::RunOutput;

// A scene of the repository run into `out` (replacing what is there), streams captured.
Captured run(const std::string& scene, const fs::path& out, const std::vector<std::string>& set,
             const std::string& restart = "") {
  RunOptions o;
  o.scene_path = source_dir + "/" + scene;
  o.out_dir = out.string();
  o.overrides = set;
  o.overwrite = true;
  o.restart = restart;
  return test::run_quietly(o);
}

std::string step_file(const fs::path& dir, int step) {
  char name[32];
  std::snprintf(name, sizeof name, "scalar_%06d.h5", step);
  return (dir / name).string();
}

// Interface node heights (y) at a written growth step, in node_sets order.
std::vector<Point> interface_points(const fs::path& dir, int step, const Mesh& mesh) {
  const auto xyz = read_h5_dataset(step_file(dir, step), "coordinates");
  std::vector<Point> p;
  for (int n : mesh.node_sets.at("biofilm_fluid"))
    p.push_back({xyz[3 * n], xyz[3 * n + 1], xyz[3 * n + 2]});
  return p;
}

Mesh scene_mesh(const std::string& scene, const std::vector<std::string>& set) {
  return make_scene_mesh(load_scene(source_dir + "/" + scene, set));
}

double min_quality_in(const std::string& summary) {
  std::smatch m;
  const std::regex re("mesh quality \\(scaled Jacobian\\) over the run: \\[([-0-9.e]+),");
  return std::regex_search(summary, m, re) ? std::stod(m[1]) : -1;
}

}  // namespace

TEST(GrowthCaseA, InterfaceRisesUniformlyAtEveryGrowthStep) {
  const fs::path dir = fresh_dir("a");
  const auto set = coarse();
  const Captured r = run("cases/coroneo2013/a_uniform.yaml", dir, set);
  ASSERT_EQ(r.rc, 0) << r.err;
  const Mesh mesh = scene_mesh("cases/coroneo2013/a_uniform.yaml", set);
  double previous_mean = -3.0;
  for (int k = 1; k <= 60; ++k) {
    const auto p = interface_points(dir, k, mesh);
    double lo = 1e300, hi = -1e300, mean = 0;
    for (const auto& q : p) lo = std::min(lo, q[1]), hi = std::max(hi, q[1]), mean += q[1];
    mean /= p.size();
    const double rise = mean + 3.0;
    ASSERT_GT(mean, previous_mean) << "step " << k;  // it grows at every step
    // The bound: the spread of the interface height below 1e-8 of the mean rise; the
    // problem is exactly x-independent, so only solver tolerances (1e-12) separate the nodes.
    EXPECT_LT(hi - lo, 1e-8 * rise) << "step " << k;
    previous_mean = mean;
  }
  EXPECT_GT(previous_mean + 3.0, 0.5);  // visible growth: about a millimetre over 60 steps
  EXPECT_GT(min_quality_in(r.out), 0.5) << r.out;  // the mesh stays valid and well shaped
}

TEST(GrowthCaseB, IsSymmetricAndGrowsMoreAtTheCentreThanAtTheWalls) {
  const fs::path dir = fresh_dir("b");
  const auto set = coarse();
  const Captured r = run("cases/coroneo2013/b_cosine.yaml", dir, set);
  ASSERT_EQ(r.rc, 0) << r.err;
  const Mesh mesh = scene_mesh("cases/coroneo2013/b_cosine.yaml", set);
  for (int k : {1, 10, 30, 60}) {
    const auto p = interface_points(dir, k, mesh);
    double max_rise = 0, centre = 0, wall = 0;
    for (const auto& q : p) max_rise = std::max(max_rise, q[1] + 3.0);
    for (const auto& q : p) {
      // Mirror partner (-x, same z).
      const auto m = std::find_if(p.begin(), p.end(), [&](const Point& o) {
        return std::abs(o[0] + q[0]) < 1e-9 && std::abs(o[2] - q[2]) < 1e-12;
      });
      ASSERT_NE(m, p.end());
      // 1e-10 relative (the bound): the discrete problem is mirror-symmetric; only the
      // iterative solvers' tolerances (1e-12 Newton, 1e-10 Krylov) break the symmetry.
      EXPECT_NEAR(q[1], (*m)[1], 1e-10 * max_rise) << "step " << k << " x " << q[0];
      if (std::abs(q[0]) < 1e-9) centre = q[1] + 3.0;
      if (std::abs(q[0] - 5.0) < 1e-9) wall = q[1] + 3.0;
    }
    EXPECT_GT(centre, wall) << "step " << k;
    if (k == 60) {
      std::cout << "case (b), 60 growth steps: centre rise " << centre << " mm, wall rise " << wall
                << " mm\n";
      EXPECT_GT(centre, 0.5);  // visible growth, order 1 mm (the case file's calibration)
    }
  }
  EXPECT_GT(min_quality_in(r.out), 0.5) << r.out;
}

// Case (c): case (b) under a shear flow to +x, the film elastic and coupled to the flow (FSI).
// Two effects make the film grow more downstream
// (x > 0) than upstream: the flow carries the substrate from the source's peak at x = 0
// downstream, so the interface flux J peaks downstream of x = 0; and the upstream-facing slope
// of the film meets the flow and sees a larger wall shear stress, so erosion (K2 sigma) removes
// more there. The run also checks that every inner loop after the first reaches the scene's
// steady_tolerance (the first starts from the initial field and needs longer).
// The scene grows the undeformed reference (growth.reference_update: keep; its file says why).
TEST(GrowthCaseC, GrowsMoreDownstreamThanUpstreamAndTheInnerLoopsBecomeStationary) {
  const fs::path dir = fresh_dir("c");
  const auto set = coarse();
  const Captured r = run("cases/coroneo2013/c_shear_quasi_steady.yaml", dir, set);
  ASSERT_EQ(r.rc, 0) << r.err;
  const Mesh mesh = scene_mesh("cases/coroneo2013/c_shear_quasi_steady.yaml", set);
  for (int k : {10, 30, 60}) {
    const auto p = interface_points(dir, k, mesh);
    const auto& gamma = mesh.node_sets.at("biofilm_fluid");
    double upstream = 0, downstream = 0;
    int n_up = 0, n_down = 0;
    // Halves by the nodes' initial x (interface nodes also move sideways along the normal).
    for (size_t i = 0; i < p.size(); ++i) {
      const double x0 = mesh.x[gamma[i]][0];
      if (x0 < -1e-9) upstream += p[i][1] + 3.0, ++n_up;
      if (x0 > 1e-9) downstream += p[i][1] + 3.0, ++n_down;
    }
    ASSERT_EQ(n_up, n_down);
    upstream /= n_up;
    downstream /= n_down;
    // The difference is a few per cent of the rise: well above the solver tolerances (1e-10
    // relative, see case (b)'s mirror symmetry), so the sign is the physics'.
    EXPECT_GT(downstream, upstream * (1 + 1e-3)) << "growth step " << k;
    if (k == 60) {
      std::cout << "case (c), 60 growth steps: mean rise upstream " << upstream
                << " mm, downstream " << downstream << " mm\n";
      EXPECT_GT(upstream, 0.3);  // erosion slows, but does not stop, the growth
    }
  }
  // The wall shear stress written at the interface is the flow's: about mu dv_x/dy = 1.25e-8 on
  // the flat film of step 0 (the case file's estimate; 20 % for the inflow profile's development).
  const auto tau = read_h5_dataset(step_file(dir, 0), "wall_shear_stress");
  const auto gamma = mesh.node_sets.at("biofilm_fluid");
  EXPECT_NEAR(tau[gamma[gamma.size() / 2]], 1.25e-8, 0.2 * 1.25e-8);
  // FSI: the flow drags the soft film downstream. Every interior interface node moves to +x, by
  // far less than the film's 2 mm thickness (E = 1 Pa under tau = 0.0125 Pa: shear strain ~3%,
  // ~60 um; the case file's estimate; the band allows the coarse mesh and the clamped ends).
  const auto d = read_h5_dataset(step_file(dir, 0), "displacement");
  double d_max = 0;
  for (size_t i = 1; i + 1 < gamma.size(); ++i) {
    const double dx = d[3 * gamma[i]];
    if (std::abs(mesh.x[gamma[i]][0]) < 4.5) {
      EXPECT_GT(dx, 0.0) << "interface node " << i;
    }
    d_max = std::max(d_max, std::abs(dx));
  }
  std::cout << "case (c): largest interface displacement at step 0: " << d_max << " mm\n";
  EXPECT_GT(d_max, 1e-3);
  EXPECT_LT(d_max, 0.2);
  std::smatch m;
  ASSERT_TRUE(
      std::regex_search(r.out, m, std::regex("\\(([0-9]+) inner loops met steady_tolerance")))
      << r.out;
  EXPECT_GE(std::stoi(m[1]), 59) << r.out;
  EXPECT_GT(min_quality_in(r.out), 0.5) << r.out;
}

// Case (c) as the paper runs it (c_shear.yaml): each inner step a transient monolithic FSI step
// (dynamic film, ALE fluid) and a transport step on the moving domains, from the steady coupled
// state. On a very coarse mesh and a few steps (the full run is hours, README): the inner loops
// run without a cut step, the growth step moves the interface, the film then moves towards its new
// equilibrium with a non-zero velocity (so u_S and the transport's Phi div u_S term are active),
// and the mesh stays valid.
TEST(GrowthCaseCTransient, InnerLoopsOfTransientFsiStepsRunWithoutCutSteps) {
  const fs::path dir = fresh_dir("c_transient");
  const std::vector<std::string> set = {"mesh.nx=10",         "mesh.blocks.0.ny=2",
                                        "mesh.blocks.1.ny=8", "growth.output_every=1",
                                        "time.steps=4",       "growth.steps=1"};
  const Captured r = run("cases/coroneo2013/c_shear.yaml", dir, set);
  ASSERT_EQ(r.rc, 0) << r.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      r.out, m, std::regex("fsi: ([0-9]+) monolithic solves, .* ([0-9]+) time steps cut;")))
      << r.out;
  // The initial steady solve and 4 inner steps before and after the growth step.
  EXPECT_EQ(std::stoi(m[1]), 9) << r.out;
  EXPECT_EQ(std::stoi(m[2]), 0) << r.out;
  EXPECT_NE(r.out.find("initial steady flow:"), std::string::npos) << r.out;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex("interface moved max ([-0-9.e]+) mm")))
      << r.out;
  EXPECT_GT(std::stod(m[1]), 0.0) << r.out;
  // After the growth step the film starts towards the equilibrium of its grown shape: 4 ms later
  // its velocity is small but far above round-off.
  double speed = 0;
  for (double v : read_h5_dataset(step_file(dir, 1), "structure_velocity"))
    speed = std::max(speed, std::abs(v));
  std::cout << "case (c) transient, coarse: largest film velocity 4 ms after the growth step: "
            << speed << " mm/ms\n";
  EXPECT_GT(speed, 1e-6);
  EXPECT_GT(min_quality_in(r.out), 0.5) << r.out;
}

// Started from the steady coupled state (fields.fluid.initial: steady), the transient inner loop
// stays near it, so the wall shear stress and the flux density it leaves at the interface are the
// quasi-steady run's up to the small drift of the transient scheme from the steady solve's state:
// compared after the first inner loop, on the coarse mesh, as means over the interface nodes.
// Measured after 20 inner steps: sigma 0.75 %, J 2e-6 (the substrate sees the flow only through
// its convective velocity); bounds 3 % and 1e-3. (From rest the same loop leaves sigma 27 times
// too large: docs/known-limits.md.)
TEST(GrowthCaseCTransient, FromTheSteadyStateItsShearAndFluxAreTheQuasiSteadyOnes) {
  const auto set = coarse({"time.steps=20", "growth.steps=1"});
  const fs::path transient = fresh_dir("c_from_steady"), quasi = fresh_dir("c_quasi_steady");
  const Captured a = run("cases/coroneo2013/c_shear.yaml", transient, set);
  ASSERT_EQ(a.rc, 0) << a.err;
  const Captured b = run("cases/coroneo2013/c_shear_quasi_steady.yaml", quasi, set);
  ASSERT_EQ(b.rc, 0) << b.err;
  const Mesh mesh = scene_mesh("cases/coroneo2013/c_shear.yaml", set);
  const auto& gamma = mesh.node_sets.at("biofilm_fluid");
  auto interface_mean = [&](const fs::path& dir, const char* dataset) {
    const auto v = read_h5_dataset(step_file(dir, 0), dataset);
    double sum = 0;
    for (int n : gamma) sum += v[n];
    return sum / gamma.size();
  };
  const double sigma_t = interface_mean(transient, "wall_shear_stress"),
               sigma_q = interface_mean(quasi, "wall_shear_stress"),
               j_t = interface_mean(transient, "flux_density"),
               j_q = interface_mean(quasi, "flux_density");
  std::cout << "case (c) coarse, after the first inner loop: mean sigma transient " << sigma_t
            << ", quasi-steady " << sigma_q << "; mean J " << j_t << ", " << j_q << "\n";
  EXPECT_NEAR(sigma_t, sigma_q, 0.03 * sigma_q);
  EXPECT_NEAR(j_t, j_q, 1e-3 * j_q);
}

// solver.reuse_preconditioner: the transient coupled steps keep their assembled preconditioner
// while it serves. The Jacobian action is exact either way, so the run converges to the same states
// (to the Newton tolerance) with far fewer set-ups. Coarse case (c), 10 inner steps before and
// after one growth step: the interface motion equal in the 6 digits the summary prints (bound 1e-6
// relative); 7 set-ups and 39 reuses, where without reuse every Newton step sets up (bound: 4
// reuses per set-up).
TEST(GrowthCaseCTransient, ReusingThePreconditionerGivesTheSameRun) {
  auto run_with = [](bool reuse) {
    const fs::path dir = fresh_dir(reuse ? "c_reuse" : "c_rebuild");
    const Captured r =
        run("cases/coroneo2013/c_shear.yaml", dir,
            coarse({"time.steps=10", "growth.steps=1",
                    std::string("solver.reuse_preconditioner=") + (reuse ? "true" : "false")}));
    EXPECT_EQ(r.rc, 0) << r.err;
    return r.out;
  };
  const std::string rebuilt = run_with(false), reused = run_with(true);
  std::smatch m;
  const std::regex moved("interface moved max ([-0-9.e]+) mm");
  const std::regex setups("([0-9]+) preconditioner set-ups, ([0-9]+) reused");
  ASSERT_TRUE(std::regex_search(rebuilt, m, moved)) << rebuilt;
  const double a = std::stod(m[1]);
  ASSERT_TRUE(std::regex_search(reused, m, moved)) << reused;
  const double b = std::stod(m[1]);
  ASSERT_TRUE(std::regex_search(reused, m, setups)) << reused;
  std::cout << "case (c) coarse, reused preconditioner: interface motion " << b << " against " << a
            << ", " << m[1] << " set-ups, " << m[2] << " reused\n";
  EXPECT_NEAR(b, a, 1e-6 * a);
  EXPECT_GT(std::stoi(m[2]), 4 * std::stoi(m[1]));
}

namespace {

// Runs `scene` for `steps` growth steps, and again restarted from the first run's checkpoint at
// `restart`; the last step's datasets `names` of both agree to `relative` of their largest value.
void expect_restart_reproduces(const std::string& scene, const std::string& tag, int steps,
                               int restart, const std::vector<const char*>& names,
                               double relative) {
  const fs::path full = fresh_dir(tag + "_full"), resumed = fresh_dir(tag + "_resumed");
  const auto set = coarse({"growth.steps=" + std::to_string(steps)});
  ASSERT_EQ(run(scene, full, set).rc, 0);
  const std::string checkpoint = std::to_string(restart);
  const Captured r =
      run(scene, resumed, set,
          (full / ("checkpoint_" + std::string(6 - checkpoint.size(), '0') + checkpoint + ".h5"))
              .string());
  ASSERT_EQ(r.rc, 0) << r.err;
  for (const char* name : names) {
    const auto a = read_h5_dataset(step_file(full, steps), name);
    const auto b = read_h5_dataset(step_file(resumed, steps), name);
    ASSERT_EQ(a.size(), b.size());
    double diff = 0, scale = 0;
    for (size_t i = 0; i < a.size(); ++i)
      diff = std::max(diff, std::abs(a[i] - b[i])), scale = std::max(scale, std::abs(a[i]));
    EXPECT_LE(diff, relative * scale) << name;
  }
}

}  // namespace

// As for case (b): bitwise-reproducible kernels.
TEST(GrowthRestart, ReproducesTheUninterruptedRunWithFlow) {
  expect_restart_reproduces("cases/coroneo2013/c_shear_quasi_steady.yaml", "c", 4, 2,
                            {"coordinates", "phi", "velocity", "pressure", "displacement"}, 1e-12);
}

// The bound.
TEST(GrowthRestart, ReproducesTheUninterruptedRun) {
  expect_restart_reproduces("cases/coroneo2013/b_cosine.yaml", "b", 6, 3, {"coordinates", "phi"},
                            1e-12);
}

TEST(GrowthLimits, AggressiveGrowthStopsWithAClearMessageAfterWritingTheLastValidState) {
  const fs::path dir = fresh_dir("aggressive");
  // 100 times the calibrated rate: the interface would cross the fluid within a few steps.
  const Captured r = run("cases/coroneo2013/b_cosine.yaml", dir, coarse({"growth.k1=0.035"}));
  EXPECT_EQ(r.rc, 3);
  EXPECT_NE(r.err.find("field 'growth'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("growth step"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("element"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("min_quality"), std::string::npos) << r.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.err, m, std::regex("growth step ([0-9]+)"))) << r.err;
  const int failed = std::stoi(m[1]);
  // The state before the failed step is in the results, readable, with a valid mesh.
  const auto phi = read_h5_dataset(step_file(dir, failed - 1), "phi");
  for (double v : phi) ASSERT_TRUE(std::isfinite(v));
  std::ifstream index(dir / "scalar.xdmf");
  const std::string text((std::istreambuf_iterator<char>(index)), {});
  EXPECT_NE(text.find("scalar_" + std::string(6 - std::to_string(failed - 1).size(), '0') +
                      std::to_string(failed - 1) + ".h5"),
            std::string::npos);
}

TEST(GrowthLimits, AKilledRunLeavesOnlyReadableFiles) {
  const fs::path dir = fresh_dir("killed");
  fs::create_directories(dir);
  // Start the real program, wait until it has written a few growth steps, then SIGKILL it in the
  // middle of its work (no chance to clean up).
  const fs::path pid_file = dir / "pid";
  const std::string start = std::string(BIOFSI_BINARY) + " run " + source_dir +
                            "/cases/coroneo2013/b_cosine.yaml --out " + dir.string() +
                            " --overwrite --set growth.output_every=1 > " +
                            (dir / "log.txt").string() + " 2>&1 & echo $! > " + pid_file.string();
  ASSERT_EQ(std::system(start.c_str()), 0);
  for (int i = 0; i < 1200 && !fs::exists(step_file(dir, 3)); ++i) std::system("sleep 0.1");
  ASSERT_TRUE(fs::exists(step_file(dir, 3))) << "the run did not reach growth step 3 in 120 s";
  std::ifstream pid_in(pid_file);
  std::string pid;
  pid_in >> pid;
  ASSERT_FALSE(pid.empty());
  ASSERT_EQ(std::system(("kill -KILL " + pid).c_str()), 0);  // still running: killed mid-run
  std::system(("while kill -0 " + pid + " 2>/dev/null; do sleep 0.1; done").c_str());
  std::ifstream index(dir / "scalar.xdmf");
  ASSERT_TRUE(index.good());
  const std::string text((std::istreambuf_iterator<char>(index)), {});
  EXPECT_NE(text.find("</Xdmf>"), std::string::npos);  // complete index, never half written
  const std::regex file_re("scalar_[0-9]{6}\\.h5");
  int listed = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), file_re);
       it != std::sregex_iterator(); ++it, ++listed)
    EXPECT_NO_THROW(read_h5_dataset((dir / it->str()).string(), "phi")) << it->str();
  EXPECT_GT(listed, 0);
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".h5") continue;
    const bool checkpoint = e.path().filename().string().rfind("checkpoint", 0) == 0;
    EXPECT_NO_THROW(read_h5_dataset(e.path().string(), checkpoint ? "coordinates" : "phi"))
        << e.path();
  }
}
