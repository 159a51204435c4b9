// The mesh-motion pointwise physics through the kernel drivers, without src/ (so the CUDA preset
// compiles it): rigid motions are in the kernel, and the matrix-free tangent equals the residual
// of this linear operator. Tolerances: exact identities, 40 eps relative to the operator's scale.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "kernels/ale/pointwise.hpp"
#include "small_mesh.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

// Nodal displacement a + w x p (translation plus infinitesimal rotation), or a stretch.
Vector motion(const SmallMesh& m, bool rigid) {
  Vector d(std::string("test::d"), 3 * m.n_nodes());
  auto h = Kokkos::create_mirror_view(d);
  for (int n = 0; n < m.n_nodes(); ++n) {
    const double x = m.x_host(n, 0), y = m.x_host(n, 1), z = m.x_host(n, 2);
    if (rigid) {
      h(3 * n) = 0.1 + 0.3 * z - 0.2 * y;
      h(3 * n + 1) = -0.2 + 0.2 * x - 0.1 * z;
      h(3 * n + 2) = 0.05 + 0.1 * y - 0.3 * x;
    } else {
      h(3 * n) = 0.1 * x;
      h(3 * n + 1) = h(3 * n + 2) = 0;
    }
  }
  Kokkos::deep_copy(d, h);
  return d;
}

void subtract(Vector y, ConstVector r) {
  Kokkos::parallel_for(
      "test::difference", Kokkos::RangePolicy<ExecSpace>(0, y.extent(0)),
      KOKKOS_LAMBDA(int i) { y(i) -= r(i); });
}

double max_abs(ConstVector v) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  double s = 0;
  for (size_t i = 0; i < h.extent(0); ++i) s = std::max(s, std::abs(h(i)));
  return s;
}

}  // namespace

TEST(PseudoElasticKernel, RigidMotionsAreInTheKernelAndTheTangentIsTheResidual) {
  const double length[3] = {1.0, 0.7, 0.4};
  const SmallMesh m = make_small_mesh(4, 3, 2, length, 0.05);
  PseudoElasticPhysics p;
  p.stiffening = 1.0;
  ElementOperator<PseudoElasticPhysics> op(m.conn, m.x, m.block, ConstNodalView{}, p);
  const ElementGroups groups = element_groups(m, Scatter::Colored);
  const Vector zero(std::string("test::zero"), 3 * m.n_nodes());
  Vector r(std::string("test::r"), 3 * m.n_nodes()), y(std::string("test::y"), 3 * m.n_nodes());
  const Vector stretch = motion(m, false);
  op.residual(groups, stretch, r);
  const double scale = max_abs(r);
  ASSERT_GT(scale, 0);
  op.apply_tangent(groups, zero, stretch, y);
  subtract(y, r);
  EXPECT_LE(max_abs(y), 40 * eps * scale);
  Kokkos::deep_copy(r, 0.0);
  op.residual(groups, motion(m, true), r);
  EXPECT_LE(max_abs(r), 40 * eps * scale * 10);  // rotation amplitude 0.3 vs stretch 0.1
}
