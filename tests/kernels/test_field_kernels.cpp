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

#include "kernels/core/stored_tangent.hpp"
#include "kernels/fluid/pointwise.hpp"
#include "kernels/structure/pointwise.hpp"
#include "small_mesh.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

// A smooth nodal field with `nc` components: value c of node n is f(c, x, y, z).
template <class F>
Vector nodal(const SmallMesh& m, int nc, F f, const std::string& label) {
  Vector v(label, nc * m.n_nodes());
  auto h = Kokkos::create_mirror_view(v);
  for (int n = 0; n < m.n_nodes(); ++n)
    for (int c = 0; c < nc; ++c)
      h(nc * n + c) = f(c, m.x_host(n, 0), m.x_host(n, 1), m.x_host(n, 2));
  Kokkos::deep_copy(v, h);
  return v;
}

template <class F>
NodalView auxiliary(const SmallMesh& m, int na, F f) {
  NodalView a(std::string("test::aux"), m.n_nodes(), na);
  auto h = Kokkos::create_mirror_view(a);
  for (int n = 0; n < m.n_nodes(); ++n)
    for (int c = 0; c < na; ++c) h(n, c) = f(c, m.x_host(n, 0), m.x_host(n, 1), m.x_host(n, 2));
  Kokkos::deep_copy(a, h);
  return a;
}

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
  p.viscosity = 0.01;  // element Reynolds number ~ 10: convection and SUPG matter
  p.inv_dt = transient ? 20.0 : 0.0;
  p.theta = 0.66;
  // aux: u_n, u_grid, b
  const NodalView aux = auxiliary(m, FluidPhysics::n_aux, [](int c, double x, double y, double z) {
    if (c < 3) return 0.5 * std::sin(1.3 * x + c) * std::cos(y - 0.4 * z);
    if (c < 6) return 0.1 * std::cos(x + 2 * y + c);
    return 0.3 * (c - 7);
  });
  const ElementOperator<FluidPhysics> op(m.conn, m.x, m.block, aux, p);
  const Vector u = nodal(
      m, 4,
      [](int c, double x, double y, double z) {
        return c < 3 ? std::cos(2 * x + c) * std::sin(1 + y + 0.5 * z) : x * y - z;
      },
      "test::u");
  const Vector du = nodal(
      m, 4, [](int c, double x, double y, double z) { return std::sin(3 * x - y + c) + 0.2 * z; },
      "test::du");
  return tangent_defect(m, op, u, du, 1e-6, stored);
}

double structure_defect(int model, bool stored = false) {
  const double length[3] = {1.0, 0.6, 0.3};
  const SmallMesh m = make_small_mesh(4, 3, 2, length, 0.04);
  StructurePhysics p;
  for (int b = 0; b < 2; ++b) {
    p.materials.model[b] = model;
    p.materials.lambda[b] = 1.0 + b;
    p.materials.mu[b] = 0.5;
    p.materials.density[b] = 2.0;
  }
  p.mass_coefficient = 10.0;
  p.dt = 0.1;
  p.theta = 0.66;
  // aux: d_n (a large-strain field: stretches and shears of order 0.3), v_n, b
  const NodalView aux =
      auxiliary(m, StructurePhysics::n_aux, [](int c, double x, double y, double z) {
        if (c < 3) return 0.3 * std::sin(x + 2 * y + c) + 0.2 * z * (c == 0);
        return 0.1 * std::cos(x - y + c);
      });
  const ElementOperator<StructurePhysics> op(m.conn, m.x, m.block, aux, p);
  const Vector u = nodal(
      m, 3,
      [](int c, double x, double y, double z) {
        return 0.2 * std::cos(2 * x + c) * (1 + y) - 0.1 * z;
      },
      "test::u");
  const Vector du = nodal(
      m, 3, [](int c, double x, double y, double z) { return std::sin(3 * x - y + c) + 0.2 * z; },
      "test::du");
  return tangent_defect(m, op, u, du, 1e-6, stored);
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
