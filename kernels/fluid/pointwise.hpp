// kernels/fluid: pointwise physics of the incompressible fluid (paper eqs. 2-5) in ALE form on
// hex8 with equal-order Q1-Q1 velocity/pressure and residual-based stabilisation. Used by
// src/fluid (and through it by the FSI coupling); depends on kernels/core only. Nothing here
// knows of meshes, boundary conditions or solvers.
//
// Unknowns per node: (u, v, w, p), interleaved. One-step-theta in its midpoint form (theta = 1,
// inv_dt = 0 gives the steady problem): every term is evaluated at the state
// u_theta = theta u + (1 - theta) u_n with the time derivative (u - u_n)/dt, and p is the pressure
// at t_{n+theta}. With c = u_theta - u_grid the ALE convective velocity (eq. 4):
//   R_M = rho ((u - u_n)/dt + (c.grad)u_theta - b) + grad p
//         (strong momentum residual; the viscous second derivatives, which vanish for Q1 on affine
//         elements, are neglected as usual for trilinear elements)
//   momentum f0 = R_M - grad p,  f1 = mu E(u_theta) - p I
//                                     + tau_M c (x) R_M            (SUPG)
//                                     + rho tau_C (div u_theta) I  (grad-div)
//   continuity f0 = div u_theta,  f1 = tau_M R_M / rho              (PSPG)
// with E(u) = grad u + grad u^T (symmetric, paper eq. 2) or grad u (the "Laplacian" form, whose
// do-nothing outflow is the one the DFG/Turek benchmarks define). b is the body force at
// t_{n+theta}. theta = 1 is backward Euler; theta = 1/2 is the implicit midpoint rule, i.e. the
// generalized-alpha method of Jansen, Whiting & Hulbert (CMAME 190 (2000) 305) with rho_inf = 1.
// Why every term at one time level: the stabilisation terms contain the time derivative, so
// the continuity equation is a differential one; with the trapezoidal form (convection and
// viscosity averaged, continuity, SUPG, PSPG and tau at t_{n+1}) Crank-Nicolson is first order
// (tests/fluid/test_fluid_time_order.cpp). All terms live on the current configuration, so a
// constant state is an exact discrete solution under any mesh motion (GCL).
//
// Stabilisation parameters (metric form of Shakib/Tezduyar as used by Bazilevs et al., CMAME 197
// (2007) 173, with G the metric of the reference cell [-1,1]^3 carried in QpData):
//   tau_M = 1 / sqrt((2/dt)^2 + c.G.c + C_I nu^2 G:G),    C_I = 36 (trilinear elements)
//   tau_C = 1 / (tau_M,s tr G),   tau_M,s = tau_M without the (2/dt)^2 term
// In 1-D (G = 4/h^2) tau_M -> h/(2|c|) (advective) and h^2/(24 nu) (viscous), tau_C -> |c| h/2.
// tau_C uses the steady tau_M so that grad-div does not grow like 1/dt for tiny time steps.
// transient_tau = false drops the (2/dt)^2 term: the stabilised operator then does not change
// with the step (tests/fluid/test_fluid_time_order.cpp).
//
// Linearisation (FluidLinearisation): Full is the exact derivative of the residual, the
// dependence of tau_M and tau_C on the convective velocity included; LaggedTau holds tau_M and
// tau_C at their values at the current iterate (the usual choice in codes); Picard also drops
// (du.grad)u and the variation of the SUPG test function, i.e. freezes the convective velocity.
// tests/fluid measures the Newton iterations of the three.
#pragma once

#include "kernels/core/element_loop.hpp"

namespace biofsi {

// tau_M and tau_C at one point from the convective velocity, the kinematic viscosity and 1/dt.
// d_m, d_c: derivatives with respect to the convective velocity.
struct FluidTau {
  Real m = 0, c = 0;
  Real d_m[3] = {0, 0, 0}, d_c[3] = {0, 0, 0};
};

enum class FluidLinearisation { Full, LaggedTau, Picard };

KOKKOS_INLINE_FUNCTION FluidTau fluid_tau(const Real c[3], const Real metric[3][3], Real nu,
                                          Real inv_dt) {
  constexpr Real c_inverse = 36.0;  // C_I, Bazilevs et al. (2007) for trilinear elements
  Real cgc = 0, gg = 0, tr = 0;
  for (int i = 0; i < 3; ++i) {
    tr += metric[i][i];
    for (int j = 0; j < 3; ++j) {
      cgc += c[i] * metric[i][j] * c[j];
      gg += metric[i][j] * metric[i][j];
    }
  }
  const Real steady = cgc + c_inverse * nu * nu * gg;
  FluidTau t;
  const Real all = steady + 4 * inv_dt * inv_dt;
  Real gc[3];
  for (int i = 0; i < 3; ++i)
    gc[i] = metric[i][0] * c[0] + metric[i][1] * c[1] + metric[i][2] * c[2];
  if (all > 0) {
    t.m = 1 / math::sqrt(all);
    for (int i = 0; i < 3; ++i) t.d_m[i] = -t.m * t.m * t.m * gc[i];
  }
  if (steady > 0 && tr > 0) {
    const Real root = math::sqrt(steady);
    t.c = root / tr;
    for (int i = 0; i < 3; ++i) t.d_c[i] = gc[i] / (root * tr);
  }
  return t;
}

// Element physics. Auxiliary nodal data: [u_n (3), u_grid (3), b (3)]; only u_n needs gradients.
struct FluidPhysics {
  static constexpr int n_components = 4, n_aux = 9, n_aux_gradients = 3;
  // First columns of the auxiliary vectors (host code fills them by these names).
  static constexpr int aux_velocity_old = 0, aux_grid_velocity = 3, aux_body_force = 6;
  Real density = 0, viscosity = 0;  // rho, dynamic mu: FluidSettings (src/fluid) holds the defaults
  Real inv_dt = 0;                  // 0: steady
  Real theta = 1;
  bool supg = true, grad_div = true;  // PSPG is always on: Q1-Q1 needs it
  bool symmetric_viscous = true;
  bool transient_tau = true;  // tau_M with its (2/dt)^2 term
  FluidLinearisation linearisation = FluidLinearisation::Full;

  // The velocity and its gradient at t_{n+theta}, the convective velocity there and tau.
  struct Local {
    Real u[3], gu[3][3], c[3];
    FluidTau tau;
  };

  KOKKOS_INLINE_FUNCTION Local local(const QpData<n_aux>& q, const Real u[4],
                                     const Real gu[4][3]) const {
    Local l;
    for (int i = 0; i < 3; ++i) {
      l.u[i] = theta * u[i] + (1 - theta) * q.aux[aux_velocity_old + i];
      for (int j = 0; j < 3; ++j) l.gu[i][j] = theta * gu[i][j] + (1 - theta) * q.grad_aux[i][j];
      l.c[i] = l.u[i] - q.aux[aux_grid_velocity + i];
    }
    l.tau = fluid_tau(l.c, q.metric, viscosity / density, transient_tau ? inv_dt : Real(0));
    if (!grad_div) {
      l.tau.c = 0;
      for (int i = 0; i < 3; ++i) l.tau.d_c[i] = 0;
    }
    return l;
  }

  // Momentum terms without the pressure gradient: rho (du/dt + convection - b).
  KOKKOS_INLINE_FUNCTION void momentum(const QpData<n_aux>& q, const Local& l, const Real u[4],
                                       Real m[3]) const {
    for (int i = 0; i < 3; ++i) {
      Real conv = 0;
      for (int j = 0; j < 3; ++j) conv += l.c[j] * l.gu[i][j];
      m[i] = density *
             ((u[i] - q.aux[aux_velocity_old + i]) * inv_dt + conv - q.aux[aux_body_force + i]);
    }
  }

  KOKKOS_INLINE_FUNCTION static Real divergence(const Real g[3][3]) {
    return g[0][0] + g[1][1] + g[2][2];
  }

  KOKKOS_INLINE_FUNCTION void residual(const QpData<n_aux>& q, const Real u[4], const Real gu[4][3],
                                       Real f0[4], Real f1[4][3]) const {
    const Local l = local(q, u, gu);
    Real m[3], r[3];
    momentum(q, l, u, m);
    for (int i = 0; i < 3; ++i) r[i] = m[i] + gu[3][i];
    const Real div = divergence(l.gu);
    const Real s = symmetric_viscous ? 1.0 : 0.0;
    for (int i = 0; i < 3; ++i) {
      f0[i] = m[i];
      for (int j = 0; j < 3; ++j)
        f1[i][j] =
            viscosity * (l.gu[i][j] + s * l.gu[j][i]) + (supg ? l.tau.m * l.c[j] * r[i] : 0.0);
      f1[i][i] += density * l.tau.c * div - u[3];
    }
    f0[3] = div;
    for (int j = 0; j < 3; ++j) f1[3][j] = l.tau.m * r[j] / density;
  }

  // What the tangent needs of the linearisation point, per point: the convective velocity, the
  // velocity gradient and the momentum residual (for the Newton terms; zero for Picard), tau_M,
  // tau_C, their derivatives along the convective velocity (zero unless Full) and div u. All
  // members are T, so that a stored tangent can keep it as a row of doubles
  // (kernels/core/stored_tangent.hpp).
  template <class T>
  struct PointState {
    T c[3], gu[3][3], r[3], tau_m, tau_c, d_m[3], d_c[3], div;
  };

  KOKKOS_INLINE_FUNCTION PointState<Real> point_state(const QpData<n_aux>& q, const Real u[4],
                                                      const Real gu[4][3]) const {
    const Local l = local(q, u, gu);
    const bool newton = linearisation != FluidLinearisation::Picard;
    const bool full = linearisation == FluidLinearisation::Full;
    PointState<Real> s;
    Real m[3];
    momentum(q, l, u, m);
    for (int i = 0; i < 3; ++i) {
      s.c[i] = l.c[i];
      s.r[i] = newton ? m[i] + gu[3][i] : 0.0;
      for (int j = 0; j < 3; ++j) s.gu[i][j] = newton ? l.gu[i][j] : 0.0;
      s.d_m[i] = full ? l.tau.d_m[i] : 0.0;
      s.d_c[i] = full ? l.tau.d_c[i] : 0.0;
    }
    s.tau_m = l.tau.m;
    s.tau_c = l.tau.c;
    s.div = divergence(l.gu);
    return s;
  }

  // The tangent at a point from its state; du is the variation of u at t_{n+1}, the state at
  // t_{n+theta} varies by theta du. T is Real or a SIMD pack of points.
  template <class T>
  KOKKOS_INLINE_FUNCTION void tangent_at(const PointState<T>& s, const T du[4], const T gdu[4][3],
                                         T df0[4], T df1[4][3]) const {
    T dut[3], gdut[3][3];
    for (int i = 0; i < 3; ++i) {
      dut[i] = theta * du[i];
      for (int j = 0; j < 3; ++j) gdut[i][j] = theta * gdu[i][j];
    }
    // Variations of tau along dc = theta du (velocity part), Full only (else d_m = d_c = 0).
    T dtm = 0, dtc = 0;
    for (int i = 0; i < 3; ++i) {
      dtm += s.d_m[i] * dut[i];
      dtc += s.d_c[i] * dut[i];
    }
    T dr[3];
    for (int i = 0; i < 3; ++i) {
      T dconv = 0;
      for (int j = 0; j < 3; ++j) dconv += s.c[j] * gdut[i][j] + dut[j] * s.gu[i][j];
      df0[i] = density * (du[i] * inv_dt + dconv);
      dr[i] = df0[i] + gdu[3][i];
    }
    const T ddiv = gdut[0][0] + gdut[1][1] + gdut[2][2];
    const Real sym = symmetric_viscous ? 1.0 : 0.0;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        df1[i][j] = viscosity * (gdut[i][j] + sym * gdut[j][i]);
        if (supg) df1[i][j] += s.tau_m * (s.c[j] * dr[i] + dut[j] * s.r[i]) + dtm * s.c[j] * s.r[i];
      }
      df1[i][i] += density * (s.tau_c * ddiv + dtc * s.div) - du[3];
    }
    df0[3] = ddiv;
    for (int j = 0; j < 3; ++j) df1[3][j] = (s.tau_m * dr[j] + dtm * s.r[j]) / density;
  }

  KOKKOS_INLINE_FUNCTION void tangent(const QpData<n_aux>& q, const Real u[4], const Real gu[4][3],
                                      const Real du[4], const Real gdu[4][3], Real df0[4],
                                      Real df1[4][3]) const {
    tangent_at(point_state(q, u, gu), du, gdu, df0, df1);
  }
};

// Prescribed traction h (force per area, at t_{n+theta}) on boundary faces: r_a -= int N_a h.
// Auxiliary nodal data on the faces: [h_x, h_y, h_z]. A do-nothing outflow is no face term at all.
struct FluidTractionPhysics {
  static constexpr int n_components = 4, n_aux = 3;
  KOKKOS_INLINE_FUNCTION void residual(const Real aux[3], const Real[4], Real f0[4]) const {
    for (int i = 0; i < 3; ++i) f0[i] = -aux[i];
    f0[3] = 0;
  }
  KOKKOS_INLINE_FUNCTION void tangent(const Real[3], const Real[4], const Real[4],
                                      Real df0[4]) const {
    for (int i = 0; i < 4; ++i) df0[i] = 0;
  }
};

}  // namespace biofsi
