// Cook's membrane, compressible Neo-Hooke, quasi-static (../shared/reference/benchmarks.md; the
// deal.II code-gallery "Quasi-static finite-strain compressible elasticity" by Pelteret & McBride,
// whose material law kernels/structure implements): the trapezoid (0,0), (48,44), (48,60), (0,44)
// mm, one element (1 mm) thick, left edge clamped, a dead-load vertical traction of 1/16 N/mm^2 on
// the right edge (1 N in total); mu = 422.5 kPa = 0.4225 N/mm^2, nu = 0.3. The mesh is the box
// generator's 48 x 44 rectangle moved by the code-gallery's own bilinear map y -> (1 - y/44)
// (44/48) x + (y/44)(44 + x/3), so the element layout is the reference's.
//
// Out-of-plane constraint: benchmarks.md (and the code gallery's text) say plane strain, but the
// published numbers are those of a one-element-thick slab whose z displacement is free: the code
// marks the z faces by testing the face centre's *x* coordinate against +-0.5, which no face
// matches, so its plane-strain constraint is never applied. Measured here: z free reproduces the
// table to 0.1% at 1 and 2 elements per edge; z held at zero gives values ~4% lower at every
// refinement (13.72 mm at 32). So the published values are compared with z free, and the
// plane-strain variant is checked for convergence and reported.
//
// Tolerance, and why: tip u_y within 1% of the published Q1 value at each refinement (the issue's
// requirement). The published values carry two decimals (a rounding of up to 0.005 mm, 0.1% at
// 5 mm); the formulation is the same (full 2x2x2 Gauss, same energy, same load and constraints),
// so any difference larger than the rounding means a different discrete problem. Newton to 1e-10.
//
// Nearly incompressible, nu = 0.499, plane strain: no published value for these constants, so the
// check is behaviour. With the volumetric term at the element centre (volumetric_integration:
// reduced) the tip converges: each refinement changes it by less than half the previous change
// (measured 7.93, 10.23, 11.09, 11.35 mm at 2, 4, 8, 16 elements per edge, 11.44 at 32: ratios
// ~1/3), while full integration locks (4.92 mm at 8, under half the reduced 11.09; 8.44 at 32).
// At nu = 0.3 both integrations discretise the same problem and converge to one limit: at 16
// within 1.2% of each other (measured 0.8%, 13.577 and 13.688 mm; 13.721 and 13.752 at 32).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "structure/structure_test_support.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

struct CookResult {
  double tip_uy = 0;
  int newton = 0, cut_steps = 0;
};

CookResult cook(int n, bool plane_strain, double nu = 0.3,
                VolumetricIntegration volumetric = VolumetricIntegration::Full) {
  BoxSpec spec;
  spec.x0 = 0;
  spec.x1 = 48;
  spec.z0 = -0.5;
  spec.z1 = 0.5;
  spec.nx = n;
  spec.nz = 1;
  spec.blocks = {{"membrane", 0.0, 44.0, n, 1.0}};
  Mesh mesh = make_box_mesh(spec);
  distort(mesh, [](const Point& p) {
    const double t = p[1] / 44.0;
    return Point{p[0], (1 - t) * (44.0 / 48.0) * p[0] + t * (44.0 + (16.0 / 48.0) * p[0]), p[2]};
  });
  CookResult out;
  int& out_newton = out.newton;
  const double mu = 0.4225;
  StructureMaterial m;
  m.model = NeoHooke;
  m.mu = mu;
  m.lambda = 2 * mu * nu / (1 - 2 * nu);
  StructureSettings s = tight_structure_settings({m}, true);
  s.plane_strain = plane_strain;
  s.volumetric_integration = volumetric;
  // The load ramps linearly over 10 quasi-static steps, as in the reference (its end time 1, step
  // 0.1); the final state of a hyperelastic body does not depend on the path.
  StructureTraction load{
      "right", {constant(0), [](const Point&, double t) { return t / 16.0; }, constant(0)}};
  StructureField field(mesh, s, {clamp("left")}, {load});
  NewtonResult r;
  for (int step = 1; step <= 10; ++step) {
    r = field.step(0.1, "Cook n=" + std::to_string(n) + " load step " + std::to_string(step));
    out_newton += r.iterations;
  }
  const auto d = field.displacement();
  int found = 0;
  for (int i = 0; i < mesh.n_nodes(); ++i)
    if (std::abs(mesh.x[i][0] - 48) < 1e-9 && std::abs(mesh.x[i][1] - 60) < 1e-9) {
      out.tip_uy += d[i][1];
      ++found;
    }
  if (found != 2) throw std::runtime_error("Cook: tip nodes not found");
  out.tip_uy /= found;
  out.cut_steps = field.stats().cut_steps;
  return out;
}

void check(const std::vector<int>& sizes) {
  // Published Q1 tip u_y (mm) per elements per edge (code-gallery README, Pelteret & McBride).
  const std::map<int, double> published{{1, 5.15},   {2, 8.72},   {4, 12.02}, {8, 13.61},
                                        {16, 14.13}, {32, 14.28}, {64, 14.32}};
  for (int n : sizes) {
    const CookResult r = cook(n, false);
    const double ref = published.at(n);
    std::printf(
        "[ measured ] Cook n = %d (z free): tip u_y = %.4f mm, published %.2f (%+.2f%%), "
        "Newton %d over 10 load steps, cut steps %d\n",
        n, r.tip_uy, ref, 100 * (r.tip_uy / ref - 1), r.newton, r.cut_steps);
    EXPECT_NEAR(r.tip_uy, ref, 0.01 * ref) << "n = " << n;
  }
}

}  // namespace

#ifndef BIOFSI_STRUCTURE_LONG
// 16 and 32 elements per edge take minutes (FGMRES needs ~150 iterations per Newton iteration on
// the 1 mm thick slab with its thickness direction free); they run under the long label.
TEST(StructureCook, TipDisplacementMatchesPublishedQ1Values) { check({1, 2, 4, 8}); }

// The plane-strain variant (z held at zero) is stiffer: no published value to compare with, so
// the test asks for a converging sequence (each refinement changes the tip by less than half the
// previous change, the behaviour of an O(h^2) error) and prints it.
TEST(StructureCook, PlaneStrainVariantConverges) {
  std::vector<double> tip;
  for (int n : {4, 8, 16, 32}) {
    tip.push_back(cook(n, true).tip_uy);
    std::printf("[ measured ] Cook n = %d (plane strain): tip u_y = %.4f mm\n", n, tip.back());
  }
  for (size_t i = 2; i < tip.size(); ++i)
    EXPECT_LT(std::abs(tip[i] - tip[i - 1]), 0.5 * std::abs(tip[i - 1] - tip[i - 2]));
}

// Nearly incompressible (nu = 0.499), plane strain, with the volumetric term at the element
// centre: a converging sequence, far from full integration's locked values.
TEST(StructureCook, NearlyIncompressibleWithReducedVolumetricIntegrationConverges) {
  std::vector<double> tip;
  for (int n : {2, 4, 8, 16}) {
    tip.push_back(cook(n, true, 0.499, VolumetricIntegration::Reduced).tip_uy);
    std::printf("[ measured ] Cook n = %d (plane strain, nu = 0.499, reduced): tip u_y = %.4f mm\n",
                n, tip.back());
  }
  for (size_t i = 2; i < tip.size(); ++i)
    EXPECT_LT(std::abs(tip[i] - tip[i - 1]), 0.5 * std::abs(tip[i - 1] - tip[i - 2]));
  const double locked = cook(8, true, 0.499).tip_uy;
  std::printf("[ measured ] Cook n = 8 (plane strain, nu = 0.499, full): tip u_y = %.4f mm\n",
              locked);
  EXPECT_LT(locked, 0.5 * tip[2]);
}

// At nu = 0.3 both integrations discretise the same problem: they agree as the mesh is refined.
TEST(StructureCook, ReducedAndFullVolumetricIntegrationAgreeAtModeratePoissonRatio) {
  const double full = cook(16, true).tip_uy,
               reduced = cook(16, true, 0.3, VolumetricIntegration::Reduced).tip_uy;
  std::printf("[ measured ] Cook n = 16 (plane strain, nu = 0.3): full %.4f, reduced %.4f mm\n",
              full, reduced);
  EXPECT_NEAR(reduced, full, 0.012 * full);
}
#else
// 64 elements per edge is not run: at 16 Newton takes 4-5 iterations per load step but FGMRES
// ~150 iterations per Newton iteration (systems AMG on the 1 mm slab whose thickness direction
// is free), ~45 s; 32 takes several minutes and 64 would take tens.
TEST(StructureCookLong, TipDisplacementMatchesPublishedQ1Values) { check({16, 32}); }

// Nearly incompressible at 32 elements per edge (~30 s on one thread): the sequence of the default
// test goes on converging.
TEST(StructureCookLong, NearlyIncompressibleWithReducedVolumetricIntegrationConverges) {
  const double t16 = cook(16, true, 0.499, VolumetricIntegration::Reduced).tip_uy;
  const double t32 = cook(32, true, 0.499, VolumetricIntegration::Reduced).tip_uy;
  std::printf("[ measured ] Cook nu = 0.499 reduced: n = 16 %.4f, n = 32 %.4f mm\n", t16, t32);
  // Measured at 8 and 16: 11.089 and 11.353 (a change of 0.264).
  EXPECT_LT(std::abs(t32 - t16), 0.5 * 0.264);
}
#endif
