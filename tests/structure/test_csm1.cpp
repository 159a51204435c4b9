// Turek & Hron (2006) CSM1 (../shared/reference/benchmarks.md): the elastic flag alone, St.
// Venant-Kirchhoff, rho = 1000 kg/m^3, mu = 0.5e6 Pa, nu = 0.4, gravity 2 m/s^2 downwards, steady,
// clamped where it meets the cylinder, pseudo-2-D (one hex layer, z displacement held at zero:
// plane strain). Reference tip displacement at A = (0.6, 0.2): u_x = -7.18767e-3 m,
// u_y = -66.1023e-3 m.
//
// Meshes: the flag block of cases/meshes/turek_hron.geo (block-structured Gmsh geometry; the
// clamp is the circular arc x <= 0.2490 where the flag meets the cylinder), read with read_gmsh and
// cut out with submesh, at refine 1, 2, 4 (4, 8, 16 elements through the thickness). The gravity
// load is ramped over the load steps as a body force rho g t.
//
// Tolerances, and why: the reference is a converged (Q2) value, and plain Q1 approaches it from
// below at O(h^2) (bending stiffness overestimated by shear locking). Measured u_y(A) on the
// current meshes: -7.86% (refine 1), -2.13% (refine 2; u_x -4.26%), -0.56% (refine 4, 19686
// dofs; u_x -1.12%), observed orders 1.89 and 1.94; Richardson extrapolation of refine 2 and 4:
// -0.03%. (An unstructured flag mesh gives -13.7%, -4.1%, -1.1% at refine 1, 2, 4.) So
// the "within 1% on a moderate mesh" is met by raw Q1 at refine 4 (the default suite
// asserts it, ~40 s), with the extrapolation held to 0.2%; the long study adds refine 1 and asks
// for an observed order above 1.5.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "structure/turek_hron_flag.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

constexpr double ref_ux = -7.18767e-3, ref_uy = -66.1023e-3;

struct Csm1Result {
  double ux = 0, uy = 0;
  int dofs = 0, newton = 0, cut_steps = 0;
  std::vector<int> krylov_first_step;
};

Csm1Result csm1(int refine, StructureAmg amg = StructureAmg::Systems, int load_steps = 4) {
  const Mesh mesh = turek_hron_flag_mesh(refine);
  const StructureMaterial m = turek_hron_flag_material();
  const double rho = m.density, g = 2;
  StructureSettings s = tight_structure_settings({m}, true);
  s.plane_strain = true;
  s.amg = amg;
  StructureField field(mesh, s, {clamp("solid_clamp")});
  field.set_body_force(
      {constant(0), [rho, g](const Point&, double t) { return -rho * g * t; }, constant(0)});
  Csm1Result out;
  for (int i = 1; i <= load_steps; ++i) {
    const NewtonResult r = field.step(1.0 / load_steps, "CSM1 load step " + std::to_string(i));
    out.newton += r.iterations;
    if (i == 1) out.krylov_first_step = field.stats().last_step_krylov;
  }
  const auto d = field.displacement();
  int found = 0;
  for (int n = 0; n < mesh.n_nodes(); ++n)
    if (std::abs(mesh.x[n][0] - 0.6) < 1e-9 && std::abs(mesh.x[n][1] - 0.2) < 1e-9) {
      out.ux += d[n][0];
      out.uy += d[n][1];
      ++found;
    }
  if (found == 0) throw std::runtime_error("CSM1: no node at point A");
  out.ux /= found;
  out.uy /= found;
  out.dofs = field.n_dofs();
  out.cut_steps = field.stats().cut_steps;
  return out;
}

void print(int refine, const Csm1Result& r) {
  std::printf(
      "[ measured ] CSM1 refine %d (%d dofs): u_x(A) = %.5e (%+.2f%%), u_y(A) = %.5e (%+.2f%%), "
      "Newton %d, cut steps %d\n",
      refine, r.dofs, r.ux, 100 * (r.ux / ref_ux - 1), r.uy, 100 * (r.uy / ref_uy - 1), r.newton,
      r.cut_steps);
}

}  // namespace

// Richardson extrapolation of two meshes with element sizes h and h/2 for an O(h^2) error.
double richardson(double coarse, double fine) { return fine + (fine - coarse) / 3.0; }

#ifndef BIOFSI_STRUCTURE_LONG
TEST(StructureCsm1, TipDisplacementOnModerateMeshes) {
  const Csm1Result r2 = csm1(2), r4 = csm1(4);
  print(2, r2);
  print(4, r4);
  const double extrapolated = richardson(r2.uy, r4.uy);
  std::printf("[ measured ] CSM1 u_y(A) Richardson (refine 2, 4) = %.5e (%+.2f%%)\n", extrapolated,
              100 * (extrapolated / ref_uy - 1));
  EXPECT_NEAR(r4.uy, ref_uy, 0.01 * std::abs(ref_uy));  // the 1%; measured -0.56%
  EXPECT_NEAR(r4.ux, ref_ux, 0.02 * std::abs(ref_ux));  // measured -1.12% (u_x is 10x smaller)
  EXPECT_NEAR(extrapolated, ref_uy, 0.002 * std::abs(ref_uy));
  EXPECT_LT(std::abs(r4.uy - ref_uy), std::abs(r2.uy - ref_uy));
}
#else
TEST(StructureCsm1Long, ConvergenceStudy) {
  std::vector<Csm1Result> rs;
  for (int refine : {1, 2, 4}) {
    rs.push_back(csm1(refine));
    print(refine, rs.back());
  }
  for (size_t i = 1; i < rs.size(); ++i) {
    const double e0 = std::abs(rs[i - 1].uy - ref_uy), e1 = std::abs(rs[i].uy - ref_uy);
    const double order = std::log(e0 / e1) / std::log(2.0);
    std::printf("[ measured ] CSM1 u_y error %.3e -> %.3e, observed order %.2f\n", e0, e1, order);
    EXPECT_GT(order, 1.5);  // Q1 displacement converges at O(h^2); measured 1.89 and 1.94
  }
  const double extrapolated = richardson(rs[1].uy, rs[2].uy);
  std::printf("[ measured ] CSM1 u_y(A) Richardson (refine 2, 4) = %.5e (%+.2f%%)\n", extrapolated,
              100 * (extrapolated / ref_uy - 1));
  EXPECT_NEAR(rs.back().uy, ref_uy, 0.01 * std::abs(ref_uy));
  EXPECT_NEAR(extrapolated, ref_uy, 0.002 * std::abs(ref_uy));
}

// Krylov iterations per Newton iteration (first of 4 load steps, refine 2) for the three BoomerAMG
// variants: the measurement behind StructureSettings' default (bench/README.md).
TEST(StructureCsm1Long, AmgVariantsIterationCounts) {
  const char* names[] = {"scalar", "systems (3 functions, nodal)", "systems + rigid-body modes"};
  for (int v = 0; v < 3; ++v) {
    const Csm1Result r = csm1(2, StructureAmg(v));
    std::printf("[ measured ] CSM1 refine 2, AMG %s: Krylov per Newton iteration:", names[v]);
    for (int k : r.krylov_first_step) std::printf(" %d", k);
    std::printf("; u_y(A) = %.5e\n", r.uy);
    EXPECT_NEAR(r.uy, ref_uy, 0.05 * std::abs(ref_uy));
  }
}
#endif
