// Verification of the boundary-face driver (kernels/core/face.hpp) with the transport Robin/Neumann
// term (TransportBoundaryPhysics) on a distorted mesh whose sides stay flat rectangles.
//
// Tolerances, and why:
//  * 1e-12 relative (to the largest entry): matrix-free action versus assembled matrix are the
//    same face integrals summed in another order, so they agree to round-off.
//  * 1e-13 relative for the integrated flux: the bilinear area element of a flat quadrilateral is
//    linear in each face parameter, so 2x2 Gauss integrates it exactly and the partition of unity
//    makes sum_a int N_a dA the area; only the round-off of summing a few hundred terms remains.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "kernels/core/csr.hpp"
#include "kernels/core/face.hpp"
#include "kernels/scalar/pointwise.hpp"
#include "kernels/small_mesh.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

using RobinOperator = FaceOperator<TransportBoundaryPhysics>;

// Face data [phi_n, h, alpha, phi_inf] per node.
template <class F>
NodalView make_face_aux(const SmallMesh& m, F f) {
  NodalView aux(std::string("face_aux"), m.n_nodes(), TransportBoundaryPhysics::n_aux);
  auto h = Kokkos::create_mirror_view(aux);
  for (int n = 0; n < m.n_nodes(); ++n) {
    double v[4];
    f(m.x_host(n, 0), m.x_host(n, 1), m.x_host(n, 2), v);
    for (int c = 0; c < 4; ++c) h(n, c) = v[c];
  }
  Kokkos::deep_copy(aux, h);
  return aux;
}

double relative_difference(const HostVector& a, const HostVector& b) {
  double d = 0, s = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    d = std::max(d, std::abs(a[i] - b[i]));
    s = std::max(s, std::abs(b[i]));
  }
  return d / s;
}

HostVector wiggly_field(const SmallMesh& m, double phase) {
  HostVector v(m.n_nodes());
  for (int n = 0; n < m.n_nodes(); ++n)
    v[n] =
        0.3 + std::sin(2.1 * m.x_host(n, 0) - 1.3 * m.x_host(n, 1) + 0.7 * m.x_host(n, 2) + phase);
  return v;
}

}  // namespace

TEST(TransportBoundaryOperator, RobinMatrixFreeActionAndDiagonalEqualAssembled) {
  const SmallMesh m = box_5x4x3();
  // Three sides meeting at a corner, so that nodes on edges collect several faces.
  const FaceView faces = biofsi::test::boundary_faces(m, {0, 3, 4});
  const NodalView aux = make_face_aux(m, [](double x, double y, double z, double v[4]) {
    v[0] = 0.2 + 0.1 * x;                  // phi_n
    v[1] = 0.5 * std::cos(y);              // h
    v[2] = 1.5 + std::sin(2 * x + z + y);  // alpha > 0, varying along the face
    v[3] = 1.0 - 0.3 * z;                  // phi_inf
  });
  TransportBoundaryPhysics p;
  p.theta = 0.66;
  const RobinOperator op(faces, m.conn, m.x, aux, p);
  const HostVector u = wiggly_field(m, 0.0), du = wiggly_field(m, 1.7);

  Vector y(std::string("y"), m.n_nodes()), d(std::string("d"), m.n_nodes());
  op.apply_tangent(to_device(u), to_device(du), y);
  op.diagonal(to_device(u), d);
  CsrMatrix a = biofsi::test::make_pattern(m);
  op.assemble(to_device(u), a);
  Vector ay(std::string("ay"), m.n_nodes()), ad(std::string("ad"), m.n_nodes());
  csr_multiply(a, to_device(du), ay);
  csr_diagonal(a, ad);
  EXPECT_LT(relative_difference(to_host(y), to_host(ay)), 1e-12);
  EXPECT_LT(relative_difference(to_host(d), to_host(ad)), 1e-12);

  // The residual is affine in u with exactly that matrix: r(u + du) - r(u) = A du.
  Vector r0(std::string("r0"), m.n_nodes()), r1(std::string("r1"), m.n_nodes());
  HostVector u1(u);
  for (size_t i = 0; i < u1.size(); ++i) u1[i] += du[i];
  op.residual(to_device(u), r0);
  op.residual(to_device(u1), r1);
  HostVector diff = to_host(r1), base = to_host(r0);
  for (size_t i = 0; i < diff.size(); ++i) diff[i] -= base[i];
  EXPECT_LT(relative_difference(diff, to_host(ay)), 1e-12);
}

TEST(TransportBoundaryOperator, ConstantFluxIntegratesToFluxTimesArea) {
  const SmallMesh m = box_5x4x3();
  const double flux = 2.5;
  // Pure Neumann (alpha = 0): r_a = -int N_a h dA, so sum_a r_a = -h * area.
  const NodalView aux = make_face_aux(m, [&](double, double, double, double v[4]) {
    v[0] = 0.3;
    v[1] = flux;
    v[2] = 0.0;
    v[3] = 0.0;
  });
  TransportBoundaryPhysics p;
  p.theta = 0.66;
  const double lx = m.length[0], ly = m.length[1], lz = m.length[2];
  const double side_area[6] = {ly * lz, ly * lz, lx * lz, lx * lz, lx * ly, lx * ly};
  const HostVector u = wiggly_field(m, 0.0);
  double total_area = 0, total = 0;
  for (int side = 0; side < 6; ++side) {
    const RobinOperator op(biofsi::test::boundary_faces(m, {side}), m.conn, m.x, aux, p);
    Vector r(std::string("r"), m.n_nodes());
    op.residual(to_device(u), r);
    double sum = 0;
    for (double v : to_host(r)) sum += v;
    EXPECT_NEAR(sum, -flux * side_area[side], 1e-13 * flux * side_area[side]) << "side " << side;
    total += sum;
    total_area += side_area[side];
  }
  const RobinOperator all(biofsi::test::boundary_faces(m, {0, 1, 2, 3, 4, 5}), m.conn, m.x, aux, p);
  Vector r(std::string("r"), m.n_nodes());
  all.residual(to_device(u), r);
  double sum = 0;
  for (double v : to_host(r)) sum += v;
  EXPECT_NEAR(sum, -flux * total_area, 1e-13 * flux * total_area);
  EXPECT_NEAR(total, sum, 1e-13 * flux * total_area);
}
