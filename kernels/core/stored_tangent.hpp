// The tangent stored at the quadrature points: what a Krylov solve applies many times at one
// linearisation point.
//
// At one point the tangent of any Physics is a linear map from (du, grad du) to (df0, df1), i.e. a
// (4 NC) x (4 NC) matrix. `linearise` evaluates it once per Newton linearisation through the
// Physics' own `tangent` (so residual, tangent, diagonal and assembly still share one pointwise
// definition) and folds in everything that depends only on the linearisation point and the
// geometry: the quadrature weight times det J and the inverse Jacobians on both sides, so that
// the stored matrix acts on reference values and gradients directly. The apply is then gather,
// sum-factorised interpolation, one small matrix-vector product per point, sum-factorised
// integration and scatter: no geometry, no auxiliary fields, no stabilisation parameters, no
// transcendental functions per Krylov iteration.
//
// Elements are processed in batches of `simd_width` (8 on the CPU) taken from one element group,
// with the stored data laid out [batch][entry][lane], so that every arithmetic operation of the
// apply is a packed one over the batch's elements (kernels/core/simd.hpp). On CUDA a batch is one
// element and the layout puts consecutive elements next to each other (coalesced loads).
//
// Cost per element and apply (hex8, 8 points): the stored matrices are 8 (4 NC)^2 doubles, 1 KiB
// for a scalar field and 16 KiB for the fluid's 4 components, less where the Physics declares a
// symmetric or block-decoupled map (3 KiB for the structure and mesh motion). A Physics whose
// tangent is cheap given a small per-point state can store that state and the geometry instead
// (StoredPointStates: the fluid, 34 doubles per point instead of 256; mesh motion, 11 instead of
// 45; transport, 16 like its map, but its linearisation then evaluates SUPG's tau once per point)
// and have its tangent evaluated on SIMD packs. Against either, the on-the-fly apply recomputes
// geometry, interpolates every auxiliary field with gradients and evaluates the physics at every
// point (bench/README.md has the measured bytes and rates).
//
// The same store can hold what a Physics' residual needs of a time step's data (StepStates:
// transport, 13 doubles per point plus the geometry), taken once when a Newton solve starts; each
// iteration's residual and linearisation are then evaluated from it on SIMD packs, reading only
// the unknown (case (a) of the main job: the transport's residual and linearisation 2.5x cheaper).
#pragma once

#include <vector>

#include "element_loop.hpp"
#include "simd.hpp"

namespace biofsi {

// Which entries of the local map are stored. A Physics may declare
//   static constexpr bool tangent_symmetric = true;  // the map is symmetric (hyperelasticity)
//   static constexpr bool tangent_couples_values_and_gradients = false;  // df0 only from du, df1
//                                                                       // only from grad du
// Then only the upper triangle and only the non-zero blocks are stored: 48 instead of 144 entries
// per point for the structure, 45 for mesh motion.
template <int NC, bool Symmetric = false, bool Coupled = true>
struct TangentPattern {
  static constexpr int n_local = 4 * NC;  // value and 3 reference gradients per component
  static constexpr bool symmetric = Symmetric;
  KOKKOS_INLINE_FUNCTION static constexpr bool stored(int k, int l) {
    return (!Symmetric || k <= l) && (Coupled || (k % 4 == 0) == (l % 4 == 0));
  }
  static constexpr int count() {
    int n = 0;
    for (int k = 0; k < n_local; ++k)
      for (int l = 0; l < n_local; ++l) n += stored(k, l) ? 1 : 0;
    return n;
  }
  static constexpr int n_entries = count();  // per quadrature point
};

namespace detail {
template <class Physics, class = void>
struct DeclaredSymmetric : std::false_type {};
template <class Physics>
struct DeclaredSymmetric<Physics, std::void_t<decltype(Physics::tangent_symmetric)>>
    : std::integral_constant<bool, Physics::tangent_symmetric> {};
template <class Physics, class = void>
struct DeclaredCoupled : std::true_type {};
template <class Physics>
struct DeclaredCoupled<Physics,
                       std::void_t<decltype(Physics::tangent_couples_values_and_gradients)>>
    : std::integral_constant<bool, Physics::tangent_couples_values_and_gradients> {};
}  // namespace detail

// The pattern a Physics declares.
template <class Physics>
using PatternOf = TangentPattern<Physics::n_components, detail::DeclaredSymmetric<Physics>::value,
                                 detail::DeclaredCoupled<Physics>::value>;

// Elements in batches of W taken from the groups of an ElementGroups, in the groups' order.
template <int W>
struct ElementBatches {
  // On a GPU (one element per thread) consecutive elements side by side, for coalesced loads; on
  // the CPU each batch's data contiguous, whatever its width.
  using Layout =
      std::conditional_t<W == 1 && simd_width == 1, Kokkos::LayoutLeft, Kokkos::LayoutRight>;

  // Batches of group g: [group_offset[g], group_offset[g + 1]).
  std::vector<int> group_offset;
  Scatter scatter = Scatter::Atomic;
  // Lexicographic node ids of each batch's lanes; -1 in the padding lanes of a group's last batch.
  Kokkos::View<int** [W], Layout, MemSpace> nodes;
};

template <class Pattern, int W = simd_width>
struct StoredTangent : ElementBatches<W> {
  static constexpr int n_local = Pattern::n_local, n_entries = Pattern::n_entries;
  // Per batch, point q and stored entry e (row-major over the pattern's stored (k, l)):
  // matrix(batch, q n_entries + e, lane).
  Kokkos::View<Real** [W], typename ElementBatches<W>::Layout, MemSpace> matrix;

  std::size_t bytes() const {
    return matrix.span() * sizeof(Real) + this->nodes.span() * sizeof(int);
  }
};

// For a Physics whose tangent is a cheap function of a small per-point state (it declares
//   template <class T> struct PointState { T ...; };            // T members only
//   PointState<Real> point_state(const QpData&, u, grad u) const;
//   template <class T> void tangent_at(const PointState<T>&, du, grad du, df0, df1) const;
// with tangent() = tangent_at(point_state(...))): the state, the inverse Jacobian and w det J per
// point are stored instead of the map, and the apply evaluates tangent_at on SIMD packs. The
// fluid's dense 16 x 16 map (256 doubles per point) becomes 24 + 10.
// Which per-point state a StoredPointStates holds and what is evaluated from it on SIMD packs.
//  TangentStates: Physics::PointState at a linearisation point; applied, the tangent along du.
//  StepStates: Physics::StepState, what the residual needs of a time step's data (auxiliary
//    fields, coefficients, stabilisation) without the unknown, declared as
//      template <class T> struct StepState { T ...; };
//      StepState<Real> step_state(const QpData&) const;
//      template <class T> void residual_at(const StepState<T>&, u, grad u, f0, f1) const;
//      template <class T> PointState<T> point_state_at(const StepState<T>&, u, grad u) const;
//    with residual() and point_state() defined through them. Stored once per step, each Newton
//    iteration's residual (residual_stored) and linearisation (linearise_from_step_states) are a
//    pass over the unknown alone.
struct TangentStates {
  template <class Physics, class T>
  using State = typename Physics::template PointState<T>;
  template <class Physics, class U, class G>
  KOKKOS_INLINE_FUNCTION static State<Physics, Real> evaluate(const Physics& p,
                                                              const QpData<Physics::n_aux>& q,
                                                              const U& u, const G& gu) {
    return p.point_state(q, u, gu);
  }
  template <class Physics, class T, class X, class GX, class F0, class F1>
  KOKKOS_INLINE_FUNCTION static void apply(const Physics& p, const State<Physics, T>& s, const X& x,
                                           const GX& gx, F0& f0, F1& f1) {
    p.tangent_at(s, x, gx, f0, f1);
  }
};
struct StepStates {
  template <class Physics, class T>
  using State = typename Physics::template StepState<T>;
  template <class Physics, class U, class G>
  KOKKOS_INLINE_FUNCTION static State<Physics, Real> evaluate(const Physics& p,
                                                              const QpData<Physics::n_aux>& q,
                                                              const U&, const G&) {
    return p.step_state(q);
  }
  template <class Physics, class T, class X, class GX, class F0, class F1>
  KOKKOS_INLINE_FUNCTION static void apply(const Physics& p, const State<Physics, T>& s, const X& x,
                                           const GX& gx, F0& f0, F1& f1) {
    p.residual_at(s, x, gx, f0, f1);
  }
};

template <class Physics, int W = simd_width, class Kind = TangentStates>
struct StoredPointStates : ElementBatches<W> {
  using State = typename Kind::template State<Physics, Real>;
  static constexpr int n_state = sizeof(State) / sizeof(Real);
  static constexpr int n_entries = n_state + 10;  // state, inv J (row-major), w det J
  static_assert(sizeof(State) == n_state * sizeof(Real), "a state must hold T members only");
  Physics physics;  // the parameters tangent_at reads
  // data(batch, q n_entries + e, lane)
  Kokkos::View<Real** [W], typename ElementBatches<W>::Layout, MemSpace> data;

  std::size_t bytes() const {
    return data.span() * sizeof(Real) + this->nodes.span() * sizeof(int);
  }
};

// The store type of an operator's Physics.
template <class Physics, int W = simd_width>
using StoredTangentOf = StoredTangent<PatternOf<Physics>, W>;

namespace detail {

// Fills one lane of the store from the Physics' tangent at the linearisation point u.
template <class Physics, class Basis, int W>
struct LineariseLoop {
  using Pattern = PatternOf<Physics>;
  using Store = StoredTangent<Pattern, W>;
  static constexpr int NC = Physics::n_components, NM = Pattern::n_local;
  static constexpr int NE = Pattern::n_entries, NN = Basis::n_nodes, NQ = Basis::n_qp;

  ElementLoop<Physics, Basis> element;
  ConstIndexView group;
  int batch_offset;
  decltype(Store::nodes) nodes;
  decltype(Store::matrix) matrix;

  KOKKOS_INLINE_FUNCTION void operator()(int i) const {
    const int b = batch_offset + i / W, l = i % W;
    if (i >= static_cast<int>(group.extent(0))) {
      for (int a = 0; a < NN; ++a) nodes(b, a, l) = -1;
      for (int k = 0; k < NQ * NE; ++k) matrix(b, k, l) = 0;
      return;
    }
    typename ElementLoop<Physics, Basis>::Gathered g;
    element.gather(group(i), g);
    for (int a = 0; a < NN; ++a) nodes(b, a, l) = g.node[a];
    for (int q = 0; q < NQ; ++q) {
      const auto& inv = g.geo.inv[q];
      Real uq[NC], gu[NC][3];
      for (int c = 0; c < NC; ++c) {
        uq[c] = g.uq[c][q];
        for (int d = 0; d < 3; ++d) gu[c][d] = g.gu[c][q][d];
      }
      // A Physics with point states evaluates its state once per point, not once per column.
      const PointTangent<Physics, NC, HasPointState<Physics>::value> tangent(element.physics,
                                                                             g.qp[q], uq, gu);
      // Column `col` of the local map: the input is a unit value (j = 0) or a unit reference
      // gradient along j - 1 of component cc, whose physical gradient is that row of inv.
      Real local[NM][NM];
      for (int col = 0; col < NM; ++col) {
        const int cc = col / 4, j = col % 4;
        Real du[NC], gdu[NC][3], r0[NC], r1[NC][3];
        for (int c = 0; c < NC; ++c) {
          du[c] = (c == cc && j == 0) ? 1.0 : 0.0;
          for (int d = 0; d < 3; ++d) gdu[c][d] = (c == cc && j > 0) ? inv[j - 1][d] : 0.0;
        }
        tangent(du, gdu, r0, r1);
        for (int c = 0; c < NC; ++c) {
          Real ref[3];
          reference_flux(inv, r1[c], ref);
          local[4 * c][col] = g.geo.wdet[q] * r0[c];
          for (int d = 0; d < 3; ++d) local[4 * c + 1 + d][col] = g.geo.wdet[q] * ref[d];
        }
      }
      int e = q * NE;
      for (int k = 0; k < NM; ++k)
        for (int m = 0; m < NM; ++m)
          if (Pattern::stored(k, m)) matrix(b, e++, l) = local[k][m];
    }
  }
};

// du of a batch's nodes, one element per lane (zero in padding lanes).
template <int NC, int NN, class Nodes, class T>
KOKKOS_INLINE_FUNCTION void gather_batch(const Nodes& nodes, int b, const ConstVector& du,
                                         T (*de)[NN]) {
  constexpr int W = Nodes::rank == 3 ? static_cast<int>(Nodes::static_extent(2)) : 1;
  for (int a = 0; a < NN; ++a)
    for (int l = 0; l < W; ++l) {
      const int n = nodes(b, a, l);
      for (int c = 0; c < NC; ++c) lane(de[c][a], l) = n >= 0 ? du(n * NC + c) : 0.0;
    }
}

// Integrates a batch's (f0, f1) (reference components, weights folded in) against the test
// functions and adds each lane into `out`.
template <class Basis, int NC, class Nodes, class T>
KOKKOS_INLINE_FUNCTION void integrate_and_scatter_batch(const Nodes& nodes, int b,
                                                        T (*f0)[Basis::n_qp],
                                                        T (*f1)[Basis::n_qp][3], const Vector& out,
                                                        bool atomic) {
  constexpr int W = Nodes::rank == 3 ? static_cast<int>(Nodes::static_extent(2)) : 1;
  for (int c = 0; c < NC; ++c) {
    T re[Basis::n_nodes];
    integrate_value_and_gradient<Basis>(f0[c], f1[c], re);
    for (int a = 0; a < Basis::n_nodes; ++a)
      for (int l = 0; l < W; ++l) {
        const int n = nodes(b, a, l);
        if (n >= 0) accumulate(atomic, &out(n * NC + c), lane(re[a], l));
      }
  }
}

// The local map of point q of one batch applied to x: y = M x (entries in storage order, the
// transposed half of a symmetric pattern from the same entries).
template <class Pattern, class T, class Load>
KOKKOS_INLINE_FUNCTION void apply_local(const Load& load, int base, const T* x, T* y) {
  constexpr int NM = Pattern::n_local;
  for (int k = 0; k < NM; ++k) y[k] = 0;
  int e = base;
  BIOFSI_UNROLL
  for (int k = 0; k < NM; ++k) {
    BIOFSI_UNROLL
    for (int m = 0; m < NM; ++m) {
      if (!Pattern::stored(k, m)) continue;
      const T v = load(e++);
      y[k] += v * x[m];
      if (Pattern::symmetric && k != m) y[m] += v * x[k];
    }
  }
}

template <class Pattern, class Basis, int W>
struct StoredApplyLoop {
  using Store = StoredTangent<Pattern, W>;
  using T = SimdValue<W>;
  static constexpr int NC = Pattern::n_local / 4, NM = Pattern::n_local, NE = Pattern::n_entries;
  static constexpr int NN = Basis::n_nodes, NQ = Basis::n_qp;

  decltype(Store::nodes) nodes;
  decltype(Store::matrix) matrix;
  ConstVector du;
  Vector out;
  int batch_offset;
  bool atomic;

  KOKKOS_INLINE_FUNCTION void operator()(int i) const {
    const int b = batch_offset + i;
    T de[NC][NN];
    gather_batch<NC>(nodes, b, du, de);
    T x[NQ][NM];
    for (int c = 0; c < NC; ++c) {
      T val[NQ], grad[NQ][3];
      interpolate_with_gradient<Basis>(de[c], val, grad);
      for (int q = 0; q < NQ; ++q) {
        x[q][4 * c] = val[q];
        for (int d = 0; d < 3; ++d) x[q][4 * c + 1 + d] = grad[q][d];
      }
    }
    const auto load = [&](int e) {
      T v;
      for (int l = 0; l < W; ++l) lane(v, l) = matrix(b, e, l);
      return v;
    };
    T f0[NC][NQ], f1[NC][NQ][3];
    for (int q = 0; q < NQ; ++q) {
      T y[NM];
      apply_local<Pattern>(load, q * NE, x[q], y);
      for (int c = 0; c < NC; ++c) {
        f0[c][q] = y[4 * c];
        for (int d = 0; d < 3; ++d) f1[c][q][d] = y[4 * c + 1 + d];
      }
    }
    integrate_and_scatter_batch<Basis, NC>(nodes, b, f0, f1, out, atomic);
  }
};

// The element matrix of one lane from the store, K_(a c),(b cb) = sum_q phi_a^T M_q phi_b with
// phi = (N, reference grad N): its diagonal or all of it scattered.
template <class Pattern, class Basis, int W>
struct StoredMatrixLoop {
  using Store = StoredTangent<Pattern, W>;
  static constexpr int NC = Pattern::n_local / 4, NM = Pattern::n_local, NE = Pattern::n_entries;
  static constexpr int NN = Basis::n_nodes, NQ = Basis::n_qp;

  decltype(Store::nodes) nodes;
  decltype(Store::matrix) matrix;
  Vector diagonal;      // when non-empty: accumulate the diagonal
  CsrMatrix assembled;  // otherwise: accumulate the element matrix
  int batch_offset;
  bool atomic;

  // The full local map of point q.
  KOKKOS_INLINE_FUNCTION void expand(int b, int l, int q, Real (*m)[NM]) const {
    int e = q * NE;
    for (int k = 0; k < NM; ++k)
      for (int j = 0; j < NM; ++j) {
        if (!Pattern::stored(k, j)) {
          const bool mirrored = Pattern::symmetric && k > j && Pattern::stored(j, k);
          if (!mirrored) m[k][j] = 0;
          continue;
        }
        m[k][j] = matrix(b, e++, l);
        if (Pattern::symmetric) m[j][k] = m[k][j];
      }
  }

  KOKKOS_INLINE_FUNCTION void operator()(int i) const {
    const int b = batch_offset + i / W, l = i % W;
    if (nodes(b, 0, l) < 0) return;
    const bool diagonal_only = diagonal.extent(0) > 0;
    Real ke[NN * NC][NN * NC];
    for (int r = 0; r < NN * NC; ++r)
      for (int c = 0; c < NN * NC; ++c) ke[r][c] = 0;
    for (int q = 0; q < NQ; ++q) {
      Real m[NM][NM], phi[NN][4];
      expand(b, l, q, m);
      for (int a = 0; a < NN; ++a) basis_at_point<Basis>(a, q, phi[a][0], phi[a] + 1);
      for (int a = 0; a < NN; ++a)
        for (int c = 0; c < NC; ++c)
          for (int bb = 0; bb < NN; ++bb)
            for (int cb = 0; cb < NC; ++cb) {
              if (diagonal_only && (a != bb || c != cb)) continue;
              Real s = 0;
              for (int x = 0; x < 4; ++x)
                for (int y = 0; y < 4; ++y) s += phi[a][x] * m[4 * c + x][4 * cb + y] * phi[bb][y];
              ke[a * NC + c][bb * NC + cb] += s;
            }
    }
    if (diagonal_only) {
      for (int a = 0; a < NN; ++a)
        for (int c = 0; c < NC; ++c)
          accumulate(atomic, &diagonal(nodes(b, a, l) * NC + c), ke[a * NC + c][a * NC + c]);
      return;
    }
    const int* rp = assembled.row_ptr.data();
    const int* cols = assembled.col.data();
    for (int a = 0; a < NN; ++a)
      for (int c = 0; c < NC; ++c)
        for (int bb = 0; bb < NN; ++bb)
          for (int cb = 0; cb < NC; ++cb) {
            const int k = csr_find(rp, cols, nodes(b, a, l) * NC + c, nodes(b, bb, l) * NC + cb);
            accumulate(atomic, &assembled.val(k), ke[a * NC + c][bb * NC + cb]);
          }
  }
};

}  // namespace detail

namespace detail {

// Entry e of batch b of a [batch][entry][lane] view as a pack of its lanes.
template <class T, class Data>
KOKKOS_INLINE_FUNCTION T load_lanes(const Data& data, int b, int e) {
  constexpr int W = static_cast<int>(Data::static_extent(2));
  T v;
  for (int l = 0; l < W; ++l) lane(v, l) = data(b, e, l);
  return v;
}

// Point q of batch b of a point-state store holding NS state entries and NE in all: the state,
// the inverse Jacobian and w det J.
template <int NS, int NE, class State, class T, class Data>
KOKKOS_INLINE_FUNCTION void load_point(const Data& data, int b, int q, State& state, T (&inv)[3][3],
                                       T& wdet) {
  static_assert(sizeof(State) == NS * sizeof(T), "a state must hold T members only");
  T* v = reinterpret_cast<T*>(&state);
  const int base = q * NE;
  for (int e = 0; e < NS; ++e) v[e] = load_lanes<T>(data, b, base + e);
  for (int d = 0; d < 3; ++d)
    for (int c = 0; c < 3; ++c) inv[d][c] = load_lanes<T>(data, b, base + NS + 3 * d + c);
  wdet = load_lanes<T>(data, b, base + NS + 9);
}

// Point states of one lane (element) at the linearisation point (or the step's states), with the
// geometry.
template <class Physics, class Basis, int W, class Kind = TangentStates>
struct PointStateLoop {
  using Store = StoredPointStates<Physics, W, Kind>;
  static constexpr int NC = Physics::n_components, NS = Store::n_state, NE = Store::n_entries;
  static constexpr int NN = Basis::n_nodes, NQ = Basis::n_qp;

  ElementLoop<Physics, Basis> element;
  ConstIndexView group;
  int batch_offset;
  decltype(Store::nodes) nodes;
  decltype(Store::data) data;

  KOKKOS_INLINE_FUNCTION void operator()(int i) const {
    const int b = batch_offset + i / W, l = i % W;
    if (i >= static_cast<int>(group.extent(0))) {
      for (int a = 0; a < NN; ++a) nodes(b, a, l) = -1;
      for (int k = 0; k < NQ * NE; ++k) data(b, k, l) = 0;
      return;
    }
    typename ElementLoop<Physics, Basis>::Gathered g;
    element.gather(group(i), g);
    for (int a = 0; a < NN; ++a) nodes(b, a, l) = g.node[a];
    for (int q = 0; q < NQ; ++q) {
      Real uq[NC], gu[NC][3];
      for (int c = 0; c < NC; ++c) {
        uq[c] = g.uq[c][q];
        for (int d = 0; d < 3; ++d) gu[c][d] = g.gu[c][q][d];
      }
      const typename Store::State state = Kind::evaluate(element.physics, g.qp[q], uq, gu);
      const Real* v = reinterpret_cast<const Real*>(&state);
      const int base = q * NE;
      for (int e = 0; e < NS; ++e) data(b, base + e, l) = v[e];
      for (int d = 0; d < 3; ++d)
        for (int c = 0; c < 3; ++c) data(b, base + NS + 3 * d + c, l) = g.geo.inv[q][d][c];
      data(b, base + NS + 9, l) = g.geo.wdet[q];
    }
  }
};

template <class Physics, class Basis, int W, class Kind = TangentStates>
struct PointStateApplyLoop {
  using Store = StoredPointStates<Physics, W, Kind>;
  using T = SimdValue<W>;
  using State = typename Kind::template State<Physics, T>;
  static constexpr int NC = Physics::n_components, NS = Store::n_state, NE = Store::n_entries;
  static constexpr int NN = Basis::n_nodes, NQ = Basis::n_qp;
  static_assert(sizeof(State) == NS * sizeof(T), "a state must hold T members only");

  decltype(Store::nodes) nodes;
  decltype(Store::data) data;
  Physics physics;
  ConstVector du;
  Vector out;
  int batch_offset;
  bool atomic;

  KOKKOS_INLINE_FUNCTION void operator()(int i) const {
    const int b = batch_offset + i;
    T de[NC][NN];
    gather_batch<NC>(nodes, b, du, de);
    T val[NC][NQ], ref[NC][NQ][3];
    for (int c = 0; c < NC; ++c) interpolate_with_gradient<Basis>(de[c], val[c], ref[c]);
    T f0[NC][NQ], f1[NC][NQ][3];
    for (int q = 0; q < NQ; ++q) {
      State state;
      T inv[3][3], wdet;
      load_point<NS, NE>(data, b, q, state, inv, wdet);
      T duq[NC], gdu[NC][3], df0[NC], df1[NC][3];
      for (int c = 0; c < NC; ++c) {
        duq[c] = val[c][q];
        for (int k = 0; k < 3; ++k)
          gdu[c][k] =
              ref[c][q][0] * inv[0][k] + ref[c][q][1] * inv[1][k] + ref[c][q][2] * inv[2][k];
      }
      Kind::template apply<Physics, T>(physics, state, duq, gdu, df0, df1);
      for (int c = 0; c < NC; ++c) {
        f0[c][q] = wdet * df0[c];
        for (int d = 0; d < 3; ++d)
          f1[c][q][d] =
              wdet * (inv[d][0] * df1[c][0] + inv[d][1] * df1[c][1] + inv[d][2] * df1[c][2]);
      }
    }
    integrate_and_scatter_batch<Basis, NC>(nodes, b, f0, f1, out, atomic);
  }
};

// The tangent's point states at u of one batch from its step states, the geometry copied over.
template <class Physics, class Basis, int W>
struct StepToPointStateLoop {
  using Steps = StoredPointStates<Physics, W, StepStates>;
  using Points = StoredPointStates<Physics, W, TangentStates>;
  using T = SimdValue<W>;
  using StepState = typename Physics::template StepState<T>;
  using PointState = typename Physics::template PointState<T>;
  static constexpr int NC = Physics::n_components, NN = Basis::n_nodes, NQ = Basis::n_qp;
  static constexpr int NSS = Steps::n_state, NES = Steps::n_entries;
  static constexpr int NSP = Points::n_state, NEP = Points::n_entries;
  static_assert(sizeof(StepState) == NSS * sizeof(T), "StepState must hold T members only");

  decltype(Steps::nodes) nodes;
  decltype(Steps::data) steps;
  decltype(Points::data) points;
  Physics physics;
  ConstVector u;
  int batch_offset;

  KOKKOS_INLINE_FUNCTION void store(int b, int e, const T& v) const {
    for (int l = 0; l < W; ++l) points(b, e, l) = lane(v, l);
  }

  KOKKOS_INLINE_FUNCTION void operator()(int i) const {
    const int b = batch_offset + i;
    T ue[NC][NN];
    gather_batch<NC>(nodes, b, u, ue);
    T val[NC][NQ], ref[NC][NQ][3];
    for (int c = 0; c < NC; ++c) interpolate_with_gradient<Basis>(ue[c], val[c], ref[c]);
    for (int q = 0; q < NQ; ++q) {
      StepState state;
      T inv[3][3], wdet;
      load_point<NSS, NES>(steps, b, q, state, inv, wdet);
      T uq[NC], gu[NC][3];
      for (int c = 0; c < NC; ++c) {
        uq[c] = val[c][q];
        for (int k = 0; k < 3; ++k)
          gu[c][k] = ref[c][q][0] * inv[0][k] + ref[c][q][1] * inv[1][k] + ref[c][q][2] * inv[2][k];
      }
      const PointState p = physics.point_state_at(state, uq, gu);
      const T* pv = reinterpret_cast<const T*>(&p);
      for (int e = 0; e < NSP; ++e) store(b, q * NEP + e, pv[e]);
      for (int d = 0; d < 3; ++d)
        for (int c = 0; c < 3; ++c) store(b, q * NEP + NSP + 3 * d + c, inv[d][c]);
      store(b, q * NEP + NSP + 9, wdet);
    }
  }
};

// Batches of `set`'s groups into `store` (its nodes and offsets), re-allocating `values` to
// n_batches x entries when the size changed; calls fill(group, batch_offset, lanes) per group.
template <int W, class Values, class Fill>
void prepare_batches(const ElementGroups& set, int n_nodes, int entries, ElementBatches<W>& store,
                     Values& values, const Fill& fill) {
  std::vector<int> offset{0};
  for (const auto& g : set.groups)
    offset.push_back(offset.back() + (static_cast<int>(g.extent(0)) + W - 1) / W);
  const int n = offset.back();
  if (static_cast<int>(values.extent(0)) != n || static_cast<int>(values.extent(1)) != entries) {
    store.nodes = decltype(store.nodes)("biofsi::stored_tangent::nodes", n, n_nodes);
    values = Values(Kokkos::view_alloc(Kokkos::WithoutInitializing, "biofsi::stored_tangent"), n,
                    entries);
  }
  store.group_offset = offset;
  store.scatter = set.scatter;
  for (size_t g = 0; g < set.groups.size(); ++g)
    fill(set.groups[g], offset[g], (offset[g + 1] - offset[g]) * W);
}

}  // namespace detail

// Linearises `op` at u over the element groups `set` into `store` (re-using its memory when the
// sizes match): once per Newton iteration, before the Krylov solve.
template <class Physics, class Basis, int W>
void linearise(const ElementOperator<Physics, Basis>& op, const ElementGroups& set, ConstVector u,
               StoredTangent<PatternOf<Physics>, W>& store) {
  detail::LineariseLoop<Physics, Basis, W> loop{
      op.element_loop(u, u, Vector{}), ConstIndexView{}, 0, {}, {}};
  detail::prepare_batches(set, Basis::n_nodes, Basis::n_qp * store.n_entries, store, store.matrix,
                          [&](ConstIndexView group, int offset, int lanes) {
                            loop.group = group;
                            loop.batch_offset = offset;
                            loop.nodes = store.nodes;
                            loop.matrix = store.matrix;
                            Kokkos::parallel_for("biofsi::linearise",
                                                 Kokkos::RangePolicy<ExecSpace>(0, lanes), loop);
                          });
}

template <class Physics, class Basis, int W, class Kind>
void linearise(const ElementOperator<Physics, Basis>& op, const ElementGroups& set, ConstVector u,
               StoredPointStates<Physics, W, Kind>& store) {
  store.physics = op.physics();
  detail::PointStateLoop<Physics, Basis, W, Kind> loop{
      op.element_loop(u, u, Vector{}), ConstIndexView{}, 0, {}, {}};
  detail::prepare_batches(set, Basis::n_nodes, Basis::n_qp * store.n_entries, store, store.data,
                          [&](ConstIndexView group, int offset, int lanes) {
                            loop.group = group;
                            loop.batch_offset = offset;
                            loop.nodes = store.nodes;
                            loop.data = store.data;
                            Kokkos::parallel_for("biofsi::linearise",
                                                 Kokkos::RangePolicy<ExecSpace>(0, lanes), loop);
                          });
}

namespace detail {
template <class Loop, int W>
void run_batches(const char* label, const ElementBatches<W>& store, Loop& loop) {
  for (size_t g = 0; g + 1 < store.group_offset.size(); ++g) {
    loop.batch_offset = store.group_offset[g];
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(0, store.group_offset[g + 1] - store.group_offset[g]),
        loop);
  }
}
}  // namespace detail

// y += J du with the stored tangent.
template <class Basis = Hex8, class Pattern, int W>
void apply_stored(const StoredTangent<Pattern, W>& store, ConstVector du, Vector y) {
  detail::StoredApplyLoop<Pattern, Basis, W> loop{
      store.nodes, store.matrix, du, y, 0, store.scatter == Scatter::Atomic};
  detail::run_batches("biofsi::apply_stored", store, loop);
}

template <class Basis = Hex8, class Physics, int W>
void apply_stored(const StoredPointStates<Physics, W>& store, ConstVector du, Vector y) {
  detail::PointStateApplyLoop<Physics, Basis, W> loop{
      store.nodes, store.data, store.physics, du, y, 0, store.scatter == Scatter::Atomic};
  detail::run_batches("biofsi::apply_point_states", store, loop);
}

// The step's states of `op` over `set` (what its Physics' residual needs of the step's data;
// `any` is only gathered, the states do not depend on it).
template <class Physics, class Basis, int W>
void store_step_states(const ElementOperator<Physics, Basis>& op, const ElementGroups& set,
                       ConstVector any, StoredPointStates<Physics, W, StepStates>& store) {
  linearise(op, set, any, store);
}

// r += the residual at u, from the step's states.
template <class Basis = Hex8, class Physics, int W>
void residual_stored(const StoredPointStates<Physics, W, StepStates>& store, ConstVector u,
                     Vector r) {
  detail::PointStateApplyLoop<Physics, Basis, W, StepStates> loop{
      store.nodes, store.data, store.physics, u, r, 0, store.scatter == Scatter::Atomic};
  detail::run_batches("biofsi::residual_stored", store, loop);
}

// The tangent's point states at u, from the step's states (the same batches; `points` re-uses its
// memory when the sizes match).
template <class Basis = Hex8, class Physics, int W>
void linearise_from_step_states(const StoredPointStates<Physics, W, StepStates>& steps,
                                ConstVector u, StoredPointStates<Physics, W>& points) {
  using Points = StoredPointStates<Physics, W>;
  points.physics = steps.physics;
  points.nodes = steps.nodes;
  points.group_offset = steps.group_offset;
  points.scatter = steps.scatter;
  const int n = static_cast<int>(steps.data.extent(0));
  const int entries = Basis::n_qp * Points::n_entries;
  if (static_cast<int>(points.data.extent(0)) != n ||
      static_cast<int>(points.data.extent(1)) != entries)
    points.data = decltype(points.data)(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "biofsi::stored_tangent"), n, entries);
  detail::StepToPointStateLoop<Physics, Basis, W> loop{steps.nodes,   steps.data, points.data,
                                                       steps.physics, u,          0};
  detail::run_batches("biofsi::linearise_from_step_states", steps, loop);
}

namespace detail {
template <class Basis, class Pattern, int W>
void run_stored_matrix(const StoredTangent<Pattern, W>& store, Vector d, const CsrMatrix& a) {
  StoredMatrixLoop<Pattern, Basis, W> loop{
      store.nodes, store.matrix, d, a, 0, store.scatter == Scatter::Atomic};
  for (size_t g = 0; g + 1 < store.group_offset.size(); ++g) {
    loop.batch_offset = store.group_offset[g];
    const int lanes = (store.group_offset[g + 1] - store.group_offset[g]) * W;
    Kokkos::parallel_for("biofsi::stored_matrix", Kokkos::RangePolicy<ExecSpace>(0, lanes), loop);
  }
}
}  // namespace detail

// d += diag(J) from the stored tangent.
template <class Basis = Hex8, class Pattern, int W>
void diagonal_stored(const StoredTangent<Pattern, W>& store, Vector d) {
  detail::run_stored_matrix<Basis>(store, d, CsrMatrix{});
}

// A += J from the stored tangent, into A's fixed pattern.
template <class Basis = Hex8, class Pattern, int W>
void assemble_stored(const StoredTangent<Pattern, W>& store, const CsrMatrix& a) {
  detail::run_stored_matrix<Basis>(store, Vector{}, a);
}

// A stored tangent with the state it was taken at, for the terms a field still applies on the fly
// at that state (boundary faces, couplings).
// The store a field uses: point states where the Physics declares them, the map otherwise.
template <class Physics, int W = simd_width>
using FieldStoreOf = std::conditional_t<detail::HasPointState<Physics>::value,
                                        StoredPointStates<Physics, W>, StoredTangentOf<Physics, W>>;

template <class Physics, int W = simd_width>
struct Linearisation {
  FieldStoreOf<Physics, W> tangent;
  Vector point;

  template <class Basis>
  void update(const ElementOperator<Physics, Basis>& op, const ElementGroups& set, ConstVector u) {
    keep_point(u);
    linearise(op, set, u, tangent);
  }
  // The same from a store of the step's states (StepStates) taken with op's physics.
  template <class Basis = Hex8>
  void update_from(const StoredPointStates<Physics, W, StepStates>& steps, ConstVector u) {
    keep_point(u);
    linearise_from_step_states<Basis>(steps, u, tangent);
  }

 private:
  void keep_point(ConstVector u) {
    if (point.extent(0) != u.extent(0))
      point = Vector(Kokkos::view_alloc(Kokkos::WithoutInitializing, "biofsi::linearisation_point"),
                     u.extent(0));
    Kokkos::deep_copy(point, u);
  }
};

}  // namespace biofsi
