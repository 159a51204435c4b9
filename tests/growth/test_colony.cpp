// Growth on a curved, closed interface read as Gmsh lists it (once per side): a circular colony in
// a circular fluid domain (colony_support.hpp). The interface is taken from the biofilm side; the
// flux density on it converges to the radial Monod solution; the colony grows and stays round.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>

#include "app/report.hpp"
#include "colony_support.hpp"
#include "growth/growth.hpp"
#include "io/output.hpp"
#include "io/scene.hpp"
#include "scalar/transport.hpp"
#include "scene_run.hpp"

using namespace biofsi;
using colony::kBiofilmDiffusivity, colony::kMonodRate, colony::kHalfSaturation,
    colony::kFluidDiffusivity, colony::monod_settings, colony::steady_flux_into_colony;

namespace {

colony::DiscSpec disc_spec(int n) {
  colony::DiscSpec s;
  s.n = n;
  s.n_ring = n / 2;
  s.n_fluid = n;
  return s;
}

double radial_reference(double r_outer) {
  const colony::RadialMonod ode{kBiofilmDiffusivity, kMonodRate, kHalfSaturation, kFluidDiffusivity,
                                r_outer};
  return ode.interface_flux_density();
}

double radius(const Point& p) { return std::hypot(p[0], p[1]); }

// The largest relative deviation of the flux density on the circle from the reference.
double flux_error(const colony::DiscSpec& spec) {
  Mesh mesh = colony::disc_in_annulus(spec);
  EXPECT_EQ(orient_interface(mesh, "biofilm_fluid", mesh.block_index("biofilm")), "");
  const BoundaryFlux flux = steady_flux_into_colony(mesh);
  const double reference = radial_reference(spec.r_outer);
  double worst = 0;
  for (double j : flux.density) worst = std::max(worst, std::abs(j - reference) / reference);
  return worst;
}

// 2-D area of a block of an extruded mesh: the shoelace area of its elements' bottom faces.
double block_area(const Mesh& mesh, int block) {
  double area = 0;
  for (int e : mesh.elements_of_block(block)) {
    const auto& c = mesh.conn[e];
    for (int k = 0; k < 4; ++k) {
      const Point &p = mesh.x[c[k]], &q = mesh.x[c[(k + 1) % 4]];
      area += 0.5 * (p[0] * q[1] - q[0] * p[1]);
    }
  }
  return area;
}

MeshMotionSettings colony_mesh_motion() {
  MeshMotionSettings m;
  m.fixed_walls = {"outer"};
  m.sliding_walls = {"front", "back"};
  return m;
}

GrowthSettings colony_growth(double dt_bio) {
  GrowthSettings g;
  g.k1 = 2e-3;
  g.dt_bio = dt_bio;
  g.mesh_motion = colony_mesh_motion();
  return g;
}

}  // namespace

TEST(ColonyInterface, IsTakenFromTheBiofilmSideWithNormalsIntoTheFluid) {
  Mesh mesh = colony::disc_in_annulus(disc_spec(4));
  const int biofilm = mesh.block_index("biofilm");
  const size_t both_sides = mesh.face_sets.at("biofilm_fluid").size();
  EXPECT_TRUE(lists_both_sides(mesh, "biofilm_fluid"));
  ASSERT_EQ(orient_interface(mesh, "biofilm_fluid", biofilm), "");
  EXPECT_EQ(2 * mesh.face_sets.at("biofilm_fluid").size(), both_sides);
  EXPECT_FALSE(lists_both_sides(mesh, "biofilm_fluid"));
  const auto& nodes = mesh.node_sets.at("biofilm_fluid");
  const auto normals = nodal_normals(mesh, "biofilm_fluid");
  for (size_t i = 0; i < nodes.size(); ++i) {
    const Point& p = mesh.x[nodes[i]];
    // The circle's nodes are equally spaced, so each nodal normal is radial up to round-off.
    EXPECT_NEAR(normals[i][0], p[0] / radius(p), 1e-12);
    EXPECT_NEAR(normals[i][1], p[1] / radius(p), 1e-12);
  }
}

// The summary's flux through an interface listed once per side goes into the block the set's name
// begins with, and its density divides by that side's area alone: the same as on the set cut to
// the biofilm side (to round-off: the same residual, the same faces).
TEST(ColonyInterface, ListedOncePerSideReportsItsFluxIntoTheBlockItsNameBeginsWith) {
  const Mesh both = colony::disc_in_annulus(disc_spec(4));
  const int biofilm = both.block_index("biofilm");
  EXPECT_EQ(flux_block(both, "biofilm_fluid"), biofilm);
  EXPECT_EQ(flux_block(both, "outer"), both.block_index("fluid"));
  Mesh one_side = both;
  ASSERT_EQ(orient_interface(one_side, "biofilm_fluid", biofilm), "");
  const BoundaryFlux a = steady_flux_into_colony(both), b = steady_flux_into_colony(one_side);
  ASSERT_EQ(a.density.size(), b.density.size());
  for (size_t i = 0; i < a.density.size(); ++i) EXPECT_NEAR(a.density[i], b.density[i], 1e-12);
  EXPECT_GT(a.total, 0);
  // A box's side wall spans both blocks but is no interface: its flux is the domain's.
  BoxSpec box;
  box.blocks = {{"biofilm", 0, 1, 2, 1.0}, {"fluid", 1, 2, 2, 1.0}};
  const Mesh stacked = make_box_mesh(box);
  EXPECT_EQ(flux_block(stacked, "left"), -1);
  EXPECT_EQ(flux_block(stacked, "biofilm_fluid"), stacked.block_index("biofilm"));
}

TEST(ColonyInterface, WithoutBiofilmFacesOrWithCancellingNormalsIsRefused) {
  Mesh mesh = colony::disc_in_annulus(disc_spec(4));
  const std::string outer = orient_interface(mesh, "outer", mesh.block_index("biofilm"));
  EXPECT_NE(outer.find("no face of a 'biofilm' element"), std::string::npos) << outer;
  // Both sides of the circle in one block: the normals cancel at every node.
  Mesh one_block = colony::disc_in_annulus(disc_spec(4));
  std::fill(one_block.element_block.begin(), one_block.element_block.end(), 0);
  const std::string cancel = orient_interface(one_block, "biofilm_fluid", 0);
  EXPECT_NE(cancel.find("nearly cancel"), std::string::npos) << cancel;
}

TEST(ColonyInterface, AGmshSceneWhoseInterfaceMissesTheBiofilmIsAnInputError) {
  const std::string scene = std::string(BIOFSI_SOURCE_DIR) + "/cases/colonies/disc.yaml";
  try {
    load_scene(scene, {"growth.interface=outer"});
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    for (const char* part : {"disc.yaml:", "growth.interface", "'outer'", "'biofilm'"})
      EXPECT_NE(what.find(part), std::string::npos) << part << " in: " << what;
  }
}

// Reference: the radial ODE to round-off (RK4 with 20000 steps, error ~1e-15). 0.5 %: the issue's
// accuracy for the test mesh (n = 16, 64 arcs on the circle); measured 0.13 %. The observed order
// of the worst node's error over n = 4, 8, 16 is 2 for Q1 with the reaction flux (DESIGN.md);
// 1.8 leaves room for the pre-asymptotic coarse mesh (measured 1.96 and 1.96).
TEST(ColonyFlux, MatchesTheRadialMonodSolutionAtSecondOrder) {
  const double e4 = flux_error(disc_spec(4)), e8 = flux_error(disc_spec(8)),
               e16 = flux_error(disc_spec(16));
  std::cout << "flux density error n = 4, 8, 16: " << e4 << " " << e8 << " " << e16 << ", orders "
            << std::log2(e4 / e8) << " " << std::log2(e8 / e16) << "\n";
  EXPECT_LT(e16, 5e-3);
  EXPECT_GT(std::log2(e4 / e8), 1.8);
  EXPECT_GT(std::log2(e8 / e16), 1.8);
}

// Ten growth steps, each on the steady substrate of the moved mesh. The radius of every interface
// node is the same to 1e-3 of the mean (the bound): the nodes move along radial normals by
// dt_bio k1 J, and J varies round the circle only by its discretisation error (at most 0.5 % at
// n = 8, ColonyFlux above) of a growth of about 0.02 per step. Measured: 3.2e-4.
TEST(ColonyGrowth, ACircularColonyStaysCircular) {
  Mesh mesh = colony::disc_in_annulus(disc_spec(8));
  const int biofilm = mesh.block_index("biofilm");
  ASSERT_EQ(orient_interface(mesh, "biofilm_fluid", biofilm), "");
  const GrowthSettings gs = colony_growth(200);
  MeshMotion motion(mesh, gs.mesh_motion);
  colony::grow_on_steady_substrate(mesh, motion, gs, 10);
  const auto [mean, spread] = colony::roundness(mesh, radius);
  std::cout << "after 10 growth steps: mean radius " << mean << ", relative spread " << spread
            << "\n";
  EXPECT_GT(mean, 1.1);  // it grew: about 0.02 per step
  EXPECT_LT(spread, 1e-3);
}

// One growth step of dt_bio, dt_bio/2, dt_bio/4 from the same colony and substrate. The area the
// colony gains equals, to first order, the interface integral of the prescribed normal
// displacement dt_bio k1 J n (the displacement interpolated on the interface's faces): the area
// of the polygon is a quadratic in its nodes, so the remainder is the quadratic term alone and
// falls as dt_bio^2 (observed order 2.00; 1.95 allows the round-off of the mesh-motion solve).
// Relative to the integral the remainder is about d / (2 r) for a circle of radius r grown by d:
// 1.1 % at dt_bio/4 (d = 0.022), below 2 %.
TEST(ColonyGrowth, AreaGainIsTheInterfaceIntegralOfTheDisplacementToFirstOrder) {
  Mesh initial = colony::disc_in_annulus(disc_spec(8));
  const int biofilm = initial.block_index("biofilm");
  ASSERT_EQ(orient_interface(initial, "biofilm_fluid", biofilm), "");
  const BoundaryFlux flux = steady_flux_into_colony(initial);
  const auto& nodes = initial.node_sets.at("biofilm_fluid");
  // m_a = sum over the faces at node a of their area vector / 4: the first variation of the
  // volume is sum_a d_a . m_a, and the 2-D area's is that over the thickness.
  std::vector<Point> m(nodes.size(), Point{0, 0, 0});
  for (const auto& f : initial.face_sets.at("biofilm_fluid")) {
    const Point a = face_area_vector(initial, f);
    for (int k = 0; k < 4; ++k) {
      const int i =
          position_in_sorted(nodes, initial.conn[f.element][hex8_face_nodes[f.local_face][k]]);
      for (int c = 0; c < 3; ++c) m[i][c] += a[c] / 4;
    }
  }
  const double thickness = disc_spec(8).thickness, area0 = block_area(initial, biofilm);
  std::vector<double> remainder;
  MeshMotion motion(initial, colony_mesh_motion());  // it solves on the coordinates it is given
  for (double dt_bio : {1000.0, 500.0, 250.0}) {
    Mesh mesh = initial;
    const GrowthSettings gs = colony_growth(dt_bio);
    const InterfaceMotion im =
        interface_motion(mesh, gs, flux.density, std::vector<double>(nodes.size(), 0.0));
    double integral = 0;
    for (size_t i = 0; i < nodes.size(); ++i)
      for (int c = 0; c < 3; ++c) integral += im.displacement[i][c] * m[i][c] / thickness;
    grow(mesh, motion, gs, im, "growth step");
    const double gain = block_area(mesh, biofilm) - area0;
    std::cout << "dt_bio " << dt_bio << ": area gain " << gain << ", interface integral "
              << integral << "\n";
    EXPECT_GT(integral, 0);
    remainder.push_back(std::abs(gain - integral));
    if (dt_bio == 250.0) {
      EXPECT_LT(remainder.back(), 0.02 * integral);
    }
  }
  EXPECT_GT(std::log2(remainder[0] / remainder[1]), 1.95);
  EXPECT_GT(std::log2(remainder[1] / remainder[2]), 1.95);
}

// The shipped scene, its Gmsh mesh listing the circle once per side: two growth steps (one
// move). The colony's rim moves outward, and the summary reports that motion and the flux into the
// biofilm, which balances its consumption (both 0.0439 at the steady state).
TEST(ColonyScene, DiscGrowsAndReportsTheFluxIntoTheBiofilm) {
  const auto out = test::scratch_dir("colony_disc");
  const test::RunOutput r =
      test::run_quietly(test::case_run("colonies/disc.yaml", out, {"growth.steps=2"}));
  ASSERT_EQ(r.rc, 0) << r.out << r.err;
  const Mesh mesh =
      make_scene_mesh(load_scene(std::string(BIOFSI_SOURCE_DIR) + "/cases/colonies/disc.yaml"));
  auto mean_rim_radius = [&](const char* file) {
    const auto xyz = read_h5_dataset((out / file).string(), "coordinates");
    double sum = 0;
    for (int n : mesh.node_sets.at("biofilm_fluid")) sum += std::hypot(xyz[3 * n], xyz[3 * n + 1]);
    return sum / mesh.node_sets.at("biofilm_fluid").size();
  };
  // 1000 * 2e-3 * J with J = 0.023 in the first step: 0.045 (the scene's header).
  EXPECT_GT(mean_rim_radius("scalar_000002.h5") - mean_rim_radius("scalar_000000.h5"), 0.03);
  std::smatch m;
  const std::regex moved("interface 'biofilm_fluid' moved up to ([-0-9.e]+) mm");
  ASSERT_TRUE(std::regex_search(r.out, m, moved)) << r.out;
  EXPECT_GT(std::stod(m[1]), 0.03);
  const std::regex flux("flux through 'biofilm_fluid' into block 'biofilm': total ([-0-9.e]+)");
  const std::regex consumption("consumption rate ([-0-9.e]+)");
  ASSERT_TRUE(std::regex_search(r.out, m, flux)) << r.out;
  const double into_biofilm = std::stod(m[1]);
  ASSERT_TRUE(std::regex_search(r.out, m, consumption)) << r.out;
  // The inner loop stops at a relative change of 1e-6 per step, so the balance holds to ~1e-4.
  EXPECT_GT(into_biofilm, 0);
  EXPECT_NEAR(into_biofilm, std::stod(m[1]), 1e-3 * into_biofilm);
}

namespace {

colony::DiscSpec on_substratum(int n) {
  colony::DiscSpec s = disc_spec(n);
  s.on_substratum = true;
  return s;
}

}  // namespace

// Half a colony on the substratum y = 0, the interface meeting the wall at a right angle. The
// wall is a symmetry plane of the whole colony (zero flux), so the flux density on the half
// circle, at the rim nodes on the wall too, is the radial solution's: the whole colony's bound
// (0.5 % at 64 arcs on the whole circle; measured 0.13 %, as for the whole colony). Growing, the
// rim nodes slide along the wall (their wall-normal displacement removed) and the half colony
// stays round up to the rim: a rim node's normal, from its one face, leans off the wall by half
// an arc (pi/32 at n = 8), so it moves cos(pi/32) = 0.9952 as far as the others, 0.48 % of the
// growth (0.195): 9.4e-4 of the radius, an O(h^2) effect. Measured spread 9.1e-4; bound 2e-3.
TEST(ColonyOnTheSubstratum, FluxIsTheRadialSolutionAndTheRimSlidesAlongTheWall) {
  EXPECT_LT(flux_error(on_substratum(16)), 5e-3);
  Mesh mesh = colony::disc_in_annulus(on_substratum(8));
  const int biofilm = mesh.block_index("biofilm");
  ASSERT_EQ(orient_interface(mesh, "biofilm_fluid", biofilm), "");
  GrowthSettings gs = colony_growth(200);
  gs.mesh_motion.sliding_walls.push_back("bottom");
  MeshMotion motion(mesh, gs.mesh_motion);
  colony::grow_on_steady_substrate(mesh, motion, gs, 10);
  const auto [mean, spread] = colony::roundness(mesh, radius);
  int on_wall = 0;
  for (int n : mesh.node_sets.at("biofilm_fluid")) {
    const Point& p = mesh.x[n];
    if (position_in_sorted(mesh.node_sets.at("bottom"), n) >= 0) {
      EXPECT_EQ(p[1], 0.0);  // still on the wall
      ++on_wall;
    }
  }
  std::cout << "half colony after 10 growth steps: mean radius " << mean << ", relative spread "
            << spread << "\n";
  EXPECT_EQ(on_wall, 4);  // the two rim nodes, front and back
  EXPECT_GT(mean, 1.1);
  EXPECT_LT(spread, 2e-3);
}
