// Hex8 (trilinear) basis on [-1,1]^3 with tensor Gauss quadrature, sum-factorised.
//
// Local node numbering inside kernels is lexicographic, l = i + P*(j + P*k); meshes store VTK/XDMF
// order, and `vtk_of_lex` maps between them. Sizes are template parameters (P nodes and Q points
// per direction) so loops unroll; hex8 with 2x2x2 Gauss is P = Q = 2, and the same code serves Q2.
#pragma once

#include "types.hpp"

namespace biofsi {

template <int P, int Q>
struct TensorBasis;

// Q1 on [-1,1] with Q-point Gauss-Legendre: Q = 2 is exact for the trilinear mass matrix; Q = 1
// (the centre) is the reduced rule of selective reduced integration.
template <int NQ>
struct TensorBasis<2, NQ> {
  static_assert(NQ == 1 || NQ == 2, "Q1 is paired with the 1- or 2-point Gauss rule");
  static constexpr int P = 2, Q = NQ, n_nodes = 8, n_qp = NQ * NQ * NQ;
  KOKKOS_INLINE_FUNCTION static Real point(int q) {
    if (NQ == 1) return 0.0;
    return q == 0 ? -0.57735026918962576451 : 0.57735026918962576451;
  }
  KOKKOS_INLINE_FUNCTION static Real weight(int) { return NQ == 1 ? 2.0 : 1.0; }
  KOKKOS_INLINE_FUNCTION static Real value(int i, Real xi) {
    return i == 0 ? 0.5 * (1.0 - xi) : 0.5 * (1.0 + xi);
  }
  KOKKOS_INLINE_FUNCTION static Real derivative(int i, Real) { return i == 0 ? -0.5 : 0.5; }
  KOKKOS_INLINE_FUNCTION static Real B(int q, int i) { return value(i, point(q)); }
  KOKKOS_INLINE_FUNCTION static Real D(int q, int i) { return derivative(i, point(q)); }
};

using Hex8 = TensorBasis<2, 2>;
using Hex8Centre = TensorBasis<2, 1>;

// VTK hexahedron order of the lexicographic node l = i + 2j + 4k.
KOKKOS_INLINE_FUNCTION int vtk_of_lex(int l) {
  constexpr int map[8] = {0, 1, 3, 2, 4, 5, 7, 6};
  return map[l];
}

// 1-D matrices seen by a contraction: forward (points x nodes) or transposed (nodes x points).
template <class Basis, bool Derivative, bool Transpose>
struct BasisMatrix {
  KOKKOS_INLINE_FUNCTION Real operator()(int out, int in) const {
    const int q = Transpose ? in : out, i = Transpose ? out : in;
    return Derivative ? Basis::D(q, i) : Basis::B(q, i);
  }
};

// out = M contracted along dimension Dir of a tensor stored as in[i0 + N0*(i1 + N1*i2)];
// dimension Dir becomes NO long.
template <int Dir, int N0, int N1, int N2, int NO, class Matrix, class T>
KOKKOS_INLINE_FUNCTION void contract(const Matrix& m, const T* in, T* out) {
  constexpr int O0 = Dir == 0 ? NO : N0, O1 = Dir == 1 ? NO : N1, O2 = Dir == 2 ? NO : N2;
  constexpr int NI = Dir == 0 ? N0 : (Dir == 1 ? N1 : N2);
  for (int o2 = 0; o2 < O2; ++o2)
    for (int o1 = 0; o1 < O1; ++o1)
      for (int o0 = 0; o0 < O0; ++o0) {
        const int o = Dir == 0 ? o0 : (Dir == 1 ? o1 : o2);
        T s = 0;
        for (int i = 0; i < NI; ++i) {
          const int i0 = Dir == 0 ? i : o0, i1 = Dir == 1 ? i : o1, i2 = Dir == 2 ? i : o2;
          s += m(o, i) * in[i0 + N0 * (i1 + N1 * i2)];
        }
        out[o0 + O0 * (o1 + O1 * o2)] = s;
      }
}

// Values and reference gradients at the Q^3 points of nodal values u[P^3] (three 1-D passes).
// T is Real, or a SIMD pack holding one element per lane.
template <class Basis, class T>
KOKKOS_INLINE_FUNCTION void interpolate_with_gradient(const T* u, T* val, T (*grad)[3]) {
  constexpr int P = Basis::P, Q = Basis::Q;
  const BasisMatrix<Basis, false, false> b;
  const BasisMatrix<Basis, true, false> d;
  T uB[Q * P * P], uD[Q * P * P];
  contract<0, P, P, P, Q>(b, u, uB);
  contract<0, P, P, P, Q>(d, u, uD);
  T uBB[Q * Q * P], uDB[Q * Q * P], uBD[Q * Q * P];
  contract<1, Q, P, P, Q>(b, uB, uBB);
  contract<1, Q, P, P, Q>(b, uD, uDB);
  contract<1, Q, P, P, Q>(d, uB, uBD);
  T gx[Q * Q * Q], gy[Q * Q * Q], gz[Q * Q * Q];
  contract<2, Q, Q, P, Q>(b, uBB, val);
  contract<2, Q, Q, P, Q>(b, uDB, gx);
  contract<2, Q, Q, P, Q>(b, uBD, gy);
  contract<2, Q, Q, P, Q>(d, uBB, gz);
  for (int q = 0; q < Q * Q * Q; ++q) {
    grad[q][0] = gx[q];
    grad[q][1] = gy[q];
    grad[q][2] = gz[q];
  }
}

// Values only at the Q^3 points (three 1-D passes), for data whose gradient nobody reads.
template <class Basis, class T>
KOKKOS_INLINE_FUNCTION void interpolate_values(const T* u, T* val) {
  constexpr int P = Basis::P, Q = Basis::Q;
  const BasisMatrix<Basis, false, false> b;
  T uB[Q * P * P], uBB[Q * Q * P];
  contract<0, P, P, P, Q>(b, u, uB);
  contract<1, Q, P, P, Q>(b, uB, uBB);
  contract<2, Q, Q, P, Q>(b, uBB, val);
}

// Transpose of interpolate_with_gradient: out[P^3] = sum_q B^T f0[q] + D^T . f1[q] (reference
// components), i.e. the test-function integration without weights (the caller folds them in).
template <class Basis, class T>
KOKKOS_INLINE_FUNCTION void integrate_value_and_gradient(const T* f0, const T (*f1)[3], T* out) {
  constexpr int P = Basis::P, Q = Basis::Q;
  const BasisMatrix<Basis, false, true> bt;
  const BasisMatrix<Basis, true, true> dt;
  T fx[Q * Q * Q], fy[Q * Q * Q], fz[Q * Q * Q];
  for (int q = 0; q < Q * Q * Q; ++q) {
    fx[q] = f1[q][0];
    fy[q] = f1[q][1];
    fz[q] = f1[q][2];
  }
  // z pass: value and x,y-gradients go through B^T, the z-gradient through D^T.
  T aBB[Q * Q * P], aDB[Q * Q * P], aBD[Q * Q * P], tmp[Q * Q * P];
  contract<2, Q, Q, Q, P>(bt, f0, aBB);
  contract<2, Q, Q, Q, P>(dt, fz, tmp);
  for (int i = 0; i < Q * Q * P; ++i) aBB[i] += tmp[i];
  contract<2, Q, Q, Q, P>(bt, fx, aDB);
  contract<2, Q, Q, Q, P>(bt, fy, aBD);
  // y pass
  T aB[Q * P * P], aD[Q * P * P], tmp2[Q * P * P];
  contract<1, Q, Q, P, P>(bt, aBB, aB);
  contract<1, Q, Q, P, P>(dt, aBD, tmp2);
  for (int i = 0; i < Q * P * P; ++i) aB[i] += tmp2[i];
  contract<1, Q, Q, P, P>(bt, aDB, aD);
  // x pass
  T tmp3[P * P * P];
  contract<0, Q, P, P, P>(bt, aB, out);
  contract<0, Q, P, P, P>(dt, aD, tmp3);
  for (int i = 0; i < P * P * P; ++i) out[i] += tmp3[i];
}

// Basis function a (lexicographic) and its reference gradient at quadrature point q, evaluated
// directly; used where one column of the element matrix is needed (diagonal, assembly).
template <class Basis>
KOKKOS_INLINE_FUNCTION void basis_at_point(int a, int q, Real& value, Real grad[3]) {
  constexpr int P = Basis::P, Q = Basis::Q;
  const int i = a % P, j = (a / P) % P, k = a / (P * P);
  const int q0 = q % Q, q1 = (q / Q) % Q, q2 = q / (Q * Q);
  const Real bx = Basis::B(q0, i), by = Basis::B(q1, j), bz = Basis::B(q2, k);
  value = bx * by * bz;
  grad[0] = Basis::D(q0, i) * by * bz;
  grad[1] = bx * Basis::D(q1, j) * bz;
  grad[2] = bx * by * Basis::D(q2, k);
}

template <class Basis>
KOKKOS_INLINE_FUNCTION Real quadrature_weight(int q) {
  constexpr int Q = Basis::Q;
  return Basis::weight(q % Q) * Basis::weight((q / Q) % Q) * Basis::weight(q / (Q * Q));
}

// Geometry at one point from the reference gradients of the three coordinates:
// jac[c][d] = dx_c/dxi_d; inv[d][c] = dxi_d/dx_c. Returns det J.
KOKKOS_INLINE_FUNCTION Real invert_jacobian(const Real jac[3][3], Real inv[3][3]) {
  const Real c00 = jac[1][1] * jac[2][2] - jac[1][2] * jac[2][1];
  const Real c01 = jac[1][2] * jac[2][0] - jac[1][0] * jac[2][2];
  const Real c02 = jac[1][0] * jac[2][1] - jac[1][1] * jac[2][0];
  const Real det = jac[0][0] * c00 + jac[0][1] * c01 + jac[0][2] * c02;
  const Real s = 1.0 / det;
  inv[0][0] = c00 * s;
  inv[1][0] = c01 * s;
  inv[2][0] = c02 * s;
  inv[0][1] = (jac[0][2] * jac[2][1] - jac[0][1] * jac[2][2]) * s;
  inv[1][1] = (jac[0][0] * jac[2][2] - jac[0][2] * jac[2][0]) * s;
  inv[2][1] = (jac[0][1] * jac[2][0] - jac[0][0] * jac[2][1]) * s;
  inv[0][2] = (jac[0][1] * jac[1][2] - jac[0][2] * jac[1][1]) * s;
  inv[1][2] = (jac[0][2] * jac[1][0] - jac[0][0] * jac[1][2]) * s;
  inv[2][2] = (jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0]) * s;
  return det;
}

// Physical gradient from a reference gradient: g[c] = sum_d ref[d] * inv[d][c].
KOKKOS_INLINE_FUNCTION void physical_gradient(const Real inv[3][3], const Real ref[3], Real g[3]) {
  for (int c = 0; c < 3; ++c) g[c] = ref[0] * inv[0][c] + ref[1] * inv[1][c] + ref[2] * inv[2][c];
}

// Pull a physical flux back to reference components: ref[d] = sum_c inv[d][c] * f[c].
KOKKOS_INLINE_FUNCTION void reference_flux(const Real inv[3][3], const Real f[3], Real ref[3]) {
  for (int d = 0; d < 3; ++d) ref[d] = inv[d][0] * f[0] + inv[d][1] * f[1] + inv[d][2] * f[2];
}

// Geometry of one element at all quadrature points, computed on the fly from its vertices.
template <class Basis>
struct ElementGeometry {
  static constexpr int NQ = Basis::n_qp;
  Real x[NQ][3];       // physical coordinates of the points
  Real inv[NQ][3][3];  // dxi/dx
  Real det[NQ];        // det J (reference cell [-1,1]^3)
  Real wdet[NQ];       // quadrature weight * det J
  Real min_det;

  KOKKOS_INLINE_FUNCTION void compute(const Real (*xe)[3]) {
    constexpr int NN = Basis::n_nodes;
    Real grad[3][NQ][3];
    for (int c = 0; c < 3; ++c) {
      Real u[NN];
      for (int a = 0; a < NN; ++a) u[a] = xe[a][c];
      Real val[NQ];
      interpolate_with_gradient<Basis>(u, val, grad[c]);
      for (int q = 0; q < NQ; ++q) x[q][c] = val[q];
    }
    min_det = 1e300;
    for (int q = 0; q < NQ; ++q) {
      Real jac[3][3];
      for (int c = 0; c < 3; ++c)
        for (int d = 0; d < 3; ++d) jac[c][d] = grad[c][q][d];
      det[q] = invert_jacobian(jac, inv[q]);
      min_det = det[q] < min_det ? det[q] : min_det;
      wdet[q] = quadrature_weight<Basis>(q) * det[q];
    }
  }
};

}  // namespace biofsi
