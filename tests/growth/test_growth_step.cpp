// The growth law on its own (paper eq. 11): one growth step on a configuration that is 1-D in
// effect moves the interface by exactly dt_bio K1 J along its normal.
#include <gtest/gtest.h>

#include <cmath>

#include "growth/growth.hpp"
#include "scalar/transport.hpp"

using namespace biofsi;

namespace {

// A column: biofilm y in [0, 1] under fluid y in [1, 3], one element in x and z.
Mesh column() {
  BoxSpec s;
  s.x0 = 0, s.x1 = 0.5, s.z0 = 0, s.z1 = 0.5, s.nx = 1, s.nz = 1;
  s.blocks = {{"biofilm", 0, 1, 10, 1.0}, {"fluid", 1, 3, 20, 1.0}};
  return make_box_mesh(s);
}

}  // namespace

TEST(GrowthStep, MovesAOneDimensionalInterfaceByDtBioTimesK1TimesFlux) {
  Mesh mesh = column();
  TransportSettings ts;
  ts.coefficients.diffusivity[0] = 0.5;
  ts.coefficients.monod_rate[0] = 0.05;
  ts.coefficients.monod_half_saturation[0] = 0.1;
  ts.coefficients.diffusivity[1] = 1.0;
  ts.newton.rel_tol = 1e-13;
  ts.newton.abs_tol = 1e-15;
  TransportField field(
      mesh, ts, {{"top", ScalarBcKind::Dirichlet, [](const Point&, double) { return 1.0; }}});
  field.solve_steady("steady");
  const int biofilm = mesh.block_index("biofilm");
  const BoundaryFlux flux = field.boundary_flux("biofilm_fluid", biofilm);
  ASSERT_EQ(flux.density.size(), 4u);
  // 1-D: the same flux density at the four interface nodes (to the solver's tolerance).
  for (double j : flux.density) EXPECT_NEAR(j, flux.density[0], 1e-10 * flux.density[0]);
  EXPECT_GT(flux.density[0], 0);  // substrate flows into the consuming biofilm

  GrowthSettings gs;
  gs.k1 = 3.5e-4;
  gs.dt_bio = 1000;
  const auto before = mesh.x;
  const InterfaceMotion im =
      interface_motion(mesh, gs, flux.density, std::vector<double>(flux.density.size(), 0.0));
  MeshMotion motion(mesh, MeshMotionSettings{});
  grow(mesh, motion, gs, im, "growth step 1");
  for (size_t i = 0; i < im.nodes.size(); ++i) {
    const int n = im.nodes[i];
    const double expected = gs.dt_bio * gs.k1 * flux.density[i];
    // Exact up to the round-off of the normal (unit y) and the mesh-motion solve (1e-10 rel).
    EXPECT_NEAR(mesh.x[n][1] - before[n][1], expected, 1e-12 * (1 + expected));
    EXPECT_NEAR(mesh.x[n][0], before[n][0], 1e-14);
    EXPECT_NEAR(mesh.x[n][2], before[n][2], 1e-14);
  }
  // The substratum and the top do not move.
  for (const char* set : {"bottom", "top"})
    for (int n : mesh.node_sets.at(set))
      for (int c = 0; c < 3; ++c) EXPECT_EQ(mesh.x[n][c], before[n][c]) << set;
}

TEST(GrowthStep, ErosionByShearOpposesGrowth) {
  Mesh mesh = column();
  GrowthSettings gs;
  gs.k1 = 1.0;
  gs.k2 = 2.0;
  gs.dt_bio = 0.1;
  const std::vector<double> j(4, 0.3), sigma(4, 0.25);
  const InterfaceMotion im = interface_motion(mesh, gs, j, sigma);
  for (const auto& d : im.displacement) EXPECT_NEAR(d[1], 0.1 * (0.3 - 0.5), 1e-15);
}

TEST(GrowthStep, InterfaceNodesOnSideWallsSlideAlongThem) {
  BoxSpec s;
  s.x0 = -1, s.x1 = 1, s.z0 = 0, s.z1 = 0.2, s.nx = 4, s.nz = 1;
  s.blocks = {{"biofilm", 0, 1, 2, 1.0}, {"fluid", 1, 2, 2, 1.0}};
  Mesh mesh = make_box_mesh(s);
  // Tilt the interface so its normals at the walls are not vertical.
  for (auto& p : mesh.x)
    if (std::abs(p[1] - 1) < 1e-12) p[1] = 1 + 0.2 * p[0];
  GrowthSettings gs;
  gs.k1 = 1;
  gs.dt_bio = 0.1;
  const auto& nodes = mesh.node_sets.at("biofilm_fluid");
  const InterfaceMotion im = interface_motion(mesh, gs, std::vector<double>(nodes.size(), 1.0),
                                              std::vector<double>(nodes.size(), 0.0));
  for (size_t i = 0; i < nodes.size(); ++i) {
    const Point& p = mesh.x[nodes[i]];
    if (std::abs(std::abs(p[0]) - 1) < 1e-12)
      EXPECT_EQ(im.displacement[i][0], 0.0);
    else
      EXPECT_LT(im.displacement[i][0], 0.0);  // the tilted normal leans towards -x
    EXPECT_EQ(im.displacement[i][2], 0.0);    // front and back walls: pseudo-2-D stays flat
  }
}
