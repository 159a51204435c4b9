// sigma in eq. 11 is the fluid's wall shear stress on the interface. Simple shear (Couette) flow
// u = (g y, 0, 0), p = const is in the Q1-Q1 space and makes every stabilisation residual vanish,
// so the discrete solution is exact on any mesh and the consistent wall shear stress must be
// mu g at every interface node, however the elements next to the wall are shaped.
#include <gtest/gtest.h>

#include <cmath>

#include "fluid/fluid.hpp"

using namespace biofsi;

namespace {

// Biofilm y in [-1, 0] under fluid y in [0, 1]; interior nodes moved by a smooth map that keeps
// the interface y = 0 and the outer walls in place (x moves along the interface too).
Mesh distorted_two_block_box(double amplitude) {
  BoxSpec s;
  s.x0 = 0, s.x1 = 2, s.z0 = 0, s.z1 = 0.1, s.nx = 16, s.nz = 1;
  s.blocks = {{"biofilm", -1, 0, 4, 1.0}, {"fluid", 0, 1, 8, 1.0}};
  Mesh m = make_box_mesh(s);
  const double pi = 3.14159265358979323846;
  distort(m, [&](const Point& p) {
    const double bx = std::sin(pi * p[0] / 2), by = std::sin(pi * p[1]);
    return Point{p[0] + amplitude * bx * std::sin(pi * (p[1] + 1)) * 0.5 + 0.3 * amplitude * bx,
                 p[1] + amplitude * by * std::sin(2 * pi * p[0] / 2 + 0.3), p[2]};
  });
  // Keep the outer walls straight: the map above moves x at y = +-1 and the ends; undo there.
  for (int n : m.node_sets.at("left")) m.x[n][0] = 0;
  for (int n : m.node_sets.at("right")) m.x[n][0] = 2;
  return m;
}

// A pressure level p0 >> mu g: any pressure force that leaks into the shear shows.
constexpr double p0 = 1e-6;

double max_shear_error(double density, double amplitude) {
  const Mesh mesh = distorted_two_block_box(amplitude);
  const double g = 0.0125, mu = 1e-6;
  FluidSettings s;
  s.density = density;
  s.viscosity = mu;
  s.pseudo_2d = true;
  s.blocks = {"fluid"};
  s.preconditioner = FluidPreconditioner::Simple;
  auto shear = [g](const Point& x, double) { return g * x[1]; };
  auto zero = [](const Point&, double) { return 0.0; };
  FluidField fluid(
      mesh, s,
      {fluid_velocity("fluid_left", shear, zero, zero),
       fluid_velocity("fluid_right", shear, zero, zero), fluid_velocity("top", shear, zero, zero),
       fluid_no_slip("biofilm_fluid"), fluid_pressure("top", zero)});
  fluid.solve_steady("couette");
  const auto tau = fluid.wall_shear_stress("biofilm_fluid");
  double err = 0;
  for (const auto& t : tau)
    err = std::max(err, std::hypot(std::abs(t[0]) - mu * g, t[1]) / (mu * g));
  return err;
}

}  // namespace

TEST(WallShear, IsMuTimesTheShearRateOfCouetteFlowOnAFlatMesh) {
  // 1e-6 relative: the Newton tolerance (1e-10 relative on residuals of size rho u^2 ~ 1e-7)
  // leaves that much in the reaction.
  EXPECT_LT(max_shear_error(1e-3, 0.0), 1e-6);
}

TEST(WallShear, IsMuTimesTheShearRateOfCouetteFlowOnADistortedMesh) {
  // 1e-5 relative: on the distorted mesh the linear solves' tolerance leaves 2-4e-6 (measured);
  // a wrong normal or a missing term would be O(1) (a 0.15 distortion tilts elements by ~25 deg).
  EXPECT_LT(max_shear_error(1e-6, 0.15), 1e-5);  // Stokes limit
  EXPECT_LT(max_shear_error(1e-3, 0.15), 1e-5);  // the case (c) fluid, Re ~ 800
}
