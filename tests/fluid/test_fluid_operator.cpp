// The fluid operator against independent references: the tangent action against central finite
// differences of the residual (Full linearisation is the exact derivative), and the matrix-free
// tangent (on the fly and stored at the quadrature points) and its diagonal against the assembled
// matrix built by the same pointwise code (STYLE.md 7), for all three linearisations.
//
// Tolerances, and why:
//  * FD: 1e-6 relative (STYLE.md 7: "~1e-6 for finite-difference derivatives"); with a central
//    difference of step 1e-6 the truncation error is ~1e-12 and the round-off ~1e-10 relative.
//  * apply and diagonal vs assembled: 1e-12 relative (the issue): the same arithmetic summed in a
//    different order, i.e. round-off.
#include <gtest/gtest.h>

#include "fluid/fluid_test_support.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

// A small distorted 3-D mesh (3 elements thick, so w and all couplings are exercised) with a
// random state, random old velocity and random grid velocity: every term of the residual is on.
struct OperatorCase {
  Mesh mesh;
  FluidSettings settings;
  std::unique_ptr<FluidField> field;
  std::vector<double> u;

  explicit OperatorCase(FluidLinearisation lin, bool with_bcs = false, bool symmetric = true) {
    mesh = box_mesh(4, 3, 0.6, {{"fluid", 0.0, 1.0, 3, 1.5}});
    distort_smoothly(mesh);
    settings = tight_fluid_settings(1.3, 0.02);
    settings.pseudo_2d = false;
    settings.linearisation = lin;
    settings.symmetric_viscous = symmetric;
    std::vector<FluidBoundaryCondition> bcs;
    if (with_bcs) {
      bcs.push_back(fluid_no_slip("bottom"));
      bcs.push_back(fluid_velocity("left", constant(1.0), constant(0.1), constant(0.0)));
      bcs.push_back(fluid_slip("top"));
      bcs.push_back(fluid_traction("right", constant(-0.3), constant(0.1), constant(0.0)));
      bcs.push_back(fluid_pressure("front", constant(0.0)));
    }
    field = std::make_unique<FluidField>(mesh, settings, bcs);
    const int n = field->n_dofs();
    field->set_solution(random_values(n, -1, 1, 7));
    std::vector<Point> ug(mesh.n_nodes());
    const auto g = random_values(3 * mesh.n_nodes(), -0.3, 0.3, 11);
    for (int i = 0; i < mesh.n_nodes(); ++i) ug[i] = {g[3 * i], g[3 * i + 1], g[3 * i + 2]};
    field->set_grid_velocity(ug);
    field->prepare(5.0, 0.66);
    u = random_values(n, -1, 1, 13);
  }
};

double finite_difference_error(FluidLinearisation lin, bool symmetric) {
  OperatorCase c(lin, false, symmetric);
  const int n = c.field->n_dofs();
  const auto du = random_values(n, -1, 1, 17);
  Vector y("test::y", n), rp("test::rp", n), rm("test::rm", n);
  c.field->apply_tangent(device_vector(c.u), device_vector(du), y);
  const double h = 1e-6;
  std::vector<double> up(c.u), um(c.u);
  for (int i = 0; i < n; ++i) {
    up[i] += h * du[i];
    um[i] -= h * du[i];
  }
  c.field->residual(device_vector(up), rp);
  c.field->residual(device_vector(um), rm);
  const auto jy = host_vector(y), p = host_vector(rp), m = host_vector(rm);
  double err = 0, norm = 0;
  for (int i = 0; i < n; ++i) {
    const double fd = (p[i] - m[i]) / (2 * h);
    err += (fd - jy[i]) * (fd - jy[i]);
    norm += fd * fd;
  }
  return std::sqrt(err / norm);
}

}  // namespace

TEST(FluidOperator, FullTangentMatchesFiniteDifferences) {
  const double e_sym = finite_difference_error(FluidLinearisation::Full, true);
  const double e_lap = finite_difference_error(FluidLinearisation::Full, false);
  const double e_lag = finite_difference_error(FluidLinearisation::LaggedTau, true);
  std::printf(
      "[ measured ] |J du - FD| / |FD|: full %.2e (grad u form %.2e); lagged tau %.2e (the "
      "omitted tau derivative)\n",
      e_sym, e_lap, e_lag);
  EXPECT_LT(e_sym, 1e-6);
  EXPECT_LT(e_lap, 1e-6);
  // The lagged-tau tangent is not the derivative: it must differ visibly, or the FD check above
  // would not see the tau derivative at all.
  EXPECT_GT(e_lag, 1e-4);
}

TEST(FluidOperator, ApplyAndDiagonalMatchAssembledMatrix) {
  for (auto lin :
       {FluidLinearisation::Full, FluidLinearisation::LaggedTau, FluidLinearisation::Picard})
    for (bool bcs : {false, true}) {
      OperatorCase c(lin, bcs);
      const int n = c.field->n_dofs();
      const Vector u = device_vector(c.u);
      const Vector du = device_vector(random_values(n, -1, 1, 19));
      Vector y("test::y", n), ya("test::ya", n), ys("test::ys", n), d("test::d", n),
          da("test::da", n);
      c.field->apply_tangent(u, du, y);
      c.field->linearise(u);
      c.field->apply_linearised(du, ys);
      const CsrMatrix& a = c.field->assemble_jacobian(u);
      csr_multiply(a, du, ya);
      c.field->diagonal(u, d);
      csr_diagonal(a, da);
      const double e_apply = relative_difference(host_vector(y), host_vector(ya));
      const double e_stored = relative_difference(host_vector(ys), host_vector(ya));
      const double e_diag = relative_difference(host_vector(d), host_vector(da));
      std::printf(
          "[ measured ] linearisation %d, %s: apply vs assembled %.2e, stored tangent vs "
          "assembled %.2e, diagonal vs assembled %.2e\n",
          static_cast<int>(lin), bcs ? "with boundary conditions" : "no boundary conditions",
          e_apply, e_stored, e_diag);
      EXPECT_LT(e_apply, 1e-12);
      EXPECT_LT(e_stored, 1e-12);
      EXPECT_LT(e_diag, 1e-12);
    }
}
