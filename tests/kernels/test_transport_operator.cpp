// Verification of the scalar transport element operator (kernels/scalar/pointwise.hpp through
// kernels/core/element_loop.hpp) on a distorted two-block mesh: the four products of one pointwise
// definition (residual, tangent action, diagonal, assembled matrix) against each other, against an
// independent naive element matrix, and against finite differences of the residual.
//
// Tolerances, and why:
//  * 1e-12 relative (to the largest entry): two evaluations of the same operator that differ only
//    in summation order (sum factorisation versus column-by-column element matrices, or a
//    hand-written reference), so they agree to round-off; with ~30 terms per entry and condition
//    numbers of order 10 the differences are ~1e-15, and 1e-12 leaves room while still catching a
//    wrong quadrature weight, a transposed Jacobian or a dropped term (all O(1) relative).
//  * 1e-13 relative for colouring versus atomic scatter: the same numbers added in another order.
//  * 40 eps times the row's absolute sum for identities that are exactly zero (row sums, constant
//    fields): the backward-error bound of summing a row.
//  * 1e-6 relative for central finite differences: the step is chosen so that truncation
//    (step^2 times the third derivative) and cancellation (eps over step) both stay below ~1e-8.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "kernels/core/csr.hpp"
#include "kernels/core/element_loop.hpp"
#include "kernels/scalar/pointwise.hpp"
#include "kernels/small_mesh.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();
using TransportOperator = ElementOperator<TransportPhysics>;

// A nodal field from a function of the node's coordinates.
template <class F>
HostVector nodal_field(const SmallMesh& m, F f) {
  HostVector v(m.n_nodes());
  for (int n = 0; n < m.n_nodes(); ++n) v[n] = f(m.x_host(n, 0), m.x_host(n, 1), m.x_host(n, 2));
  return v;
}

// Smooth, sign-changing test fields (no symmetry that could hide an index error).
HostVector wiggly_field(const SmallMesh& m, double offset, double amplitude, double phase) {
  return nodal_field(m, [=](double x, double y, double z) {
    return offset + amplitude * std::sin(2.1 * x - 1.3 * y + 0.7 * z + phase) *
                        std::cos(0.9 * x + 1.7 * y - 1.1 * z + 0.5 * phase);
  });
}

// Auxiliary nodal data [phi_n, w_x, w_y, w_z, c_x, c_y, c_z, s (zero)]; `speed` 0 gives no
// convection, `dilatation` 0 no material velocity (w, with div w of that size).
NodalView make_aux(const SmallMesh& m, const HostVector& phi_n, double speed,
                   double dilatation = 0.0) {
  NodalView aux(std::string("aux"), m.n_nodes(), TransportPhysics::n_aux);
  auto h = Kokkos::create_mirror_view(aux);
  for (int n = 0; n < m.n_nodes(); ++n) {
    const double x = m.x_host(n, 0), y = m.x_host(n, 1), z = m.x_host(n, 2);
    h(n, 0) = phi_n[n];
    h(n, 1) = dilatation * (x + 0.2 * std::sin(y));
    h(n, 2) = dilatation * (0.5 * y * z - 0.3 * x);
    h(n, 3) = dilatation * std::cos(x + z);
    h(n, 4) = speed * (1.0 + 0.3 * std::sin(2.0 * y + z));
    h(n, 5) = speed * (0.4 * std::cos(1.5 * x - z));
    h(n, 6) = speed * (-0.25 + 0.2 * x * y);
  }
  Kokkos::deep_copy(aux, h);
  return aux;
}

// The real operator: transient (theta 0.66), convection with SUPG, per-block diffusivity, Monod
// consumption only in block 1 (the biofilm), coefficients chosen so that mass, diffusion,
// convection and reaction are all of comparable size on this mesh (cell Peclet ~ 2).
TransportPhysics full_physics(double half_saturation = 0.1) {
  TransportPhysics p;
  p.coef.diffusivity[0] = 0.05;
  p.coef.diffusivity[1] = 0.02;
  p.coef.monod_rate[1] = 2.0;
  p.coef.monod_half_saturation[1] = half_saturation;
  p.inv_dt = 4.0;
  p.theta = 0.66;
  p.supg = true;
  return p;
}

// Diffusion (per block) plus mass only: what the naive reference below computes.
TransportPhysics diffusion_mass_physics(double inv_dt) {
  TransportPhysics p;
  p.coef.diffusivity[0] = 0.05;
  p.coef.diffusivity[1] = 0.02;
  p.inv_dt = inv_dt;
  p.theta = 0.66;
  p.supg = true;  // no convection, so tau = 0: SUPG must not add anything
  return p;
}

HostVector residual(const TransportOperator& op, const ElementGroups& g, const HostVector& u) {
  return host_result(u.size(), [&](Vector r) { op.residual(g, to_device(u), r); });
}

HostVector tangent(const TransportOperator& op, const ElementGroups& g, const HostVector& u,
                   const HostVector& du) {
  return host_result(u.size(),
                     [&](Vector y) { op.apply_tangent(g, to_device(u), to_device(du), y); });
}

HostVector diagonal(const TransportOperator& op, const ElementGroups& g, const HostVector& u) {
  return host_result(u.size(), [&](Vector d) { op.diagonal(g, to_device(u), d); });
}

CsrMatrix assemble(const TransportOperator& op, const ElementGroups& g, const SmallMesh& m,
                   const HostVector& u) {
  CsrMatrix a = biofsi::test::make_pattern(m);
  op.assemble(g, to_device(u), a);
  return a;
}

double max_abs(const HostVector& a) {
  double s = 0;
  for (double v : a) s = std::max(s, std::abs(v));
  return s;
}

// max |a - b| / max |b|: relative to the largest entry, so that entries that are small by
// cancellation are judged by the size of the operator rather than by their own size.
double relative_difference(const HostVector& a, const HostVector& b) {
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d / max_abs(b);
}

HostVector axpy(double alpha, const HostVector& x, const HostVector& y) {
  HostVector z(y);
  for (size_t i = 0; i < z.size(); ++i) z[i] += alpha * x[i];
  return z;
}

HostVector subtract(const HostVector& a, const HostVector& b) { return axpy(-1.0, b, a); }

// (R(u + h v) - R(u - h v)) / (2h)
template <class Residual>
HostVector central_difference(Residual residual_of, const HostVector& u, const HostVector& v,
                              double h) {
  const HostVector rp = residual_of(axpy(h, v, u)), rm = residual_of(axpy(-h, v, u));
  HostVector fd(u.size());
  for (size_t i = 0; i < u.size(); ++i) fd[i] = (rp[i] - rm[i]) / (2 * h);
  return fd;
}

// ---- independent reference: trilinear shape functions evaluated directly in VTK order ----

double det3(const double c0[3], const double c1[3], const double c2[3]) {
  return c0[0] * (c1[1] * c2[2] - c1[2] * c2[1]) - c1[0] * (c0[1] * c2[2] - c0[2] * c2[1]) +
         c2[0] * (c0[1] * c1[2] - c0[2] * c1[1]);
}

// Element matrix of int (mass N_a N_b + diff grad N_a . grad N_b) with 2x2x2 Gauss points, with
// nothing shared with the kernels: shape functions from the VTK corner signs, the Jacobian summed
// directly, physical gradients by Cramer's rule on J^T g = grad_xi N.
void naive_element_matrix(const double xe[8][3], double mass, double diff, double ke[8][8]) {
  const double sign[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                             {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  const double g = 1.0 / std::sqrt(3.0);
  for (int a = 0; a < 8; ++a)
    for (int b = 0; b < 8; ++b) ke[a][b] = 0;
  for (int q = 0; q < 8; ++q) {
    const double xi[3] = {(q & 1) ? g : -g, (q & 2) ? g : -g, (q & 4) ? g : -g};
    double n[8], dn[8][3];
    for (int a = 0; a < 8; ++a) {
      double f[3], df[3];
      for (int d = 0; d < 3; ++d) {
        f[d] = 1 + sign[a][d] * xi[d];
        df[d] = sign[a][d];
      }
      n[a] = 0.125 * f[0] * f[1] * f[2];
      dn[a][0] = 0.125 * df[0] * f[1] * f[2];
      dn[a][1] = 0.125 * f[0] * df[1] * f[2];
      dn[a][2] = 0.125 * f[0] * f[1] * df[2];
    }
    double jac[3][3] = {};  // jac[c][d] = dx_c / dxi_d
    for (int a = 0; a < 8; ++a)
      for (int c = 0; c < 3; ++c)
        for (int d = 0; d < 3; ++d) jac[c][d] += xe[a][c] * dn[a][d];
    // Columns of J^T are the rows of J.
    const double det = det3(jac[0], jac[1], jac[2]);
    double grad[8][3];
    for (int a = 0; a < 8; ++a)
      for (int i = 0; i < 3; ++i) {
        const double* cols[3] = {jac[0], jac[1], jac[2]};
        cols[i] = dn[a];
        grad[a][i] = det3(cols[0], cols[1], cols[2]) / det;
      }
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b)
        ke[a][b] +=
            det * (mass * n[a] * n[b] + diff * (grad[a][0] * grad[b][0] + grad[a][1] * grad[b][1] +
                                                grad[a][2] * grad[b][2]));
  }
}

}  // namespace

TEST(TransportOperator, MatrixFreeTangentEqualsAssembledMatrixTimesVector) {
  const SmallMesh m = box_5x4x3();
  const HostVector u = wiggly_field(m, 0.4, 0.5, 0.0);  // crosses 0 in places: Monod both signs
  const HostVector phi_n = wiggly_field(m, 0.35, 0.4, 1.0);
  const HostVector du = wiggly_field(m, 0.1, 1.0, 2.3);
  const TransportOperator op(m.conn, m.x, m.block, make_aux(m, phi_n, 1.0), full_physics());
  const auto coloured = biofsi::test::element_groups(m, Scatter::Colored);
  const HostVector y = tangent(op, coloured, u, du);
  const HostVector ay = to_host(assemble(op, coloured, m, u)).multiply(du);
  EXPECT_LT(relative_difference(y, ay), 1e-12);
  // Same check with the kernels' own device CSR product.
  const CsrMatrix a = assemble(op, coloured, m, u);
  Vector yd(std::string("y"), u.size());
  csr_multiply(a, to_device(du), yd);
  EXPECT_LT(relative_difference(to_host(yd), y), 1e-12);
}

TEST(TransportOperator, MatrixFreeDiagonalEqualsAssembledDiagonal) {
  const SmallMesh m = box_5x4x3();
  const HostVector u = wiggly_field(m, 0.4, 0.5, 0.0);
  const HostVector phi_n = wiggly_field(m, 0.35, 0.4, 1.0);
  const TransportOperator op(m.conn, m.x, m.block, make_aux(m, phi_n, 1.0), full_physics());
  const auto coloured = biofsi::test::element_groups(m, Scatter::Colored);
  const HostVector d = diagonal(op, coloured, u);
  const CsrMatrix a = assemble(op, coloured, m, u);
  Vector ad(std::string("ad"), u.size());
  csr_diagonal(a, ad);
  EXPECT_LT(relative_difference(d, to_host(ad)), 1e-12);
  for (double v : d) EXPECT_GT(v, 0.0);  // mass + diffusion dominate: a sign error would show
}

TEST(TransportOperator, AssembledDiffusionAndMassEqualNaiveElementMatrices) {
  const SmallMesh m = box_5x4x3();
  const TransportPhysics p = diffusion_mass_physics(4.0);
  const HostVector u = wiggly_field(m, 0.4, 0.5, 0.0);  // linear operator: u must not matter
  const TransportOperator op(m.conn, m.x, m.block, make_aux(m, u, 0.0), p);
  const HostCsr a = to_host(assemble(op, biofsi::test::element_groups(m, Scatter::Atomic), m, u));

  const int n = m.n_nodes();
  std::vector<double> dense(static_cast<size_t>(n) * n, 0.0);
  for (int e = 0; e < m.n_elements(); ++e) {
    double xe[8][3], ke[8][8];
    for (int v = 0; v < 8; ++v)
      for (int d = 0; d < 3; ++d) xe[v][d] = m.x_host(m.conn_host(e, v), d);
    const int b = m.block_host(e);
    naive_element_matrix(xe, p.inv_dt, p.theta * p.coef.diffusivity[b], ke);
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 8; ++j)
        dense[static_cast<size_t>(m.conn_host(e, i)) * n + m.conn_host(e, j)] += ke[i][j];
  }
  // Every reference entry must sit in the pattern and match; the pattern holds nothing else.
  HostVector got, want;
  std::vector<char> in_pattern(dense.size(), 0);
  for (int r = 0; r < n; ++r)
    for (int k = a.row_ptr[r]; k < a.row_ptr[r + 1]; ++k) {
      got.push_back(a.val[k]);
      want.push_back(dense[static_cast<size_t>(r) * n + a.col[k]]);
      in_pattern[static_cast<size_t>(r) * n + a.col[k]] = 1;
    }
  for (size_t k = 0; k < dense.size(); ++k)
    if (!in_pattern[k]) {
      ASSERT_EQ(dense[k], 0.0) << "reference entry outside the pattern";
    }
  EXPECT_LT(relative_difference(got, want), 1e-12);
}

TEST(TransportTangent, MatchesFiniteDifferenceOfMonodResidualAcrossZero) {
  // Reaction only (no mass, diffusion or convection), so the Monod linearisation is all that is
  // compared. phi is of the size of K = 1e-3 and changes sign: the strongly nonlinear regime and
  // the odd extension for phi < 0. Block 0 uses K = 1 (nearly linear) for contrast.
  const SmallMesh m = box_5x4x3();
  TransportPhysics p;
  p.coef.monod_rate[0] = 1.5;
  p.coef.monod_half_saturation[0] = 1.0;
  p.coef.monod_rate[1] = 3.0;
  p.coef.monod_half_saturation[1] = 1e-3;
  p.inv_dt = 0;
  p.theta = 1;
  const HostVector u = wiggly_field(m, 2e-4, 3e-3, 0.4);
  const HostVector v = wiggly_field(m, 0.3, 1.0, 2.9);
  const TransportOperator op(m.conn, m.x, m.block, make_aux(m, u, 0.0), p);
  const auto groups = biofsi::test::element_groups(m, Scatter::Colored);
  int negative = 0, small = 0;
  for (double x : u) negative += x < 0, small += std::abs(x) < 1e-3;
  ASSERT_GT(negative, 10);
  ASSERT_GT(small, 10);
  // Step 1e-9 against |phi| ~ 1e-3 and K = 1e-3: truncation (h/(K+|phi|))^2 ~ 1e-12, cancellation
  // eps |R| / (h |R'|) ~ 1e-10. A point whose phi crosses 0 within the step loses only h/K ~ 1e-6
  // there, as the odd extension has a kink in R'.
  const HostVector fd =
      central_difference([&](const HostVector& w) { return residual(op, groups, w); }, u, v, 1e-9);
  const HostVector jv = tangent(op, groups, u, v);
  EXPECT_LT(relative_difference(jv, fd), 1e-6);
  // Same test at a moderate concentration, where the curvature is weak and a larger step is fine.
  const HostVector u2 = wiggly_field(m, 0.5, 0.3, 0.4);
  const HostVector fd2 =
      central_difference([&](const HostVector& w) { return residual(op, groups, w); }, u2, v, 1e-6);
  EXPECT_LT(relative_difference(tangent(op, groups, u2, v), fd2), 1e-6);
}

TEST(TransportTangent, MatchesFiniteDifferenceOfSupgResidual) {
  // The SUPG part alone: R_supg = R(supg on) - R(supg off), and likewise for the tangent. Its
  // residual carries the whole strong residual (mass, convection, Monod) times tau c.grad N_a.
  const SmallMesh m = box_5x4x3();
  const HostVector u = wiggly_field(m, 0.3, 0.4, 0.0);
  const HostVector phi_n = wiggly_field(m, 0.35, 0.4, 1.0);
  const HostVector v = wiggly_field(m, 0.1, 1.0, 2.3);
  TransportPhysics on = full_physics(0.05), off = on;
  off.supg = false;
  const NodalView aux = make_aux(m, phi_n, 1.0);
  const TransportOperator op_on(m.conn, m.x, m.block, aux, on),
      op_off(m.conn, m.x, m.block, aux, off);
  const auto groups = biofsi::test::element_groups(m, Scatter::Colored);
  auto supg_residual = [&](const HostVector& w) {
    return subtract(residual(op_on, groups, w), residual(op_off, groups, w));
  };
  const HostVector jv = subtract(tangent(op_on, groups, u, v), tangent(op_off, groups, u, v));
  ASSERT_GT(max_abs(jv), 1e-3 * max_abs(tangent(op_on, groups, u, v)));  // SUPG is really on
  // Step 1e-6 against |phi| >= ~0.1 and K = 0.05: truncation ~ (h/K)^2 ~ 1e-9.
  EXPECT_LT(relative_difference(jv, central_difference(supg_residual, u, v, 1e-6)), 1e-6);
}

// With every term on, including the Phi div w of a deforming solid in block 1 (eq. 9).
TEST(TransportTangent, MatchesFiniteDifferenceOfFullTransientResidual) {
  const SmallMesh m = box_5x4x3();
  const HostVector u = wiggly_field(m, 0.2, 0.4, 0.0);
  const HostVector phi_n = wiggly_field(m, 0.35, 0.4, 1.0);
  const HostVector v = wiggly_field(m, 0.1, 1.0, 2.3);
  TransportPhysics p = full_physics(0.05);
  p.coef.material_motion[1] = 1;
  const TransportOperator op(m.conn, m.x, m.block, make_aux(m, phi_n, 1.0, 0.5), p);
  const auto groups = biofsi::test::element_groups(m, Scatter::Atomic);
  const HostVector fd =
      central_difference([&](const HostVector& w) { return residual(op, groups, w); }, u, v, 1e-6);
  EXPECT_LT(relative_difference(tangent(op, groups, u, v), fd), 1e-6);
}

TEST(TransportOperator, ColouredAndAtomicScatterGiveTheSameResults) {
  const SmallMesh m = box_5x4x3();
  const auto colours = biofsi::test::colour_elements(m);
  // The colouring itself must be valid, or the coloured run would race.
  for (const auto& group : colours) {
    std::vector<char> touched(m.n_nodes(), 0);
    for (int e : group)
      for (int a = 0; a < 8; ++a) {
        ASSERT_FALSE(touched[m.conn_host(e, a)]) << "two elements of one colour share a node";
        touched[m.conn_host(e, a)] = 1;
      }
  }
  ASSERT_GT(colours.size(), 1u);
  const HostVector u = wiggly_field(m, 0.4, 0.5, 0.0);
  const HostVector phi_n = wiggly_field(m, 0.35, 0.4, 1.0);
  const HostVector du = wiggly_field(m, 0.1, 1.0, 2.3);
  const TransportOperator op(m.conn, m.x, m.block, make_aux(m, phi_n, 1.0), full_physics());
  const auto coloured = biofsi::test::element_groups(m, Scatter::Colored);
  const auto atomic = biofsi::test::element_groups(m, Scatter::Atomic);
  EXPECT_LT(relative_difference(residual(op, coloured, u), residual(op, atomic, u)), 1e-13);
  EXPECT_LT(relative_difference(tangent(op, coloured, u, du), tangent(op, atomic, u, du)), 1e-13);
  EXPECT_LT(relative_difference(diagonal(op, coloured, u), diagonal(op, atomic, u)), 1e-13);
  EXPECT_LT(relative_difference(to_host(assemble(op, coloured, m, u)).val,
                                to_host(assemble(op, atomic, m, u)).val),
            1e-13);
}

TEST(TransportOperator, ConstantFieldHasZeroResidualOnDistortedMesh) {
  // A constant that equals the old solution: no time change, zero gradient, so every row vanishes
  // up to the round-off of summing that row (40 eps times its absolute sum, times the constant).
  const SmallMesh m = box_5x4x3();
  const double value = 0.7;
  const HostVector u(m.n_nodes(), value);
  for (double speed : {0.0, 1.0}) {  // without convection, as asked; with it (and SUPG), as well
    const TransportOperator op(m.conn, m.x, m.block, make_aux(m, u, speed),
                               diffusion_mass_physics(4.0));
    const auto groups = biofsi::test::element_groups(m, Scatter::Colored);
    const HostVector r = residual(op, groups, u);
    const HostCsr a = to_host(assemble(op, groups, m, u));
    for (int i = 0; i < m.n_nodes(); ++i) {
      double row = 0;
      for (int k = a.row_ptr[i]; k < a.row_ptr[i + 1]; ++k) row += std::abs(a.val[k]);
      EXPECT_LE(std::abs(r[i]), 40 * eps * row * value) << "node " << i << " speed " << speed;
    }
  }
}

TEST(TransportOperator, DiffusionPartAnnihilatesConstants) {
  const SmallMesh m = box_5x4x3();
  const HostVector u = wiggly_field(m, 0.4, 0.5, 0.0);
  const TransportOperator op(m.conn, m.x, m.block, make_aux(m, u, 0.0),
                             diffusion_mass_physics(0.0));
  const auto groups = biofsi::test::element_groups(m, Scatter::Colored);
  const HostCsr a = to_host(assemble(op, groups, m, u));
  const HostVector ones(m.n_nodes(), 1.0);
  const HostVector y = tangent(op, groups, u, ones);
  for (int i = 0; i < m.n_nodes(); ++i) {
    double sum = 0, abs_sum = 0;
    for (int k = a.row_ptr[i]; k < a.row_ptr[i + 1]; ++k)
      sum += a.val[k], abs_sum += std::abs(a.val[k]);
    EXPECT_LE(std::abs(sum), 40 * eps * abs_sum) << "row " << i;
    EXPECT_LE(std::abs(y[i]), 40 * eps * abs_sum) << "row " << i;
  }
}
