// The transport field's stored tangent (what its Newton iterations apply) against its on-the-fly
// tangent, with every boundary-condition kind (Dirichlet, flux, Robin), convection with SUPG, Monod
// consumption and a deforming block, on a distorted two-block mesh after a real time step.
// Tolerance 1e-12 relative to the largest entry: the same sums in another order (the kernels'
// own test, tests/kernels/test_stored_tangent.cpp, measures ~1e-15 and checks both against the
// assembled matrix).
#include <gtest/gtest.h>

#include "scalar_test_support.hpp"

using namespace biofsi;
using namespace biofsi::test;

TEST(TransportField, StoredTangentEqualsOnTheFlyWithEveryBoundaryKind) {
  Mesh mesh = box_mesh(10, 2, 0.2, {{"biofilm", 0.0, 0.5, 4, 1.0}, {"fluid", 0.5, 1.0, 4, 1.0}});
  distort_smoothly(mesh);
  TransportSettings s = tight_settings(0.66, true);
  s.coefficients.diffusivity[0] = 0.02, s.coefficients.diffusivity[1] = 0.05;
  s.coefficients.monod_rate[0] = 1.0, s.coefficients.monod_half_saturation[0] = 0.2;
  s.coefficients.material_motion[0] = 1.0;
  std::vector<ScalarBoundaryCondition> bcs{
      dirichlet("left", [](const Point&, double) { return 1.0; })};
  ScalarBoundaryCondition flux, robin;
  flux.set = "bottom", flux.kind = ScalarBcKind::Flux;
  flux.value = [](const Point& x, double) { return 0.1 * x[0]; };
  robin.set = "top", robin.kind = ScalarBcKind::Robin, robin.coefficient = 2.0;
  robin.value = [](const Point&, double) { return 0.8; };
  bcs.push_back(flux);
  bcs.push_back(robin);
  TransportField field(mesh, s, bcs);
  field.set_convective_velocity(nodal_vectors(mesh, [](const Point& x) {
    return Point{1.0 + x[1], 0.2 * x[0], 0.0};
  }));
  field.set_material_velocity(nodal_vectors(mesh, [](const Point& x) {
    return Point{0.05 * x[0], -0.02 * x[1] * x[0], 0.0};
  }));
  field.set_initial([](const Point& x, double) { return 0.5 + 0.3 * std::sin(3 * x[0]); }, 0.0);
  field.step(0.05, "step 1");  // sets the step's physics and leaves a non-trivial state

  const int n = mesh.n_nodes();
  std::vector<double> phi(n), dphi(n);
  for (int i = 0; i < n; ++i) {
    phi[i] = 0.4 + 0.3 * std::cos(2 * mesh.x[i][0] - mesh.x[i][1]);
    dphi[i] = std::sin(3 * mesh.x[i][0] + 2 * mesh.x[i][1]);
  }
  const Vector u = to_device_vector(phi, "test::phi"), du = to_device_vector(dphi, "test::dphi");
  Vector y_fly("test::y_fly", n), y_stored("test::y_stored", n);
  field.apply_tangent(u, du, y_fly);
  field.linearise(u);
  field.apply_linearised(du, y_stored);
  const auto a = to_host_vector(y_stored), b = to_host_vector(y_fly);
  double diff = 0;
  for (int i = 0; i < n; ++i) diff = std::max(diff, std::abs(a[i] - b[i]));
  const double rel = diff / max_abs(b);
  std::printf("[ measured ] stored vs on-the-fly tangent: %.2e relative\n", rel);
  EXPECT_LT(rel, 1e-12);
}
