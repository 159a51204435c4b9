// Sum factorisation against direct evaluation of the tensor basis, and exactness on trilinear
// fields. Tolerances: these are exact identities in exact arithmetic, so a small multiple of
// machine epsilon (40 eps, STYLE.md 7) relative to the data's magnitude.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "kernels/core/hex8.hpp"

using namespace biofsi;

namespace {
constexpr double eps = std::numeric_limits<double>::epsilon();

double trilinear(double x, double y, double z) {
  return 1.5 - 0.7 * x + 2.1 * y + 0.3 * z + 0.9 * x * y - 1.1 * y * z + 0.4 * x * z +
         2.5 * x * y * z;
}

// Direct (naive) evaluation: sum over all 8 basis functions at each point.
void naive(const double* u, double* val, double (*grad)[3]) {
  for (int q = 0; q < 8; ++q) {
    val[q] = 0;
    for (int d = 0; d < 3; ++d) grad[q][d] = 0;
    for (int a = 0; a < 8; ++a) {
      double n, g[3];
      basis_at_point<Hex8>(a, q, n, g);
      val[q] += n * u[a];
      for (int d = 0; d < 3; ++d) grad[q][d] += g[d] * u[a];
    }
  }
}
}  // namespace

TEST(Hex8Basis, SumFactorisationEqualsNaiveEvaluation) {
  double u[8];
  for (int a = 0; a < 8; ++a) u[a] = std::sin(1.0 + 3.7 * a);
  double v1[8], g1[8][3], v2[8], g2[8][3];
  interpolate_with_gradient<Hex8>(u, v1, g1);
  naive(u, v2, g2);
  for (int q = 0; q < 8; ++q) {
    EXPECT_NEAR(v1[q], v2[q], 40 * eps);
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(g1[q][d], g2[q][d], 40 * eps);
  }
}

TEST(Hex8Basis, TransposeIsAdjointOfInterpolation) {
  // <B u, f> = <u, B^T f> for values and gradients together.
  double u[8], f0[8], f1[8][3];
  for (int a = 0; a < 8; ++a) u[a] = std::cos(0.3 + 1.3 * a);
  for (int q = 0; q < 8; ++q) {
    f0[q] = std::sin(0.1 + q);
    for (int d = 0; d < 3; ++d) f1[q][d] = std::cos(0.7 * q + d);
  }
  double v[8], g[8][3], back[8];
  interpolate_with_gradient<Hex8>(u, v, g);
  integrate_value_and_gradient<Hex8>(f0, f1, back);
  double lhs = 0, rhs = 0;
  for (int q = 0; q < 8; ++q) {
    lhs += v[q] * f0[q];
    for (int d = 0; d < 3; ++d) lhs += g[q][d] * f1[q][d];
  }
  for (int a = 0; a < 8; ++a) rhs += u[a] * back[a];
  EXPECT_NEAR(lhs, rhs, 40 * eps * (std::abs(lhs) + 1));
}

TEST(Hex8Basis, ReproducesTrilinearFieldsExactlyOnDistortedElement) {
  // A general (non-affine) hexahedron: values of a trilinear function of the *reference*
  // coordinates are reproduced exactly, and physical gradients of a linear function of the
  // physical coordinates are exact on affine maps; check the latter on a sheared affine cell.
  double xe[8][3];
  for (int l = 0; l < 8; ++l) {
    const double xi[3] = {l % 2 ? 1.0 : -1.0, (l / 2) % 2 ? 1.0 : -1.0, l / 4 ? 1.0 : -1.0};
    xe[l][0] = 2.0 + 0.5 * xi[0] + 0.1 * xi[1];
    xe[l][1] = -1.0 + 0.2 * xi[0] + 0.7 * xi[1] + 0.05 * xi[2];
    xe[l][2] = 0.3 + 0.25 * xi[2] - 0.1 * xi[0];
  }
  ElementGeometry<Hex8> geo;
  geo.compute(xe);
  double u[8], uref[8];
  for (int l = 0; l < 8; ++l) {
    u[l] = 3.0 * xe[l][0] - 2.0 * xe[l][1] + 0.5 * xe[l][2];
    const double xi[3] = {l % 2 ? 1.0 : -1.0, (l / 2) % 2 ? 1.0 : -1.0, l / 4 ? 1.0 : -1.0};
    uref[l] = trilinear(xi[0], xi[1], xi[2]);
  }
  double v[8], g[8][3];
  interpolate_with_gradient<Hex8>(u, v, g);
  for (int q = 0; q < 8; ++q) {
    double gp[3];
    physical_gradient(geo.inv[q], g[q], gp);
    EXPECT_NEAR(gp[0], 3.0, 40 * eps * 3);
    EXPECT_NEAR(gp[1], -2.0, 40 * eps * 3);
    EXPECT_NEAR(gp[2], 0.5, 40 * eps * 3);
    EXPECT_NEAR(v[q], 3.0 * geo.x[q][0] - 2.0 * geo.x[q][1] + 0.5 * geo.x[q][2], 40 * eps * 10);
  }
  interpolate_with_gradient<Hex8>(uref, v, g);
  for (int q = 0; q < 8; ++q) {
    const double s = Hex8::point(q % 2), t = Hex8::point((q / 2) % 2), r = Hex8::point(q / 4);
    EXPECT_NEAR(v[q], trilinear(s, t, r), 40 * eps * 10);
  }
}
