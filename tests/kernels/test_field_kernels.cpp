// The fluid and structure pointwise physics through the generic element loop, without src/ (so
// that the CUDA preset compiles and, on a GPU, runs them): the matrix-free tangent action, on the
// fly and stored at the quadrature points, equals a central finite difference of the residual
// along a direction, on a distorted mesh with a state
// far from the linear regime. The fields' own tests (tests/fluid, tests/structure) check the same
// against the assembled matrices on the host; this one is the kernels' portability check.
// Tolerance: central differences with h = 1e-6 relative leave O(h^2) truncation and O(eps/h)
// round-off: measured 1e-10 (fluid, St. Venant-Kirchhoff) and 5e-8 (Neo-Hooke, whose log J term
// is the most curved); 1e-6 leaves room for other machines and the CUDA build.
#include <gtest/gtest.h>

#include <cmath>

#include "kernel_test_states.hpp"
#include "kernels/core/stored_tangent.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

void combine(Real a, ConstVector x, Real b, ConstVector y, Vector out) {
  Kokkos::parallel_for(
      "test::combine", Kokkos::RangePolicy<ExecSpace>(0, out.extent(0)),
      KOKKOS_LAMBDA(int i) { out(i) = a * x(i) + b * y(i); });
}

double max_abs(ConstVector v) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  double s = 0;
  for (size_t i = 0; i < h.extent(0); ++i) s = std::max(s, std::abs(h(i)));
  return s;
}

// max |J du - (r(u + h du) - r(u - h du)) / 2h| / max |J du|, with J the on-the-fly tangent or
// (stored = true) the tangent stored at the quadrature points.
template <class Physics>
double tangent_defect(const SmallMesh& m, const ElementOperator<Physics>& op, ConstVector u,
                      ConstVector du, double h, bool stored = false) {
  const int n = static_cast<int>(u.extent(0));
  const ElementGroups groups = element_groups(m, Scatter::Colored);
  Vector up("test::up", n), um("test::um", n), rp("test::rp", n), rm("test::rm", n),
      jdu("test::jdu", n), fd("test::fd", n);
  combine(1, u, h, du, up);
  combine(1, u, -h, du, um);
  op.residual(groups, up, rp);
  op.residual(groups, um, rm);
  if (stored) {
    StoredTangentOf<Physics> store;
    linearise(op, groups, u, store);
    apply_stored(store, du, jdu);
  } else {
    op.apply_tangent(groups, u, du, jdu);
  }
  combine(0.5 / h, rp, -0.5 / h, rm, fd);
  combine(1, jdu, -1, fd, fd);
  return max_abs(fd) / max_abs(jdu);
}

double fluid_defect(bool transient, bool stored = false) {
  const double length[3] = {1.0, 0.6, 0.3};
  const SmallMesh m = make_small_mesh(4, 3, 2, length, 0.04);
  FluidPhysics p;
  p.density = 1.0;
  p.viscosity = 0.01;
  p.inv_dt = transient ? 20.0 : 0.0;
  p.theta = 0.66;
  const ElementOperator<FluidPhysics> op(m.conn, m.x, m.block, fluid_aux(m), p);
  return tangent_defect(m, op, fluid_state(m), direction(m, 4), 1e-6, stored);
}

double structure_defect(int model, bool stored = false) {
  const double length[3] = {1.0, 0.6, 0.3};
  const SmallMesh m = make_small_mesh(4, 3, 2, length, 0.04);
  // d_n a large-strain field: stretches and shears of order 0.3.
  const ElementOperator<StructurePhysics> op(m.conn, m.x, m.block, structure_aux(m, 0.3, 0.2),
                                             structure_physics(model));
  return tangent_defect(m, op, structure_state(m, 0.2, 0.1), direction(m, 3), 1e-6, stored);
}

}  // namespace

TEST(FieldKernels, FluidTangentIsTheDerivativeOfTheResidual) {
  for (bool stored : {false, true}) {
    EXPECT_LT(fluid_defect(false, stored), 1e-6);
    EXPECT_LT(fluid_defect(true, stored), 1e-6);
  }
}

TEST(FieldKernels, StructureTangentIsTheDerivativeOfTheResidual) {
  for (bool stored : {false, true}) {
    EXPECT_LT(structure_defect(SaintVenantKirchhoff, stored), 1e-6);
    EXPECT_LT(structure_defect(NeoHooke, stored), 1e-6);
  }
}
