// Generic element-loop drivers: gather, evaluate pointwise physics at each quadrature point,
// integrate back, scatter. One pointwise definition gives the residual, the tangent action, the
// diagonal and the assembled element matrices (STYLE.md 3).
//
// A Physics type provides
//   static constexpr int n_components, n_aux;
//   KOKKOS_INLINE_FUNCTION void residual(const QpData<n_aux>&, const Real u[NC],
//       const Real gu[NC][3], Real f0[NC], Real f1[NC][3]) const;
//   KOKKOS_INLINE_FUNCTION void tangent(const QpData<n_aux>&, const Real u[NC],
//       const Real gu[NC][3], const Real du[NC], const Real gdu[NC][3], Real df0[NC],
//       Real df1[NC][3]) const;
// and optionally `static constexpr int n_aux_gradients` (default n_aux): only the first that many
// auxiliary columns get gradients in QpData, the rest values only (a third of the work each),
// with the weak residual r_a = sum_q w detJ (N_a f0 + grad N_a . f1) and tangent the directional
// derivative of (f0, f1) along du. Auxiliary nodal data (old solution, convective velocity, ...)
// arrive interpolated with their gradients in QpData.
#pragma once

#include <type_traits>
#include <vector>

#include "csr.hpp"
#include "hex8.hpp"

namespace biofsi {

template <int NA>
struct QpData {
  Real x[3];
  Real metric[3][3];  // G_ij = sum_d dxi_d/dx_i dxi_d/dx_j, for stabilisation lengths
  Real det;           // det of dx/dxi (reference cell [-1,1]^3), for Jacobian-based stiffening
  int block;
  Real aux[NA > 0 ? NA : 1];
  Real grad_aux[NA > 0 ? NA : 1][3];
};

// How contributions of elements that share a node are made race-free.
enum class Scatter { Atomic, Colored };

// The elements a loop visits, in groups that may run concurrently: one group with atomic scatter,
// or one group per colour (no two elements of a colour share a node) with plain adds.
struct ElementGroups {
  std::vector<ConstIndexView> groups;
  Scatter scatter = Scatter::Atomic;
};

// Greedy colouring on the host: each of `items` (ids below n) in turn takes the smallest colour
// that no item it conflicts with has taken; for_conflicts(i, visit) calls visit(j) for each item j
// that conflicts with i (shares a node with it). Returns the items of each colour.
template <class ForConflicts>
std::vector<std::vector<int>> greedy_colouring(const std::vector<int>& items, int n,
                                               ForConflicts for_conflicts) {
  std::vector<int> colour(n, -1);
  std::vector<std::vector<int>> groups;
  for (int i : items) {
    std::vector<char> used(groups.size() + 1, 0);
    for_conflicts(i, [&](int j) {
      if (colour[j] >= 0) used[colour[j]] = 1;
    });
    int c = 0;
    while (used[c]) ++c;
    colour[i] = c;
    if (c == static_cast<int>(groups.size())) groups.emplace_back();
    groups[c].push_back(i);
  }
  return groups;
}

namespace detail {

// Physics::n_aux_gradients if declared, else Physics::n_aux.
template <class Physics, class = void>
struct AuxGradients {
  static constexpr int value = Physics::n_aux;
};
template <class Physics>
struct AuxGradients<Physics, std::void_t<decltype(Physics::n_aux_gradients)>> {
  static constexpr int value = Physics::n_aux_gradients;
};

KOKKOS_INLINE_FUNCTION void accumulate(bool atomic, Real* target, Real value) {
  if (atomic)
    Kokkos::atomic_add(target, value);
  else
    *target += value;
}

struct ResidualTag {};
struct TangentTag {};
struct DiagonalTag {};
struct AssembleTag {};

// Whether a Physics declares point states: the tangent's dependence on the linearisation point
// condensed into PointState<T> (members of type T only), with
//   PointState<Real> point_state(const QpData&, u, grad u) const;
//   template <class T> void tangent_at(const PointState<T>&, du, grad du, df0, df1) const;
// and tangent() = tangent_at(point_state(...)).
template <class Physics, class = void>
struct HasPointState : std::false_type {};
template <class Physics>
struct HasPointState<Physics, std::void_t<typename Physics::template PointState<Real>>>
    : std::true_type {};

// The tangent at one point as a function of (du, grad du): tangent_at of the point state,
// evaluated once, where the Physics declares point states; its tangent() otherwise.
template <class Physics, int NC, bool FromState>
struct PointTangent {
  using QP = QpData<Physics::n_aux>;
  const Physics& physics;
  const QP& qp;
  const Real (&u)[NC];
  const Real (&gu)[NC][3];
  KOKKOS_INLINE_FUNCTION PointTangent(const Physics& p, const QP& q, const Real (&uq)[NC],
                                      const Real (&g)[NC][3])
      : physics(p), qp(q), u(uq), gu(g) {}
  KOKKOS_INLINE_FUNCTION void operator()(const Real du[NC], const Real gdu[NC][3], Real r0[NC],
                                         Real r1[NC][3]) const {
    physics.tangent(qp, u, gu, du, gdu, r0, r1);
  }
};
template <class Physics, int NC>
struct PointTangent<Physics, NC, true> {
  const Physics& physics;
  typename Physics::template PointState<Real> state;
  KOKKOS_INLINE_FUNCTION PointTangent(const Physics& p, const QpData<Physics::n_aux>& q,
                                      const Real (&uq)[NC], const Real (&g)[NC][3])
      : physics(p), state(p.point_state(q, uq, g)) {}
  KOKKOS_INLINE_FUNCTION void operator()(const Real du[NC], const Real gdu[NC][3], Real r0[NC],
                                         Real r1[NC][3]) const {
    physics.tangent_at(state, du, gdu, r0, r1);
  }
};

template <class Physics, class Basis>
struct ElementLoop {
  static constexpr int NC = Physics::n_components, NA = Physics::n_aux;
  static constexpr int NN = Basis::n_nodes, NQ = Basis::n_qp;
  static constexpr int NG = AuxGradients<Physics>::value;

  ConstIndexView elements;
  ConstConnView conn;
  ConstCoordView coords;
  ConstIndexView element_block;
  ConstNodalView aux;
  Physics physics;
  ConstVector u, du;
  Vector out;
  CsrMatrix matrix;
  bool atomic;

  struct Gathered {
    int node[NN];
    ElementGeometry<Basis> geo;
    Real uq[NC][NQ], gu[NC][NQ][3];  // physical gradients
    QpData<NA> qp[NQ];
  };

  KOKKOS_INLINE_FUNCTION void interpolate_nodal(const Real (*nodal)[NN], int n, Real (*val)[NQ],
                                                Real (*grad)[NQ][3],
                                                const ElementGeometry<Basis>& geo) const {
    for (int c = 0; c < n; ++c) {
      Real ref[NQ][3];
      interpolate_with_gradient<Basis>(nodal[c], val[c], ref);
      for (int q = 0; q < NQ; ++q) physical_gradient(geo.inv[q], ref[q], grad[c][q]);
    }
  }

  KOKKOS_INLINE_FUNCTION void gather(int e, Gathered& g) const {
    Real xe[NN][3];
    for (int a = 0; a < NN; ++a) {
      g.node[a] = conn(e, vtk_of_lex(a));
      for (int d = 0; d < 3; ++d) xe[a][d] = coords(g.node[a], d);
    }
    g.geo.compute(xe);
    Real ue[NC][NN];
    for (int a = 0; a < NN; ++a)
      for (int c = 0; c < NC; ++c) ue[c][a] = u(g.node[a] * NC + c);
    interpolate_nodal(ue, NC, g.uq, g.gu, g.geo);
    constexpr int NAX = NA > 0 ? NA : 1;
    Real ae[NAX][NN], aq[NAX][NQ], ga[NAX][NQ][3];
    for (int a = 0; a < NN; ++a)
      for (int c = 0; c < NA; ++c) ae[c][a] = aux(g.node[a], c);
    interpolate_nodal(ae, NG, aq, ga, g.geo);
    for (int c = NG; c < NA; ++c) {
      interpolate_values<Basis>(ae[c], aq[c]);
      for (int q = 0; q < NQ; ++q) ga[c][q][0] = ga[c][q][1] = ga[c][q][2] = 0;
    }
    const int block = element_block(e);
    for (int q = 0; q < NQ; ++q) {
      QpData<NA>& d = g.qp[q];
      d.block = block;
      d.det = g.geo.det[q];
      for (int i = 0; i < 3; ++i) {
        d.x[i] = g.geo.x[q][i];
        for (int j = 0; j < 3; ++j) {
          Real s = 0;
          for (int k = 0; k < 3; ++k) s += g.geo.inv[q][k][i] * g.geo.inv[q][k][j];
          d.metric[i][j] = s;
        }
      }
      for (int c = 0; c < NA; ++c) {
        d.aux[c] = aq[c][q];
        for (int i = 0; i < 3; ++i) d.grad_aux[c][i] = ga[c][q][i];
      }
    }
  }

  // Integrates (f0, f1) at the points against all test functions and scatters into `out`.
  KOKKOS_INLINE_FUNCTION void integrate_and_scatter(const Gathered& g, Real (*f0)[NQ],
                                                    Real (*f1)[NQ][3]) const {
    for (int c = 0; c < NC; ++c) {
      Real ref[NQ][3], w0[NQ];
      for (int q = 0; q < NQ; ++q) {
        reference_flux(g.geo.inv[q], f1[c][q], ref[q]);
        for (int d = 0; d < 3; ++d) ref[q][d] *= g.geo.wdet[q];
        w0[q] = f0[c][q] * g.geo.wdet[q];
      }
      Real re[NN];
      integrate_value_and_gradient<Basis>(w0, ref, re);
      for (int a = 0; a < NN; ++a) accumulate(atomic, &out(g.node[a] * NC + c), re[a]);
    }
  }

  KOKKOS_INLINE_FUNCTION void operator()(ResidualTag, int i) const {
    Gathered g;
    gather(elements(i), g);
    Real f0[NC][NQ], f1[NC][NQ][3];
    for (int q = 0; q < NQ; ++q) {
      Real uq[NC], gu[NC][3], r0[NC], r1[NC][3];
      for (int c = 0; c < NC; ++c) {
        uq[c] = g.uq[c][q];
        for (int d = 0; d < 3; ++d) gu[c][d] = g.gu[c][q][d];
      }
      physics.residual(g.qp[q], uq, gu, r0, r1);
      for (int c = 0; c < NC; ++c) {
        f0[c][q] = r0[c];
        for (int d = 0; d < 3; ++d) f1[c][q][d] = r1[c][d];
      }
    }
    integrate_and_scatter(g, f0, f1);
  }

  KOKKOS_INLINE_FUNCTION void operator()(TangentTag, int i) const {
    Gathered g;
    const int e = elements(i);
    gather(e, g);
    Real de[NC][NN], dq[NC][NQ], gd[NC][NQ][3];
    for (int a = 0; a < NN; ++a)
      for (int c = 0; c < NC; ++c) de[c][a] = du(g.node[a] * NC + c);
    interpolate_nodal(de, NC, dq, gd, g.geo);
    Real f0[NC][NQ], f1[NC][NQ][3];
    for (int q = 0; q < NQ; ++q) {
      Real uq[NC], gu[NC][3], duq[NC], gdu[NC][3], r0[NC], r1[NC][3];
      for (int c = 0; c < NC; ++c) {
        uq[c] = g.uq[c][q];
        duq[c] = dq[c][q];
        for (int d = 0; d < 3; ++d) {
          gu[c][d] = g.gu[c][q][d];
          gdu[c][d] = gd[c][q][d];
        }
      }
      physics.tangent(g.qp[q], uq, gu, duq, gdu, r0, r1);
      for (int c = 0; c < NC; ++c) {
        f0[c][q] = r0[c];
        for (int d = 0; d < 3; ++d) f1[c][q][d] = r1[c][d];
      }
    }
    integrate_and_scatter(g, f0, f1);
  }

  static constexpr int ND = NN * NC;  // rows (and columns) of the element matrix

  // The element matrix point by point, row a NC + c and column b NC + cb: the tangent at a point
  // (its state evaluated once) along every basis function N_b e_cb, so that a Physics with point
  // states evaluates them NQ times per element, not NQ NN NC times as column by column.
  KOKKOS_INLINE_FUNCTION void element_matrix(const Gathered& g, Real (*ke)[ND]) const {
    for (int r = 0; r < ND; ++r)
      for (int s = 0; s < ND; ++s) ke[r][s] = 0;
    for (int q = 0; q < NQ; ++q) {
      Real n[NN], grad[NN][3];
      for (int a = 0; a < NN; ++a) {
        Real gref[3];
        basis_at_point<Basis>(a, q, n[a], gref);
        physical_gradient(g.geo.inv[q], gref, grad[a]);
      }
      Real uq[NC], gu[NC][3];
      for (int c = 0; c < NC; ++c) {
        uq[c] = g.uq[c][q];
        for (int d = 0; d < 3; ++d) gu[c][d] = g.gu[c][q][d];
      }
      const PointTangent<Physics, NC, HasPointState<Physics>::value> tangent(physics, g.qp[q], uq,
                                                                             gu);
      for (int b = 0; b < NN; ++b)
        for (int cb = 0; cb < NC; ++cb) {
          Real du[NC], gdu[NC][3], r0[NC], r1[NC][3];
          for (int c = 0; c < NC; ++c) {
            du[c] = c == cb ? n[b] : 0.0;
            for (int d = 0; d < 3; ++d) gdu[c][d] = c == cb ? grad[b][d] : 0.0;
          }
          tangent(du, gdu, r0, r1);
          for (int a = 0; a < NN; ++a)
            for (int c = 0; c < NC; ++c)
              ke[a * NC + c][b * NC + cb] +=
                  g.geo.wdet[q] * (n[a] * r0[c] + grad[a][0] * r1[c][0] + grad[a][1] * r1[c][1] +
                                   grad[a][2] * r1[c][2]);
        }
    }
  }

  KOKKOS_INLINE_FUNCTION void operator()(DiagonalTag, int i) const {
    Gathered g;
    gather(elements(i), g);
    Real ke[ND][ND];
    element_matrix(g, ke);
    for (int b = 0; b < NN; ++b)
      for (int cb = 0; cb < NC; ++cb)
        accumulate(atomic, &out(g.node[b] * NC + cb), ke[b * NC + cb][b * NC + cb]);
  }

  KOKKOS_INLINE_FUNCTION void operator()(AssembleTag, int i) const {
    Gathered g;
    gather(elements(i), g);
    Real ke[ND][ND];
    element_matrix(g, ke);
    const int* rp = matrix.row_ptr.data();
    const int* cols = matrix.col.data();
    for (int b = 0; b < NN; ++b)
      for (int cb = 0; cb < NC; ++cb) {
        const int j = g.node[b] * NC + cb;
        for (int a = 0; a < NN; ++a)
          for (int c = 0; c < NC; ++c) {
            const int k = csr_find(rp, cols, g.node[a] * NC + c, j);
            accumulate(atomic, &matrix.val(k), ke[a * NC + c][b * NC + cb]);
          }
      }
  }
};

}  // namespace detail

// Binds a Physics to a mesh; every method accumulates (+=) into its output, so callers zero first
// and may sum several element sets (blocks) and boundary terms.
template <class Physics, class Basis = Hex8>
class ElementOperator {
 public:
  static constexpr int n_components = Physics::n_components;

  ElementOperator(ConstConnView conn, ConstCoordView coords, ConstIndexView element_block,
                  ConstNodalView aux, const Physics& physics)
      : conn_(conn), coords_(coords), block_(element_block), aux_(aux), physics_(physics) {}

  void set_physics(const Physics& physics) { physics_ = physics; }
  void set_aux(ConstNodalView aux) { aux_ = aux; }
  void set_coords(ConstCoordView coords) { coords_ = coords; }
  const Physics& physics() const { return physics_; }

  void residual(const ElementGroups& set, ConstVector u, Vector r) const {
    run<detail::ResidualTag>("biofsi::residual", set, u, u, r, CsrMatrix{});
  }
  void apply_tangent(const ElementGroups& set, ConstVector u, ConstVector du, Vector y) const {
    run<detail::TangentTag>("biofsi::tangent", set, u, du, y, CsrMatrix{});
  }
  void diagonal(const ElementGroups& set, ConstVector u, Vector d) const {
    run<detail::DiagonalTag>("biofsi::diagonal", set, u, u, d, CsrMatrix{});
  }
  void assemble(const ElementGroups& set, ConstVector u, const CsrMatrix& a) const {
    run<detail::AssembleTag>("biofsi::assemble", set, u, u, Vector{}, a);
  }

  // The element loop bound to this operator's mesh and physics (for drivers built on top of it,
  // e.g. the stored tangent's linearisation).
  detail::ElementLoop<Physics, Basis> element_loop(ConstVector u, ConstVector du, Vector out,
                                                   const CsrMatrix& a = {},
                                                   bool atomic = true) const {
    return {ConstIndexView{}, conn_, coords_, block_, aux_, physics_, u, du, out, a, atomic};
  }

 private:
  template <class Tag>
  void run(const char* label, const ElementGroups& set, ConstVector u, ConstVector du, Vector out,
           const CsrMatrix& a) const {
    auto loop = element_loop(u, du, out, a, set.scatter == Scatter::Atomic);
    for (const auto& group : set.groups) {
      loop.elements = group;
      Kokkos::parallel_for(
          label, Kokkos::RangePolicy<ExecSpace, Tag>(0, static_cast<int>(group.extent(0))), loop);
    }
  }

  ConstConnView conn_;
  ConstCoordView coords_;
  ConstIndexView block_;
  ConstNodalView aux_;
  Physics physics_;
};

}  // namespace biofsi
