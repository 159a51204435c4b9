// Boundary-face loops: bilinear quadrilateral faces of hex8 elements with 2x2 Gauss points.
// A BoundaryPhysics gives, at a face point, a value term f0 (no flux term) and its derivative:
//   static constexpr int n_components, n_aux;
//   KOKKOS_INLINE_FUNCTION void residual(const Real aux[NA], const Real u[NC], Real f0[NC]) const;
//   KOKKOS_INLINE_FUNCTION void tangent(const Real aux[NA], const Real u[NC], const Real du[NC],
//                                       Real df0[NC]) const;
// contributing r_a += integral over the face of N_a f0. Faces are few, so scatter is atomic.
#pragma once

#include "csr.hpp"
#include "hex8.hpp"

namespace biofsi {

// Faces as (element, local face) with local faces 0 x-, 1 x+, 2 y-, 3 y+, 4 z-, 5 z+.
using FaceView = Kokkos::View<int* [2], MemSpace>;
using ConstFaceView = Kokkos::View<const int* [2], MemSpace>;

// VTK node of corner k (counter-clockwise in the face's own parameters) of local face f.
KOKKOS_INLINE_FUNCTION int face_node(int f, int k) {
  constexpr int nodes[6][4] = {{0, 3, 7, 4}, {1, 2, 6, 5}, {0, 1, 5, 4},
                               {3, 2, 6, 7}, {0, 1, 2, 3}, {4, 5, 6, 7}};
  return nodes[f][k];
}

namespace detail {

struct FaceResidualTag {};
struct FaceTangentTag {};
struct FaceDiagonalTag {};
struct FaceAssembleTag {};

template <class BoundaryPhysics>
struct FaceLoop {
  static constexpr int NC = BoundaryPhysics::n_components, NA = BoundaryPhysics::n_aux;
  static constexpr int NAX = NA > 0 ? NA : 1;
  ConstFaceView faces;
  ConstConnView conn;
  ConstCoordView coords;
  ConstNodalView aux;
  BoundaryPhysics physics;
  ConstVector u, du;
  Vector out;
  CsrMatrix matrix;

  // Bilinear shape values of the 4 corners at Gauss point (s, t) and the area element there.
  KOKKOS_INLINE_FUNCTION static Real shape(int k, Real s, Real t) {
    const Real ss = (k == 0 || k == 3) ? 1 - s : 1 + s, tt = (k < 2) ? 1 - t : 1 + t;
    return 0.25 * ss * tt;
  }

  KOKKOS_INLINE_FUNCTION void geometry(const int node[4], Real n[4][4], Real da[4]) const {
    for (int q = 0; q < 4; ++q) {
      const Real s = Hex8::point(q % 2), t = Hex8::point(q / 2);
      Real xs[3] = {0, 0, 0}, xt[3] = {0, 0, 0};
      const Real ds[4] = {-0.25 * (1 - t), 0.25 * (1 - t), 0.25 * (1 + t), -0.25 * (1 + t)};
      const Real dt[4] = {-0.25 * (1 - s), -0.25 * (1 + s), 0.25 * (1 + s), 0.25 * (1 - s)};
      for (int k = 0; k < 4; ++k) {
        n[q][k] = shape(k, s, t);
        for (int d = 0; d < 3; ++d) {
          xs[d] += ds[k] * coords(node[k], d);
          xt[d] += dt[k] * coords(node[k], d);
        }
      }
      const Real cx = xs[1] * xt[2] - xs[2] * xt[1], cy = xs[2] * xt[0] - xs[0] * xt[2],
                 cz = xs[0] * xt[1] - xs[1] * xt[0];
      da[q] = math::sqrt(cx * cx + cy * cy + cz * cz);  // Gauss weights are 1
    }
  }

  struct Gathered {
    int node[4];
    Real n[4][4], da[4];
    Real uq[4][NC], aq[4][NAX];
  };

  KOKKOS_INLINE_FUNCTION void gather(int i, Gathered& g) const {
    const int e = faces(i, 0), f = faces(i, 1);
    for (int k = 0; k < 4; ++k) g.node[k] = conn(e, face_node(f, k));
    geometry(g.node, g.n, g.da);
    for (int q = 0; q < 4; ++q) {
      for (int c = 0; c < NC; ++c) {
        g.uq[q][c] = 0;
        for (int k = 0; k < 4; ++k) g.uq[q][c] += g.n[q][k] * u(g.node[k] * NC + c);
      }
      for (int c = 0; c < NA; ++c) {
        g.aq[q][c] = 0;
        for (int k = 0; k < 4; ++k) g.aq[q][c] += g.n[q][k] * aux(g.node[k], c);
      }
    }
  }

  KOKKOS_INLINE_FUNCTION void operator()(FaceResidualTag, int i) const {
    Gathered g;
    gather(i, g);
    for (int q = 0; q < 4; ++q) {
      Real f0[NC];
      physics.residual(g.aq[q], g.uq[q], f0);
      for (int k = 0; k < 4; ++k)
        for (int c = 0; c < NC; ++c)
          Kokkos::atomic_add(&out(g.node[k] * NC + c), g.n[q][k] * f0[c] * g.da[q]);
    }
  }

  KOKKOS_INLINE_FUNCTION void operator()(FaceTangentTag, int i) const {
    Gathered g;
    gather(i, g);
    for (int q = 0; q < 4; ++q) {
      Real dq[NC], f0[NC];
      for (int c = 0; c < NC; ++c) {
        dq[c] = 0;
        for (int k = 0; k < 4; ++k) dq[c] += g.n[q][k] * du(g.node[k] * NC + c);
      }
      physics.tangent(g.aq[q], g.uq[q], dq, f0);
      for (int k = 0; k < 4; ++k)
        for (int c = 0; c < NC; ++c)
          Kokkos::atomic_add(&out(g.node[k] * NC + c), g.n[q][k] * f0[c] * g.da[q]);
    }
  }

  // Entry (a, ca; b, cb) of the face matrix.
  KOKKOS_INLINE_FUNCTION Real entry(const Gathered& g, int a, int ca, int b, int cb) const {
    Real s = 0;
    for (int q = 0; q < 4; ++q) {
      Real dq[NC], f0[NC];
      for (int c = 0; c < NC; ++c) dq[c] = c == cb ? g.n[q][b] : 0.0;
      physics.tangent(g.aq[q], g.uq[q], dq, f0);
      s += g.n[q][a] * f0[ca] * g.da[q];
    }
    return s;
  }

  KOKKOS_INLINE_FUNCTION void operator()(FaceDiagonalTag, int i) const {
    Gathered g;
    gather(i, g);
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < NC; ++c)
        Kokkos::atomic_add(&out(g.node[a] * NC + c), entry(g, a, c, a, c));
  }

  KOKKOS_INLINE_FUNCTION void operator()(FaceAssembleTag, int i) const {
    Gathered g;
    gather(i, g);
    for (int a = 0; a < 4; ++a)
      for (int ca = 0; ca < NC; ++ca)
        for (int b = 0; b < 4; ++b)
          for (int cb = 0; cb < NC; ++cb) {
            const int k = csr_find(matrix.row_ptr.data(), matrix.col.data(), g.node[a] * NC + ca,
                                   g.node[b] * NC + cb);
            Kokkos::atomic_add(&matrix.val(k), entry(g, a, ca, b, cb));
          }
  }
};

}  // namespace detail

// Binds a BoundaryPhysics to a set of faces; methods accumulate (+=) like ElementOperator's.
template <class BoundaryPhysics>
class FaceOperator {
 public:
  FaceOperator(ConstFaceView faces, ConstConnView conn, ConstCoordView coords, ConstNodalView aux,
               const BoundaryPhysics& physics)
      : faces_(faces), conn_(conn), coords_(coords), aux_(aux), physics_(physics) {}

  void set_physics(const BoundaryPhysics& p) { physics_ = p; }
  void set_aux(ConstNodalView aux) { aux_ = aux; }
  void set_coords(ConstCoordView coords) { coords_ = coords; }

  void residual(ConstVector u, Vector r) const {
    run<detail::FaceResidualTag>("biofsi::face_residual", u, u, r, CsrMatrix{});
  }
  void apply_tangent(ConstVector u, ConstVector du, Vector y) const {
    run<detail::FaceTangentTag>("biofsi::face_tangent", u, du, y, CsrMatrix{});
  }
  void diagonal(ConstVector u, Vector d) const {
    run<detail::FaceDiagonalTag>("biofsi::face_diagonal", u, u, d, CsrMatrix{});
  }
  void assemble(ConstVector u, const CsrMatrix& a) const {
    run<detail::FaceAssembleTag>("biofsi::face_assemble", u, u, Vector{}, a);
  }

 private:
  template <class Tag>
  void run(const char* label, ConstVector u, ConstVector du, Vector out, const CsrMatrix& a) const {
    const int n = static_cast<int>(faces_.extent(0));
    if (n == 0) return;
    detail::FaceLoop<BoundaryPhysics> loop{faces_, conn_, coords_, aux_, physics_, u, du, out, a};
    Kokkos::parallel_for(label, Kokkos::RangePolicy<ExecSpace, Tag>(0, n), loop);
  }

  ConstFaceView faces_;
  ConstConnView conn_;
  ConstCoordView coords_;
  ConstNodalView aux_;
  BoundaryPhysics physics_;
};

}  // namespace biofsi
