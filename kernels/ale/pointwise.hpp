// kernels/ale: pointwise physics of mesh motion — quasi-static pseudo-elasticity (paper eqs. 7,
// 12, 13) for the mesh displacement d (3 components). Used by src/ale for the fluid mesh and the
// biofilm (growth) mesh alike; depends on kernels/core only.
//
// Linear isotropic elasticity on the configuration the mesh has before the move, with the
// stiffness scaled by (1/det J)^chi at each point (Jacobian-based stiffening, Stein-Tezduyar-Benney
// 2003): small elements, which sit next to the moving interface, become stiffer and move almost
// rigidly instead of being crushed. With Dirichlet data on the whole boundary only the ratio of
// stiffnesses matters, so the mesh's motion does not depend on the reference det J_0 in
// (J_0 / det J)^chi; its magnitude does matter inside the monolithic FSI, whose first Newton step
// from rest weighs the zero-residual fields alike (src/coupling/fsi.cpp): with J_0 = 1 in SI
// units chi = 3 made the fluid mesh's rows ~1e12 times the fluid's and the Krylov solver stalled.
// src/ale sets J_0 to the smallest element's (pseudo_elastic_physics).
#pragma once

#include "kernels/core/element_loop.hpp"

namespace biofsi {

struct PseudoElasticPhysics {
  static constexpr int n_components = 3, n_aux = 0;
  static constexpr bool tangent_symmetric = true, tangent_couples_values_and_gradients = false;
  Real lambda = 0.5, mu = 1.0;  // Lame parameters (MeshMotion sets them from E = 1 and nu)
  Real stiffening = 0.0;        // chi >= 0
  Real reference_det = 1.0;     // J_0 > 0: the det J at which the stiffness is E

  KOKKOS_INLINE_FUNCTION Real scale(const QpData<0>& q) const {
    if (stiffening == 0) return 1;
    // pow through exp/log: det > 0 for any valid element (an inverted one is caught by the
    // mesh-quality check before it gets here).
    return math::exp(-stiffening * math::log(q.det / reference_det));
  }

  // sigma = s (lambda tr(eps) I + 2 mu eps), eps = sym(grad d); linear, so the tangent is the same.
  // T is Real or a SIMD pack of points.
  template <class T>
  KOKKOS_INLINE_FUNCTION void stress(const T& s, const T g[3][3], T sigma[3][3]) const {
    const T s_mu = s * mu, s_lambda_tr = s * lambda * (g[0][0] + g[1][1] + g[2][2]);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) sigma[i][j] = s_mu * (g[i][j] + g[j][i]);
    for (int i = 0; i < 3; ++i) sigma[i][i] += s_lambda_tr;
  }

  KOKKOS_INLINE_FUNCTION void residual(const QpData<0>& q, const Real[3], const Real gu[3][3],
                                       Real f0[3], Real f1[3][3]) const {
    stress(scale(q), gu, f1);
    f0[0] = f0[1] = f0[2] = 0;
  }

  // The tangent differs between points only by the stiffness scale, so a stored tangent needs
  // that one number per point with the geometry (11 doubles instead of the map's 45): the
  // StoredPointStates of kernels/core/stored_tangent.hpp.
  template <class T>
  struct PointState {
    T scale;
  };
  KOKKOS_INLINE_FUNCTION PointState<Real> point_state(const QpData<0>& q, const Real[3],
                                                      const Real[3][3]) const {
    return {scale(q)};
  }
  template <class T>
  KOKKOS_INLINE_FUNCTION void tangent_at(const PointState<T>& s, const T[3], const T gdu[3][3],
                                         T df0[3], T df1[3][3]) const {
    stress(s.scale, gdu, df1);
    df0[0] = df0[1] = df0[2] = T(0);
  }
  KOKKOS_INLINE_FUNCTION void tangent(const QpData<0>& q, const Real u[3], const Real gu[3][3],
                                      const Real du[3], const Real gdu[3][3], Real df0[3],
                                      Real df1[3][3]) const {
    tangent_at(point_state(q, u, gu), du, gdu, df0, df1);
  }
};

}  // namespace biofsi
