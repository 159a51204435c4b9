// Manufactured solution for finite-strain elastostatics on a distorted mesh: the observed order of
// convergence of the displacement in L2 and in the H1 seminorm, for St. Venant-Kirchhoff and
// compressible Neo-Hooke, at strains ~0.1 (so the geometric and material nonlinearity matter).
//
// u(X) is smooth and not polynomial; the body force b = -Div P(I + grad u) is computed on the host
// by central differences of P (evaluated with the kernels' own constitutive functions, which
// test_structure_operator checks against finite differences of the residual) with step 1e-4: its
// error ~1e-8 |P'''| is far below the discretisation errors measured (> 1e-5). Dirichlet data are
// the exact solution on the whole boundary of the unit cube, moved by the boundary-preserving
// distortion of the ALE tests (non-affine elements at every refinement). Errors come from the
// independent host quadrature of scalar/error_norms.hpp (3x3x3 Gauss), per component.
//
// Tolerances, and why: L2 order 2 +- 0.1 and H1 order 1 +- 0.1 (Q1), observed between the last
// two refinements: the requirement for a second-order method in the asymptotic range (the mesh
// sequence shares one distortion map, the solution is smooth). Newton runs to 1e-10 relative, so
// the algebraic error is orders below the finest discretisation error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "scalar/error_norms.hpp"
#include "structure/structure_test_support.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

constexpr double amplitude = 0.1;

double exact(int c, const Point& p) {
  const double x = p[0], y = p[1], z = p[2], a = amplitude;
  if (c == 0) return a * std::sin(1.3 * x + 0.4 * y) * std::cos(0.7 * z);
  if (c == 1) return a * std::cos(0.9 * x - 0.6 * z) * (1 + y * y);
  return a * std::sin(x + 0.5 * y + 0.8 * z);
}

Gradient exact_gradient(int c, const Point& p) {
  const double x = p[0], y = p[1], z = p[2], a = amplitude;
  if (c == 0)
    return {a * 1.3 * std::cos(1.3 * x + 0.4 * y) * std::cos(0.7 * z),
            a * 0.4 * std::cos(1.3 * x + 0.4 * y) * std::cos(0.7 * z),
            -a * 0.7 * std::sin(1.3 * x + 0.4 * y) * std::sin(0.7 * z)};
  if (c == 1)
    return {-a * 0.9 * std::sin(0.9 * x - 0.6 * z) * (1 + y * y),
            a * std::cos(0.9 * x - 0.6 * z) * 2 * y,
            a * 0.6 * std::sin(0.9 * x - 0.6 * z) * (1 + y * y)};
  const double cs = a * std::cos(x + 0.5 * y + 0.8 * z);
  return {cs, 0.5 * cs, 0.8 * cs};
}

// P(X) of the exact solution.
void exact_stress(const MaterialPoint& m, const Point& p, Real pk[3][3]) {
  Real g[3][3];
  for (int c = 0; c < 3; ++c) {
    const Gradient gc = exact_gradient(c, p);
    for (int d = 0; d < 3; ++d) g[c][d] = gc[d];
  }
  first_piola_kirchhoff(m, g, pk);
}

// b_i = -d P_iJ / d X_J by central differences.
double body_force(const MaterialPoint& m, int i, const Point& p) {
  constexpr double h = 1e-4;
  double div = 0;
  for (int j = 0; j < 3; ++j) {
    Point pp = p, pm = p;
    pp[j] += h;
    pm[j] -= h;
    Real sp[3][3], sm[3][3];
    exact_stress(m, pp, sp);
    exact_stress(m, pm, sm);
    div += (sp[i][j] - sm[i][j]) / (2 * h);
  }
  return -div;
}

struct StudyPoint {
  ErrorNorms error;
  int newton = 0;
};

StudyPoint solve_manufactured(StructureModel model, int n) {
  Mesh mesh = box_mesh(n, n, 1.0, {{"solid", 0.0, 1.0, n, 1.0}});
  distort(mesh, [](const Point& p) { return smooth_cube_map(p, 0.06); });
  const StructureMaterial mat = material(model, 1.0, 0.3);
  const MaterialPoint mp{mat.model, mat.lambda, mat.mu};
  StructureSettings s = tight_structure_settings({mat}, true);
  StructureDirichlet bc;
  bc.set = "boundary";
  for (int c = 0; c < 3; ++c) bc.value[c] = [c](const Point& p, double) { return exact(c, p); };
  mesh.node_sets["boundary"] = boundary_nodes(mesh);
  StructureField field(mesh, s, {bc});
  std::array<SpaceTimeFunction, 3> b;
  for (int c = 0; c < 3; ++c)
    b[c] = [mp, c](const Point& p, double) { return body_force(mp, c, p); };
  field.set_body_force(b);
  const NewtonResult r = field.step(1.0, "manufactured n=" + std::to_string(n));
  const auto d = field.displacement();
  StudyPoint out;
  out.newton = r.iterations;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> uc(mesh.n_nodes());
    for (int node = 0; node < mesh.n_nodes(); ++node) uc[node] = d[node][c];
    const ErrorNorms e = error_norms(
        mesh, uc, [c](const Point& p) { return exact(c, p); },
        [c](const Point& p) { return exact_gradient(c, p); });
    out.error.l2 += e.l2 * e.l2;
    out.error.h1 += e.h1 * e.h1;
  }
  out.error.l2 = std::sqrt(out.error.l2);
  out.error.h1 = std::sqrt(out.error.h1);
  return out;
}

void study(StructureModel model, const std::vector<int>& sizes) {
  const char* name = model == SaintVenantKirchhoff ? "St.Venant-Kirchhoff" : "Neo-Hooke";
  std::vector<StudyPoint> pts;
  for (int n : sizes) {
    pts.push_back(solve_manufactured(model, n));
    std::printf("[ measured ] MMS %s n = %d: L2 %.3e, H1 %.3e, Newton %d\n", name, n,
                pts.back().error.l2, pts.back().error.h1, pts.back().newton);
  }
  for (size_t i = 1; i < pts.size(); ++i)
    std::printf("[ measured ] MMS %s order %d->%d: L2 %.3f, H1 %.3f\n", name, sizes[i - 1],
                sizes[i], observed_order(pts[i - 1].error.l2, pts[i].error.l2),
                observed_order(pts[i - 1].error.h1, pts[i].error.h1));
  const size_t k = pts.size() - 1;
  EXPECT_NEAR(observed_order(pts[k - 1].error.l2, pts[k].error.l2), 2.0, 0.1);
  EXPECT_NEAR(observed_order(pts[k - 1].error.h1, pts[k].error.h1), 1.0, 0.1);
}

}  // namespace

#ifndef BIOFSI_STRUCTURE_LONG
TEST(StructureConvergence, ManufacturedSolutionOrdersStVenantKirchhoff) {
  study(SaintVenantKirchhoff, {4, 8, 16});
}
TEST(StructureConvergence, ManufacturedSolutionOrdersNeoHooke) { study(NeoHooke, {4, 8, 16}); }
#else
TEST(StructureConvergenceLong, ManufacturedSolutionOrdersStVenantKirchhoff) {
  study(SaintVenantKirchhoff, {8, 16, 32});
}
TEST(StructureConvergenceLong, ManufacturedSolutionOrdersNeoHooke) { study(NeoHooke, {8, 16, 32}); }
#endif
