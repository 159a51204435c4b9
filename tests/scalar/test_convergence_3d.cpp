// The convergence study of test_convergence.cpp in full 3-D, on cubes of hex8 elements distorted
// in all three directions, for a steady convection-diffusion-reaction problem with Monod kinetics
// and SUPG: 8^3, 16^3 and 32^3 elements in test_scalar (a few seconds), 16^3, 32^3 and 64^3 in
// test_scalar_long (ctest label "long", built with BIOFSI_SCALAR_LONG).
//
// Tolerances: orders within 0.1 of theory (L2 2, H1-seminorm 1), the requirement (see
// test_convergence.cpp for why that margin is meaningful).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "scalar/error_norms.hpp"
#include "scalar/scalar_test_support.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

constexpr double D = 0.1, k = 1.5, K = 0.4;

// u = 2 + sin(2x + 1) cos(1.5y) cos(z + 0.3) (in [1, 3]); c smooth and fully 3-D.
double u_exact(const Point& p) {
  return 2 + std::sin(2 * p[0] + 1) * std::cos(1.5 * p[1]) * std::cos(p[2] + 0.3);
}
Gradient grad_exact(const Point& p) {
  const double sx = std::sin(2 * p[0] + 1), cx = std::cos(2 * p[0] + 1);
  const double sy = std::sin(1.5 * p[1]), cy = std::cos(1.5 * p[1]);
  const double sz = std::sin(p[2] + 0.3), cz = std::cos(p[2] + 0.3);
  return {2 * cx * cy * cz, -1.5 * sx * sy * cz, -sx * cy * sz};
}
Point velocity(const Point& p) {
  return {1 + 0.3 * std::sin(3 * p[1]), 0.5 * std::cos(2 * p[2]), 0.4 * std::sin(2 * p[0])};
}
double source(const Point& p) {
  const double lap = -(4 + 2.25 + 1) * (u_exact(p) - 2);
  const Gradient g = grad_exact(p);
  const Point c = velocity(p);
  const double u = u_exact(p);
  return -D * lap + c[0] * g[0] + c[1] * g[1] + c[2] * g[2] + k * u / (K + u);
}

ErrorNorms solve(int n) {
  BoxSpec spec;
  spec.nx = spec.nz = n;
  spec.blocks = {{"biofilm", 0.0, 1.0, n, 1.0}};
  Mesh mesh = make_box_mesh(spec);
  // Each coordinate moves by a smooth function that vanishes on its own two faces, so the cube's
  // faces stay on their planes; all elements are non-affine.
  distort(mesh, [](const Point& p) {
    const double sx = std::sin(pi * p[0]), sy = std::sin(pi * p[1]), sz = std::sin(pi * p[2]);
    return Point{p[0] + 0.06 * sx * std::cos(pi * p[1]) * std::cos(0.5 * pi * p[2]),
                 p[1] + 0.06 * sy * std::sin(pi * p[2] + 0.4) * std::cos(0.5 * pi * p[0]),
                 p[2] + 0.06 * sz * std::sin(pi * p[0] + 0.8) * std::cos(0.5 * pi * p[1])};
  });
  TransportSettings s = tight_settings();
  s.coefficients.diffusivity[0] = D;
  s.coefficients.monod_rate[0] = k;
  s.coefficients.monod_half_saturation[0] = K;
  const SpaceTimeFunction exact = [](const Point& p, double) { return u_exact(p); };
  TransportField field(mesh, s,
                       dirichlet_on({"left", "right", "bottom", "top", "front", "back"}, exact));
  field.set_initial([](const Point&, double) { return 2.0; }, 0.0);
  field.set_convective_velocity(nodal_vectors(mesh, velocity));
  field.set_source([](const Point& p, double) { return source(p); });
  EXPECT_TRUE(field.solve_steady("3-D n=" + std::to_string(n)).converged);
  return error_norms(field.mesh(), field.solution_host(), u_exact, grad_exact);
}

}  // namespace

#ifdef BIOFSI_SCALAR_LONG
TEST(ScalarTransportLong, ConvectionDiffusionMonodConvergesAtSecondOrderInL2AndFirstInH1In3D) {
  const std::vector<int> n = {16, 32, 64};
#else
TEST(ScalarTransport, ConvectionDiffusionMonodConvergesAtSecondOrderInL2AndFirstInH1In3D) {
  const std::vector<int> n = {8, 16, 32};
#endif
  std::vector<ErrorNorms> e;
  std::printf("[ measured ] 3-D convection-diffusion-Monod, SUPG, distorted cube\n");
  for (size_t i = 0; i < n.size(); ++i) {
    e.push_back(solve(n[i]));
    std::printf("[ measured ]   n = %3d  L2 = %.4e  H1 = %.4e", n[i], e[i].l2, e[i].h1);
    if (i > 0)
      std::printf("  order L2 = %.3f  H1 = %.3f", observed_order(e[i - 1].l2, e[i].l2),
                  observed_order(e[i - 1].h1, e[i].h1));
    std::printf("\n");
  }
  EXPECT_NEAR(observed_order(e[1].l2, e[2].l2), 2.0, 0.1);
  EXPECT_NEAR(observed_order(e[1].h1, e[2].h1), 1.0, 0.1);
}
