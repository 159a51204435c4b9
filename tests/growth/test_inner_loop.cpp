// The inner loop of a growth run, transport only: growth.inner_loop: fixed_steps runs exactly
// time.steps steps, averaging: window turns a periodic flux into its mean (both end to end,
// through the driver), and over each inner loop of case (b) the substrate balance closes — what
// enters through the boundaries is consumed by the biofilm or stored.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "app/simulation.hpp"
#include "growth/growth.hpp"
#include "io/output.hpp"
#include "io/scene.hpp"
#include "scene_run.hpp"

using namespace biofsi;
namespace fs = std::filesystem;

namespace {

const fs::path kRoot = fs::temp_directory_path() / "biofsi_inner_loop";

// Diffusion only (no Monod consumption), so the transport is linear in its boundary data: a
// substrate that enters at the top and leaves through the biofilm's bottom (phi = 0 there). The
// top value is periodic with a period of 20 inner steps; 100 steps make 5 periods.
const std::string kPeriodicScene = R"yaml(mesh:
  type: box
  x: [-5, 5]
  z: [-0.1, 0.1]
  nx: 2
  nz: 1
  blocks:
    - {name: biofilm, y: [-5, -3], ny: 2}
    - {name: fluid, y: [-3, -1], ny: 4}
materials:
  biofilm: {diffusivity: 0.5}
  fluid: {diffusivity: 1.0}
fields:
  scalar:
    initial: "0"
    boundary_conditions:
      - {boundary: top, type: dirichlet, value: "1 + 0.5*sin(2*pi*t/20)"}
      - {boundary: bottom, type: dirichlet, value: "0"}
time:
  dt: 1.0
  steps: 100
  theta: 0.66
solver:
  newton: {rel_tol: 1.0e-12, abs_tol: 1.0e-15}
  linear: {rel_tol: 1.0e-10}
growth:
  interface: biofilm_fluid
  biofilm_block: biofilm
  k1: 1.0e-3
  dt_bio: 1.0
  steps: 1
  averaging: window
  window: 20
)yaml";

// The flux density J into the biofilm that the first growth step used (written with step 0).
std::vector<double> growth_flux(const std::string& name, const std::vector<std::string>& set) {
  fs::create_directories(kRoot);
  const fs::path scene = kRoot / (name + ".yaml");
  std::ofstream(scene) << kPeriodicScene;
  RunOptions o;
  o.scene_path = scene.string();
  o.out_dir = (kRoot / name).string();
  o.overrides = set;
  o.overwrite = true;
  const test::RunOutput r = test::run_quietly(o);
  EXPECT_EQ(r.rc, 0) << r.err;
  const Mesh mesh = make_scene_mesh(load_scene(scene.string(), set));
  const auto all = read_h5_dataset((kRoot / name / "scalar_000000.h5").string(), "flux_density");
  std::vector<double> j;
  for (int n : mesh.node_sets.at("biofilm_fluid")) j.push_back(all[n]);
  return j;
}

double max_relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double diff = 0, scale = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(b[i]));
  }
  return diff / scale;
}

// Coarse case (b), two growth steps of inner loops of up to 30 steps, with `set` on top.
test::RunOutput run_case_b(const std::string& name, std::vector<std::string> set) {
  std::vector<std::string> all = {"mesh.nx=10", "mesh.blocks.0.ny=2", "mesh.blocks.1.ny=8",
                                  "growth.steps=2", "time.steps=30"};
  all.insert(all.end(), set.begin(), set.end());
  RunOptions o = test::case_run("coroneo2013/b_cosine.yaml", kRoot / name, all);
  o.overwrite = true;
  return test::run_quietly(o);
}

// The inner loop lengths of a run's log, one per growth step ("inner loop N steps (how").
std::vector<std::pair<int, std::string>> inner_loops(const std::string& log) {
  std::vector<std::pair<int, std::string>> out;
  const std::regex line("inner loop ([0-9]+) steps \\(([a-z ]+),");
  for (auto it = std::sregex_iterator(log.begin(), log.end(), line); it != std::sregex_iterator();
       ++it)
    out.push_back({std::stoi((*it)[1]), (*it)[2]});
  return out;
}

}  // namespace

TEST(GrowthInnerLoop, AFixedInnerLoopRunsExactlyTimeStepsStepsEveryGrowthStep) {
  // The stationarity stop at a loose tolerance ends the second loop after a few steps (measured:
  // 30, then 2), so it is visible against the fixed count.
  const auto stopping = run_case_b("until_stationary", {"time.steady_tolerance=1e-3"});
  ASSERT_EQ(stopping.rc, 0) << stopping.err;
  const auto stopped = inner_loops(stopping.out);
  ASSERT_EQ(stopped.size(), 2u) << stopping.out;
  EXPECT_LT(stopped[1].first, 30) << stopping.out;
  EXPECT_EQ(stopped[1].second, "stationary");

  const auto fixed =
      run_case_b("fixed", {"time.steady_tolerance=0", "growth.inner_loop=fixed_steps"});
  ASSERT_EQ(fixed.rc, 0) << fixed.err;
  const auto loops = inner_loops(fixed.out);
  ASSERT_EQ(loops.size(), 2u) << fixed.out;  // one line per growth step, for the loop before it
  for (const auto& [steps, how] : loops) {
    EXPECT_EQ(steps, 30);
    EXPECT_EQ(how, "fixed");
  }
  // The loops before both growth steps and after the last: 3 x 30.
  EXPECT_NE(fixed.out.find("growth: 2 growth steps, 90 inner steps (inner_loop fixed_steps: 30 "
                           "per loop)"),
            std::string::npos)
      << fixed.out;
}

// The one-step-theta scheme is linear here, so over a whole period of its periodic state the mean
// of phi solves the steady problem with the mean top value 1 (the storage terms telescope), and J,
// linear in phi, averages to the flux of that steady problem: the flux of the same loop with the
// constant top value 1, once both have forgotten their start.
TEST(GrowthInnerLoop, WindowAveragingOfAPeriodicFluxGivesItsMean) {
  const auto mean = growth_flux("constant", {"fields.scalar.boundary_conditions.0.value=1"});
  const auto window = growth_flux("window", {});
  const auto last = growth_flux("last", {"growth.averaging=stationary"});
  const double window_error = max_relative_difference(window, mean);
  const double last_error = max_relative_difference(last, mean);
  std::printf(
      "[ measured ] J over the last period against the mean flux: %.2e; the last step's "
      "J: %.2e\n",
      window_error, last_error);
  // The start decays as exp(-lambda t) with lambda ~ D pi^2 / L^2 ~ 0.4 / ms (L = 4 mm, D ~ 0.7),
  // far below 1e-12 after 100 ms; Newton and Krylov are run to 1e-12 and 1e-10 relative.
  EXPECT_LT(window_error, 1e-8);
  // The last step's J swings with the top value; 1e-3 is far above the window's error and far
  // below the swing (an attenuated ~0.5 modulation).
  EXPECT_GT(last_error, 1e-3);
}

namespace {

// Case (b) (cosine source on top, Monod consumption in the biofilm), coarse.
Scene coarse_case_b(std::vector<std::string> more) {
  std::vector<std::string> set = {"mesh.nx=10",
                                  "mesh.blocks.0.ny=2",
                                  "mesh.blocks.1.ny=8",
                                  "time.steps=30",
                                  "time.steady_tolerance=0",
                                  "solver.newton.rel_tol=1e-12",
                                  "solver.newton.abs_tol=1e-15",
                                  "solver.linear.rel_tol=1e-10"};
  set.insert(set.end(), more.begin(), more.end());
  return load_scene(std::string(BIOFSI_SOURCE_DIR) + "/cases/coroneo2013/b_cosine.yaml", set);
}

struct Balance {
  double inflow = 0;    // through the top, summed over the steps (times dt)
  double consumed = 0;  // the Monod reaction, one-step-theta weighted, times dt
  double stored = 0;    // change of the integral of phi
  double bound = 0;     // the algebraic solver's share: sum of dt sqrt(N) |r_final|
};

// One inner loop as the driver runs it (no flow: the scalar's steps), with its balance.
Balance inner_loop_balance(Simulation& sim) {
  const Scene& scene = sim.scene;
  const double dt = scene.time.dt, theta = scene.time.theta;
  Balance b;
  const double m0 = sim.scalar.integral();
  double r_old = sim.scalar.reaction_integral();
  for (int i = 1; i <= scene.time.steps; ++i) {
    const NewtonResult res = sim.scalar.step(dt, "inner step " + std::to_string(i));
    EXPECT_TRUE(res.converged);
    const double r = sim.scalar.reaction_integral();
    b.inflow += dt * sim.scalar.boundary_flux("top", -1).total;
    b.consumed += dt * (theta * r + (1 - theta) * r_old);
    b.bound +=
        dt * std::sqrt(static_cast<double>(sim.mesh.n_nodes())) * res.residual_history.back();
    r_old = r;
  }
  b.stored = sim.scalar.integral() - m0;
  return b;
}

void expect_closed(const Balance& b, const std::string& which) {
  const double defect = b.inflow - b.consumed - b.stored;
  const double scale = std::abs(b.inflow) + std::abs(b.consumed) + std::abs(b.stored);
  std::printf(
      "[ measured ] %s: inflow %.6e = consumed %.6e + stored %.6e, defect %.2e "
      "(solver bound %.2e)\n",
      which.c_str(), b.inflow, b.consumed, b.stored, defect, b.bound);
  // The storage is not small against the consumption: the loop starts far from stationary.
  EXPECT_GT(std::abs(b.stored), 1e-3 * b.consumed) << which;
  // The shape functions sum to one, so summed over all nodes the converged residual leaves
  // exactly storage + consumption - boundary reaction; what remains is the algebraic solver's
  // residual (bounded by sqrt(N) |r| per step, Cauchy-Schwarz) plus summation round-off.
  EXPECT_LE(std::abs(defect), b.bound + 1e-12 * scale) << which;
}

}  // namespace

TEST(GrowthInnerLoop, SubstrateEnteringAtTheTopIsConsumedOrStoredOverEachInnerLoop) {
  const Scene scene = coarse_case_b({});
  Simulation sim(scene);
  expect_closed(inner_loop_balance(sim), "first inner loop");
  // A growth step (as the driver takes it) moves the mesh with the concentration on its nodes;
  // the next loop starts from there.
  const GrowthSettings& gs = scene.growth.settings;
  const int biofilm = sim.mesh.block_index(scene.growth.biofilm_block);
  const auto flux = sim.scalar.boundary_flux(gs.interface_set, biofilm).density;
  MeshMotion motion(sim.mesh, gs.mesh_motion);
  Mesh grown = sim.growth_configuration(scene.growth.reference_update);
  const InterfaceMotion im =
      interface_motion(grown, gs, flux, std::vector<double>(flux.size(), 0.0));
  grow(grown, motion, gs, im, "growth step 1");
  sim.take_grown_reference(grown, scene.growth.reference_update);
  expect_closed(inner_loop_balance(sim), "inner loop after a growth step");
}
