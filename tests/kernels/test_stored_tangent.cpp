// The tangent stored at the quadrature points (kernels/core/stored_tangent.hpp) against the
// on-the-fly element loop and the assembled matrix, for every field's physics (transport with
// SUPG, Monod and a deforming block; the stabilised fluid; St. Venant-Kirchhoff and Neo-Hooke
// structures; pseudo-elastic mesh motion with stiffening), on a distorted two-block mesh, with
// both scatter policies and both storage widths (SIMD batches of simd_width elements, and one
// element per batch as on a GPU): apply, diagonal and assembled matrix; and the point-state stores
// of transport, the fluid (for every linearisation) and mesh motion (the tangent re-evaluated from
// a stored per-point state); and transport's step states (the residual and the linearisation at
// any phi from data stored once per time step).
//
// Tolerance 1e-12 relative to the largest entry: the stored and the on-the-fly products evaluate
// the same sums in another order (the inverse Jacobian folded into the stored matrix instead of
// applied to the gradients), so they agree to round-off (~1e-15 measured); 1e-12 still catches a
// transposed Jacobian, a wrong weight or a lane mix-up, all O(1). The structure's states carry
// strains of about 0.1: at strains near 0.5 Neo-Hooke's tangent is so ill-conditioned that even
// the on-the-fly apply and its own assembled matrix differ by 8e-9.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "kernel_test_states.hpp"
#include "kernels/ale/pointwise.hpp"
#include "kernels/core/stored_tangent.hpp"
#include "kernels/scalar/pointwise.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

// The scalar pattern expanded to nc unknowns per node (every component couples to every other).
CsrMatrix block_pattern(const SmallMesh& m, int nc) {
  const CsrMatrix s = make_pattern(m);
  auto rp = Kokkos::create_mirror_view_and_copy(HostSpace(), s.row_ptr);
  auto col = Kokkos::create_mirror_view_and_copy(HostSpace(), s.col);
  CsrMatrix a;
  a.n_rows = nc * s.n_rows;
  a.row_ptr = Kokkos::View<int*, MemSpace>(std::string("test::row_ptr"), a.n_rows + 1);
  auto arp = Kokkos::create_mirror_view(a.row_ptr);
  std::vector<int> cols;
  arp(0) = 0;
  for (int r = 0; r < s.n_rows; ++r)
    for (int c = 0; c < nc; ++c) {
      for (int k = rp(r); k < rp(r + 1); ++k)
        for (int cc = 0; cc < nc; ++cc) cols.push_back(col(k) * nc + cc);
      arp(r * nc + c + 1) = static_cast<int>(cols.size());
    }
  Kokkos::deep_copy(a.row_ptr, arp);
  a.col = to_device(cols, "test::col");
  a.val = Kokkos::View<Real*, MemSpace>(std::string("test::val"), cols.size());
  return a;
}

// max |a - b| / max |b|.
double relative_difference(ConstVector a, ConstVector b) {
  const auto ha = to_host(a), hb = to_host(b);
  double diff = 0, size = 0;
  for (size_t i = 0; i < ha.size(); ++i) {
    diff = std::max(diff, std::abs(ha[i] - hb[i]));
    size = std::max(size, std::abs(hb[i]));
  }
  return size > 0 ? diff / size : diff;
}

struct Defects {
  double apply_vs_on_the_fly = 0, apply_vs_matrix = 0, diagonal = 0, matrix = 0;
};

// A store's apply against the on-the-fly apply and against the on-the-fly matrix, assembled into
// `a`.
template <class Physics, class Store>
Defects apply_defects(const ElementOperator<Physics>& op, const ElementGroups& groups,
                      ConstVector u, ConstVector du, Store& store, const CsrMatrix& a) {
  const int n = static_cast<int>(du.extent(0));
  linearise(op, groups, u, store);
  Defects d;
  Vector y_fly("test::y_fly", n), y_stored("test::y_stored", n), y_matrix("test::y_matrix", n);
  op.apply_tangent(groups, u, du, y_fly);
  apply_stored(store, du, y_stored);
  d.apply_vs_on_the_fly = relative_difference(y_stored, y_fly);
  op.assemble(groups, u, a);
  csr_multiply(a, du, y_matrix);
  d.apply_vs_matrix = relative_difference(y_stored, y_matrix);
  return d;
}

// Every product of the stored tangent against its on-the-fly counterpart.
template <int W, class Physics>
Defects stored_defects(const SmallMesh& m, const ElementOperator<Physics>& op, ConstVector u,
                       ConstVector du, Scatter scatter) {
  constexpr int NC = Physics::n_components;
  const ElementGroups groups = element_groups(m, scatter);
  StoredTangentOf<Physics, W> store;
  const CsrMatrix a_fly = block_pattern(m, NC), a_stored = block_pattern(m, NC);
  Defects d = apply_defects(op, groups, u, du, store, a_fly);
  assemble_stored(store, a_stored);
  d.matrix = relative_difference(a_stored.val, a_fly.val);
  const int n = NC * m.n_nodes();
  Vector diag_fly("test::diag_fly", n), diag_stored("test::diag_stored", n);
  op.diagonal(groups, u, diag_fly);
  diagonal_stored(store, diag_stored);
  d.diagonal = relative_difference(diag_stored, diag_fly);
  return d;
}

// A point-state store has no diagonal or assembly of its own.
template <int W, class Physics>
Defects point_state_defects(const SmallMesh& m, const ElementOperator<Physics>& op, ConstVector u,
                            ConstVector du, Scatter scatter) {
  StoredPointStates<Physics, W> store;
  return apply_defects(op, element_groups(m, scatter), u, du, store,
                       block_pattern(m, Physics::n_components));
}

// The point-state store's apply against the on-the-fly apply and the assembled matrix, for both
// scatters and both widths.
template <class Physics>
void expect_point_states_equal_on_the_fly(const SmallMesh& m, const ElementOperator<Physics>& op,
                                          ConstVector u, ConstVector du) {
  for (Scatter scatter : {Scatter::Atomic, Scatter::Colored})
    for (const Defects& d : {point_state_defects<simd_width>(m, op, u, du, scatter),
                             point_state_defects<1>(m, op, u, du, scatter)}) {
      EXPECT_LT(d.apply_vs_on_the_fly, 1e-12);
      EXPECT_LT(d.apply_vs_matrix, 1e-12);
    }
}

template <class Physics>
void expect_stored_equals_on_the_fly(const SmallMesh& m, const ElementOperator<Physics>& op,
                                     ConstVector u, ConstVector du) {
  for (Scatter scatter : {Scatter::Atomic, Scatter::Colored}) {
    const Defects packed = stored_defects<simd_width>(m, op, u, du, scatter);
    const Defects single = stored_defects<1>(m, op, u, du, scatter);
    for (const Defects& d : {packed, single}) {
      EXPECT_LT(d.apply_vs_on_the_fly, 1e-12);
      EXPECT_LT(d.apply_vs_matrix, 1e-12);
      EXPECT_LT(d.diagonal, 1e-12);
      EXPECT_LT(d.matrix, 1e-12);
    }
  }
}

// 5x4x3 elements: 60, not a multiple of the batch width, so the last batch has padding lanes.
SmallMesh distorted_mesh() {
  const double length[3] = {1.0, 0.6, 0.3};
  return make_small_mesh(5, 4, 3, length, 0.04);
}

// Transport with SUPG, Monod and a deforming block on the distorted mesh; aux: phi_n, material
// velocity w, convective velocity c and a source of the given amplitude.
ElementOperator<TransportPhysics> transport_operator(const SmallMesh& m, double source) {
  TransportPhysics p;
  p.coef.diffusivity[0] = 1e-2, p.coef.diffusivity[1] = 5e-3;
  p.coef.monod_rate[1] = 1.0, p.coef.monod_half_saturation[1] = 0.1;
  p.coef.material_motion[1] = 1.0;
  p.inv_dt = 10;
  p.theta = 0.66;
  const NodalView aux =
      auxiliary(m, TransportPhysics::n_aux, [source](int c, double x, double y, double z) {
        if (c == 0) return 0.5 + 0.3 * std::sin(2 * x + y);
        if (c < 4) return 0.05 * std::cos(x + 2 * y - z + c);
        if (c < 7) return std::sin(1.3 * x + c) * std::cos(y - 0.4 * z);
        return source * std::cos(3 * x - z);
      });
  return ElementOperator<TransportPhysics>(m.conn, m.x, m.block, aux, p);
}

}  // namespace

TEST(StoredTangent, TransportEqualsOnTheFlyAndAssembled) {
  const SmallMesh m = distorted_mesh();
  const ElementOperator<TransportPhysics> op = transport_operator(m, 0.0);
  const Vector u = nodal(
      m, 1, [](int, double x, double y, double z) { return 0.4 + 0.3 * std::cos(2 * x - y + z); },
      "test::u");
  expect_stored_equals_on_the_fly(m, op, u, direction(m, 1));
  expect_point_states_equal_on_the_fly(m, op, u, direction(m, 1));
}

// The step's states (stored once per time step) give the residual at any phi, and the tangent's
// point states at any phi, equal to the on-the-fly loop's: stored at u, evaluated at another u2
// with negative values (Monod's odd extension), with a source and a deforming block.
TEST(StoredTangent, TransportStepStatesGiveResidualAndLinearisationAtAnyPhi) {
  const SmallMesh m = distorted_mesh();
  const ElementOperator<TransportPhysics> op = transport_operator(m, 0.2);
  const Vector u = nodal(
      m, 1, [](int, double x, double y, double z) { return 0.4 + 0.3 * std::cos(2 * x - y + z); },
      "test::u");
  const Vector u2 = nodal(
      m, 1, [](int, double x, double y, double z) { return 0.3 * std::sin(4 * x + y - 2 * z); },
      "test::u2");
  const Vector du = direction(m, 1);
  const int n = m.n_nodes();
  for (Scatter scatter : {Scatter::Atomic, Scatter::Colored}) {
    const ElementGroups groups = element_groups(m, scatter);
    Vector r_fly("test::r_fly", n), y_fly("test::y_fly", n);
    op.residual(groups, u2, r_fly);
    op.apply_tangent(groups, u2, du, y_fly);
    auto check = [&](auto& steps, auto& points) {
      store_step_states(op, groups, u, steps);
      Vector r("test::r", n), y("test::y", n);
      residual_stored(steps, u2, r);
      linearise_from_step_states(steps, u2, points);
      apply_stored(points, du, y);
      const double dr = relative_difference(r, r_fly), dy = relative_difference(y, y_fly);
      std::printf("[ measured ] step states: residual %.1e, tangent %.1e\n", dr, dy);
      EXPECT_LT(dr, 1e-12);
      EXPECT_LT(dy, 1e-12);
    };
    StoredPointStates<TransportPhysics, simd_width, StepStates> steps;
    StoredPointStates<TransportPhysics, simd_width> points;
    check(steps, points);
    StoredPointStates<TransportPhysics, 1, StepStates> steps1;
    StoredPointStates<TransportPhysics, 1> points1;
    check(steps1, points1);
  }
}

TEST(StoredTangent, FluidEqualsOnTheFlyAndAssembled) {
  const SmallMesh m = distorted_mesh();
  FluidPhysics p;
  p.density = 1.0;
  p.viscosity = 0.01;
  p.inv_dt = 20.0;
  p.theta = 0.66;
  const ElementOperator<FluidPhysics> op(m.conn, m.x, m.block, fluid_aux(m), p);
  const Vector u = fluid_state(m);
  const Vector du = direction(m, 4);
  expect_stored_equals_on_the_fly(m, op, u, du);
  expect_point_states_equal_on_the_fly(m, op, u, du);
}

TEST(StoredTangent, FluidPointStatesEqualOnTheFlyForEveryLinearisation) {
  const SmallMesh m = distorted_mesh();
  for (auto lin :
       {FluidLinearisation::Full, FluidLinearisation::LaggedTau, FluidLinearisation::Picard}) {
    FluidPhysics p;
    p.density = 1.3, p.viscosity = 0.02, p.inv_dt = 5.0, p.theta = 0.66;
    p.linearisation = lin;
    p.symmetric_viscous = lin != FluidLinearisation::Picard;
    const ElementOperator<FluidPhysics> op(m.conn, m.x, m.block, fluid_aux(m), p);
    const Vector u = fluid_state(m);
    const Defects d = point_state_defects<simd_width>(m, op, u, direction(m, 4), Scatter::Colored);
    EXPECT_LT(d.apply_vs_on_the_fly, 1e-12);
    EXPECT_LT(d.apply_vs_matrix, 1e-12);
  }
}

TEST(StoredTangent, StructureEqualsOnTheFlyAndAssembled) {
  const SmallMesh m = distorted_mesh();
  for (int model : {SaintVenantKirchhoff, NeoHooke}) {
    const ElementOperator<StructurePhysics> op(m.conn, m.x, m.block, structure_aux(m, 0.1, 0.05),
                                               structure_physics(model));
    const Vector u = structure_state(m, 0.05, 0.02);
    expect_stored_equals_on_the_fly(m, op, u, direction(m, 3));
  }
}

TEST(StoredTangent, MeshMotionEqualsOnTheFlyAndAssembled) {
  const SmallMesh m = distorted_mesh();
  PseudoElasticPhysics p;
  p.lambda = 0.7;
  p.mu = 1.0;
  p.stiffening = 2.0;
  p.reference_det = 0.01;
  const NodalView aux = auxiliary(m, 0, [](int, double, double, double) { return 0.0; });
  const ElementOperator<PseudoElasticPhysics> op(m.conn, m.x, m.block, aux, p);
  const Vector u("test::u", 3 * m.n_nodes());
  const Vector du = direction(m, 3);
  expect_stored_equals_on_the_fly(m, op, u, du);
  expect_point_states_equal_on_the_fly(m, op, u, du);
}
