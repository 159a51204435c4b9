// Growth of 3-D colonies on Gmsh hexahedral meshes: a hemispherical colony on the floor in a
// hemispherical fluid shell (cases/meshes/hemisphere.geo), whose flux density converges to the
// spherical Monod solution and which grows and stays a hemisphere, and the shipped channel scene
// (cases/colonies/channel3d.yaml), whose colonies grow more on the side the flow comes from.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <regex>

#include "colony_support.hpp"
#include "growth/growth.hpp"
#include "io/output.hpp"
#include "io/scene.hpp"
#include "mesh/gmsh.hpp"
#include "scalar/transport.hpp"
#include "scene_run.hpp"

using namespace biofsi;
using colony::kBiofilmDiffusivity, colony::kMonodRate, colony::kHalfSaturation,
    colony::kFluidDiffusivity, colony::monod_settings, colony::steady_flux_into_colony;

namespace {

constexpr double kOuterRadius = 3.0;  // hemisphere.geo's outer sphere

// The hemisphere in its shell, interface cut to the biofilm side. Its floor has no condition: zero
// flux, the symmetry plane of the whole ball.
Mesh hemisphere(double refine) {
  Mesh mesh = mesh_geo_with_gmsh(std::string(BIOFSI_SOURCE_DIR) + "/cases/meshes/hemisphere.geo",
                                 {{"refine", refine}}, 0);
  const std::string error = orient_interface(mesh, "biofilm_fluid", mesh.block_index("biofilm"));
  if (!error.empty()) throw std::logic_error(error);
  return mesh;
}

double radius(const Point& p) { return std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]); }

double min_scaled_jacobian(const Mesh& mesh) {
  const auto q = scaled_jacobians(mesh);
  return *std::min_element(q.begin(), q.end());
}

struct FluxErrors {
  double worst_node;  // the largest relative deviation of a node's flux density
  double total;       // of the total flux into the colony from 2 pi J(1)
};

FluxErrors flux_errors(double refine) {
  const Mesh mesh = hemisphere(refine);
  const BoundaryFlux flux = steady_flux_into_colony(mesh);
  colony::RadialMonod ode{kBiofilmDiffusivity, kMonodRate, kHalfSaturation, kFluidDiffusivity,
                          kOuterRadius};
  ode.dimension = 3;
  const double reference = ode.interface_flux_density(), pi = std::acos(-1.0);
  FluxErrors e{0, std::abs(flux.total - 2 * pi * reference) / (2 * pi * reference)};
  for (double j : flux.density)
    e.worst_node = std::max(e.worst_node, std::abs(j - reference) / reference);
  return e;
}

}  // namespace

// Reference: the spherical ODE to round-off (RK4, 20000 steps). Meshes refine 0.5, 1, 2 (4, 8,
// 16 arcs on a quarter of the equator). The total flux into the colony converges at second order
// (Q1 with the consistent reaction flux, DESIGN.md; measured 1.96 and 1.99, 0.42 % at refine 2).
// The worst node is always a corner of the cube-sphere, where three patches meet and the mesh is
// not smooth: there the nodal density converges more slowly (measured 4.2 %, 1.3 %, 0.48 %,
// orders 1.69 and 1.41), so its bounds are the refine-2 value with room for round-off and order 1.
TEST(Colony3d, FluxMatchesTheSphericalMonodSolution) {
  const FluxErrors e1 = flux_errors(0.5), e2 = flux_errors(1), e4 = flux_errors(2);
  std::cout << "hemisphere flux error refine 0.5, 1, 2: total " << e1.total << " " << e2.total
            << " " << e4.total << " (orders " << std::log2(e1.total / e2.total) << " "
            << std::log2(e2.total / e4.total) << "), worst node " << e1.worst_node << " "
            << e2.worst_node << " " << e4.worst_node << " (orders "
            << std::log2(e1.worst_node / e2.worst_node) << " "
            << std::log2(e2.worst_node / e4.worst_node) << ")\n";
  EXPECT_LT(e4.total, 5e-3);
  EXPECT_GT(std::log2(e1.total / e2.total), 1.9);
  EXPECT_GT(std::log2(e2.total / e4.total), 1.9);
  EXPECT_LT(e4.worst_node, 6e-3);
  EXPECT_GT(std::log2(e1.worst_node / e2.worst_node), 1.0);
  EXPECT_GT(std::log2(e2.worst_node / e4.worst_node), 1.0);
}

// Ten growth steps, each on the steady substrate of the moved mesh, the floor a sliding wall.
TEST(Colony3d, AHemisphereWithoutFlowGrowsSymmetrically) {
  Mesh mesh = hemisphere(1);
  GrowthSettings gs;
  gs.k1 = 2e-3;
  gs.dt_bio = 200;
  gs.mesh_motion.fixed_walls = {"outer"};
  gs.mesh_motion.sliding_walls = {"floor"};
  MeshMotion motion(mesh, gs.mesh_motion);
  colony::grow_on_steady_substrate(mesh, motion, gs, 10);
  const auto [mean, spread] = colony::roundness(mesh, radius);
  const auto& floor = mesh.node_sets.at("floor");
  int on_floor = 0;
  for (int n : mesh.node_sets.at("biofilm_fluid"))
    if (position_in_sorted(floor, n) >= 0) {
      EXPECT_EQ(mesh.x[n][2], 0.0);  // the rim slid along the floor
      ++on_floor;
    }
  const double quality = min_scaled_jacobian(mesh);
  std::cout << "hemisphere after 10 growth steps: mean radius " << mean << ", relative spread "
            << spread << ", smallest scaled Jacobian " << quality << "\n";
  EXPECT_GT(on_floor, 0);
  EXPECT_GT(mean, 1.05);
  EXPECT_LT(spread, 1e-3);
  EXPECT_GT(quality, 0.3);
}

namespace {

// The shipped channel scene on its coarse mesh (refine 1), two growth steps.
struct ChannelRun {
  Mesh mesh;                   // as read, before growth
  std::vector<double> x0, x2;  // node coordinates before and after the two steps
  test::RunOutput run;
};

ChannelRun run_channel() {
  const std::vector<std::string> overrides = {"mesh.parameters.refine=1", "growth.steps=2"};
  const auto out = test::scratch_dir("colony_channel3d");
  ChannelRun r;
  r.run = test::run_quietly(test::case_run("colonies/channel3d.yaml", out, overrides));
  r.mesh = make_scene_mesh(
      load_scene(std::string(BIOFSI_SOURCE_DIR) + "/cases/colonies/channel3d.yaml", overrides));
  if (r.run.rc == 0) {
    r.x0 = read_h5_dataset((out / "scalar_000000.h5").string(), "coordinates");
    r.x2 = read_h5_dataset((out / "scalar_000002.h5").string(), "coordinates");
  }
  return r;
}

// How far an interface node moved away from its colony's centre (xc, 0, 0).
double outward(const ChannelRun& r, int n, double xc) {
  auto distance = [&](const std::vector<double>& x) {
    return std::sqrt(std::pow(x[3 * n] - xc, 2) + std::pow(x[3 * n + 1], 2) +
                     std::pow(x[3 * n + 2], 2));
  };
  return distance(r.x2) - distance(r.x0);
}

}  // namespace

// The flow comes from -x. A colony's upstream side sees fresh substrate in a thin boundary layer,
// its lee the depleted wake, so it grows more upstream: measured 0.0800 mm against 0.0684 mm (the
// mean outward motion of the nodes with x < -0.5 and x > 0.5) over two steps; bound 1.1 times.
// (The third colony, as large as the first, grows only 0.1 % less on average: the flow
// replenishes the substrate the colonies before it take.) The channel is symmetric in y, so a
// node and its mirror image move alike to the solvers' tolerances (measured 1.6e-11 mm; bound
// 1e-6 of the largest motion). The summary reports the mesh quality after the moves (0.55).
TEST(Colony3d, ChannelColoniesGrowMoreUpstreamThanInTheirLee) {
  const ChannelRun r = run_channel();
  ASSERT_EQ(r.run.rc, 0) << r.run.out << r.run.err;
  const auto& nodes = r.mesh.node_sets.at("biofilm_fluid");
  double upstream = 0, lee = 0, first = 0, third = 0, mirror = 0, largest = 0;
  int n_up = 0, n_lee = 0, n_first = 0, n_third = 0;  // first and third: whole colonies
  for (int n : nodes) {
    const Point& p = r.mesh.x[n];
    if (std::abs(p[0]) < 1.5) {  // the first colony, radius 1 at x = 0
      const double d = outward(r, n, 0.0);
      first += d, ++n_first;
      largest = std::max(largest, d);
      if (p[0] < -0.5) upstream += d, ++n_up;
      if (p[0] > 0.5) lee += d, ++n_lee;
      for (int m : nodes) {
        const Point& q = r.mesh.x[m];
        if (std::abs(q[0] - p[0]) + std::abs(q[1] + p[1]) + std::abs(q[2] - p[2]) < 1e-9)
          mirror = std::max(mirror, std::abs(outward(r, m, 0.0) - d));
      }
    }
    if (std::abs(p[0] - 10) < 1.5) third += outward(r, n, 10.0), ++n_third;
  }
  upstream /= n_up, lee /= n_lee, first /= n_first, third /= n_third;
  std::smatch m;
  const std::regex quality(R"(mesh quality \(scaled Jacobian\) over the run: \[([-0-9.e]+),)");
  ASSERT_TRUE(std::regex_search(r.run.out, m, quality)) << r.run.out;
  std::cout << "first colony: moved out " << upstream << " upstream, " << lee
            << " in its lee; mean " << first << ", third colony " << third << "; mirror difference "
            << mirror << "; smallest scaled Jacobian " << m[1] << "\n";
  EXPECT_GT(lee, 0);
  EXPECT_GT(upstream, 1.1 * lee);
  EXPECT_LT(mirror, 1e-6 * largest);
  EXPECT_GT(std::stod(m[1]), 0.3);
}
