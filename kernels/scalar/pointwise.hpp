// kernels/scalar: pointwise physics of substrate transport (paper eqs. 8-10) on one continuous
// field over all blocks: ALE convection-diffusion in the fluid, diffusion with Monod consumption in
// the biofilm, with per-block coefficients. Used by src/scalar; depends on kernels/core only.
//
// Weak form at one point, one-step-theta in time (theta = 1, inv_dt = 0 gives the steady problem):
//   f0 = (phi - phi_n)/dt + theta (c.grad phi + R(phi)) + (1 - theta)(c.grad phi_n + R(phi_n)) - s
//        + m (theta phi + (1 - theta) phi_n) div w                       (eq. 9, deforming solid)
//   f1 = D (theta grad phi + (1 - theta) grad phi_n) + tau c f0          (SUPG)
// In a block whose mesh moves with a deforming material (the biofilm under FSI), w is that
// material's velocity and m = 1: the conservative term Phi div u_S of the paper's eq. (9), a
// source where the solid is compressed and a sink where it dilates (c = 0 there, the mesh being
// Lagrangian); m = 0 elsewhere.
// f0 is the strong residual as well: the diffusive second derivatives, which vanish for Q1 on
// affine elements, are neglected in the SUPG residual (standard for trilinear elements).
// c is the ALE convective velocity u - u_grid, given per node; all terms are evaluated on the
// current configuration, which makes a constant field an exact discrete solution for any mesh
// motion (geometric conservation). s is a volumetric source evaluated at t_{n+theta} (manufactured
// solutions, feeds).
#pragma once

#include "kernels/core/element_loop.hpp"
#include "kernels/core/simd.hpp"

namespace biofsi {

constexpr int max_blocks = 8;

// Per-block transport coefficients: diffusivity D, Monod rate k and half-saturation K.
struct TransportCoefficients {
  Real diffusivity[max_blocks] = {};
  Real monod_rate[max_blocks] = {};
  Real monod_half_saturation[max_blocks] = {};
  Real material_motion[max_blocks] = {};  // 1: the Phi div w term of a deforming solid block
};

// Monod consumption R = k phi / (K + |phi|): for phi >= 0 the paper's kinetics; for phi < 0 the odd
// extension, which is smooth at 0 (slope k/K from both sides), never divides by zero (K > 0), and
// turns a numerical undershoot into production that pulls phi back to zero.
// T is Real or a SIMD pack of points.
template <class T>
KOKKOS_INLINE_FUNCTION T monod_rate(const T& k, const T& K, const T& phi) {
  return k * phi / (K + abs_value(phi));
}
template <class T>
KOKKOS_INLINE_FUNCTION T monod_rate_derivative(const T& k, const T& K, const T& phi) {
  const T s = K + abs_value(phi);
  return k * K / (s * s);
}

// SUPG parameter. Advective part: tau = h/(2|c|) (coth Pe - 1/Pe), Pe = |c| h/(2D), with the
// streamline length h = 2|c| / sqrt(c.G.c) from the element metric G (reference cell [-1,1]^3);
// nodally exact for the 1-D steady boundary layer (reference/benchmarks.md). The transient limit
// adds (2/dt)^2 under the usual root so that tau stays bounded for small time steps.
KOKKOS_INLINE_FUNCTION Real supg_tau(const Real c[3], const Real metric[3][3], Real diffusivity,
                                     Real inv_dt) {
  Real cgc = 0, c2 = 0;
  for (int i = 0; i < 3; ++i) {
    c2 += c[i] * c[i];
    for (int j = 0; j < 3; ++j) cgc += c[i] * metric[i][j] * c[j];
  }
  if (c2 <= 0 || cgc <= 0) return 0;
  const Real speed = math::sqrt(c2);
  const Real h = 2 * speed / math::sqrt(cgc);
  Real xi = 1;  // coth Pe - 1/Pe
  if (diffusivity > 0) {
    const Real pe = speed * h / (2 * diffusivity);
    if (pe < 1e-3)
      xi = pe / 3;
    else if (pe < 50)
      xi = 1 / math::tanh(pe) - 1 / pe;
    else
      xi = 1 - 1 / pe;
  }
  const Real tau_adv = h / (2 * speed) * xi;
  if (tau_adv <= 0) return 0;
  const Real inv2 = 1 / (tau_adv * tau_adv) + 4 * inv_dt * inv_dt;
  return 1 / math::sqrt(inv2);
}

// Element physics. Auxiliary nodal data: [phi_n, w_x, w_y, w_z, c_x, c_y, c_z, s]; phi_n and the
// material velocity w need gradients.
struct TransportPhysics {
  static constexpr int n_components = 1, n_aux = 8, n_aux_gradients = 4;
  // Columns of the auxiliary data (host code fills them by these names).
  static constexpr int aux_phi_old = 0, aux_material_velocity = 1, aux_convective_velocity = 4,
                       aux_source = 7;
  TransportCoefficients coef;
  Real inv_dt = 0;  // 0: steady
  Real theta = 1;
  bool supg = true;

  // What the residual needs of the step's data at a point, independent of phi: the coefficients,
  // the convective velocity, SUPG's tau, the material motion's divergence, phi_n and the terms of
  // f0 and f1 made of old values and the source. Evaluated once per time step and stored with the
  // geometry (kernels/core/stored_tangent.hpp, StepStates), it makes each Newton iteration's
  // residual and linearisation a pass over phi alone: no auxiliary fields, no geometry, no tau.
  // All members are T (a row of doubles in the store). k = 0 (no Monod) stores K = 1 so that a
  // pack of points from several blocks evaluates k phi / (K + |phi|) without 0/0.
  template <class T>
  struct StepState {
    T k, K, c[3], tau, D, div_w, phi_old, f0_old, f1_old[3];
  };

  KOKKOS_INLINE_FUNCTION StepState<Real> step_state(const QpData<n_aux>& q) const {
    StepState<Real> s;
    s.D = coef.diffusivity[q.block];
    s.k = coef.monod_rate[q.block];
    s.K = s.k > 0 ? coef.monod_half_saturation[q.block] : 1.0;
    for (int i = 0; i < 3; ++i) s.c[i] = q.aux[aux_convective_velocity + i];
    s.tau = supg ? supg_tau(s.c, q.metric, s.D, inv_dt) : 0.0;
    const auto& gw = q.grad_aux;
    constexpr int w = aux_material_velocity;
    s.div_w = coef.material_motion[q.block] * (gw[w][0] + gw[w + 1][1] + gw[w + 2][2]);
    s.phi_old = q.aux[aux_phi_old];
    const Real* g_n = q.grad_aux[aux_phi_old];
    Real conv_n = 0;
    for (int i = 0; i < 3; ++i) conv_n += s.c[i] * g_n[i];
    s.f0_old = (1 - theta) * (conv_n + monod_rate(s.k, s.K, s.phi_old) + s.phi_old * s.div_w) -
               q.aux[aux_source];
    for (int i = 0; i < 3; ++i) s.f1_old[i] = (1 - theta) * s.D * g_n[i];
    return s;
  }

  template <class T>
  KOKKOS_INLINE_FUNCTION void residual_at(const StepState<T>& s, const T u[1], const T gu[1][3],
                                          T f0[1], T f1[1][3]) const {
    T conv = 0;
    for (int i = 0; i < 3; ++i) conv += s.c[i] * gu[0][i];
    f0[0] = (u[0] - s.phi_old) * inv_dt +
            theta * (conv + monod_rate(s.k, s.K, u[0]) + u[0] * s.div_w) + s.f0_old;
    for (int i = 0; i < 3; ++i)
      f1[0][i] = theta * s.D * gu[0][i] + s.f1_old[i] + s.tau * s.c[i] * f0[0];
  }

  KOKKOS_INLINE_FUNCTION void residual(const QpData<n_aux>& q, const Real u[1], const Real gu[1][3],
                                       Real f0[1], Real f1[1][3]) const {
    residual_at(step_state(q), u, gu, f0, f1);
  }

  // What the tangent needs of the linearisation point, per point: the coefficient of du in df0
  // (storage, Monod derivative, material motion), the convective velocity, tau and theta D. All
  // members are T, so that a stored tangent can keep it as a row of doubles
  // (kernels/core/stored_tangent.hpp); evaluating it once per point also keeps SUPG's tau and
  // Monod's derivative out of the per-column work of the linearisation.
  template <class T>
  struct PointState {
    T value, c[3], tau, diffusion;
  };

  template <class T>
  KOKKOS_INLINE_FUNCTION PointState<T> point_state_at(const StepState<T>& s, const T u[1],
                                                      const T[1][3]) const {
    PointState<T> p;
    p.value = inv_dt + theta * (monod_rate_derivative(s.k, s.K, u[0]) + s.div_w);
    for (int i = 0; i < 3; ++i) p.c[i] = s.c[i];
    p.tau = s.tau;
    p.diffusion = theta * s.D;
    return p;
  }

  KOKKOS_INLINE_FUNCTION PointState<Real> point_state(const QpData<n_aux>& q, const Real u[1],
                                                      const Real gu[1][3]) const {
    return point_state_at(step_state(q), u, gu);
  }

  // The tangent at a point from its state. T is Real or a SIMD pack of points.
  template <class T>
  KOKKOS_INLINE_FUNCTION void tangent_at(const PointState<T>& s, const T du[1], const T gdu[1][3],
                                         T df0[1], T df1[1][3]) const {
    T conv = 0;
    for (int i = 0; i < 3; ++i) conv += s.c[i] * gdu[0][i];
    df0[0] = s.value * du[0] + theta * conv;
    for (int i = 0; i < 3; ++i) df1[0][i] = s.diffusion * gdu[0][i] + s.tau * s.c[i] * df0[0];
  }

  KOKKOS_INLINE_FUNCTION void tangent(const QpData<n_aux>& q, const Real u[1], const Real gu[1][3],
                                      const Real du[1], const Real gdu[1][3], Real df0[1],
                                      Real df1[1][3]) const {
    tangent_at(point_state(q, u, gu), du, gdu, df0, df1);
  }
};

// Boundary physics for Neumann and Robin conditions: the prescribed inward flux
//   q = h + alpha (phi_inf - phi_theta),  phi_theta = theta phi + (1 - theta) phi_n,
// enters the residual as -q (h and phi_inf are evaluated at t_{n+theta}).
// Auxiliary nodal data on the faces: [phi_n, h, alpha, phi_inf].
struct TransportBoundaryPhysics {
  static constexpr int n_components = 1, n_aux = 4;
  static constexpr int aux_phi_old = 0, aux_flux = 1, aux_coefficient = 2, aux_ambient = 3;
  Real theta = 1;

  KOKKOS_INLINE_FUNCTION void residual(const Real aux[4], const Real u[1], Real f0[1]) const {
    const Real phi_theta = theta * u[0] + (1 - theta) * aux[aux_phi_old];
    f0[0] = -(aux[aux_flux] + aux[aux_coefficient] * (aux[aux_ambient] - phi_theta));
  }
  KOKKOS_INLINE_FUNCTION void tangent(const Real aux[4], const Real[1], const Real du[1],
                                      Real df0[1]) const {
    df0[0] = aux[aux_coefficient] * theta * du[0];
  }
};

}  // namespace biofsi

namespace biofsi {

// f0 = R(phi): with the element driver's residual, sum_a r_a = int R(phi) dV with the same
// quadrature as the transport residual (for exact discrete mass balances).
struct MonodIntegrand {
  static constexpr int n_components = 1, n_aux = 0;
  TransportCoefficients coef;
  KOKKOS_INLINE_FUNCTION void residual(const QpData<0>& q, const Real u[1], const Real[1][3],
                                       Real f0[1], Real f1[1][3]) const {
    const Real k = coef.monod_rate[q.block];
    f0[0] = k > 0 ? monod_rate(k, coef.monod_half_saturation[q.block], u[0]) : 0.0;
    f1[0][0] = f1[0][1] = f1[0][2] = 0;
  }
  KOKKOS_INLINE_FUNCTION void tangent(const QpData<0>& q, const Real u[1], const Real[1][3],
                                      const Real du[1], const Real[1][3], Real df0[1],
                                      Real df1[1][3]) const {
    const Real k = coef.monod_rate[q.block];
    df0[0] =
        k > 0 ? monod_rate_derivative(k, coef.monod_half_saturation[q.block], u[0]) * du[0] : 0.0;
    df1[0][0] = df1[0][1] = df1[0][2] = 0;
  }
};

}  // namespace biofsi
