// kernels/structure: pointwise physics of the structure field (paper eq. 1) — total Lagrangian
// finite-strain elastodynamics of the biofilm for the displacement d (3 components), with per-block
// hyperelastic materials (St. Venant-Kirchhoff, compressible Neo-Hooke), density and gravity.
// Used by src/structure; depends on kernels/core only. Everything here is device code: the same
// functions give the residual, the tangent action, the diagonal, the assembled matrix, and (called
// on the host) the stresses and energies for output and verification.
//
// Time integration is one-step-theta on displacement and velocity,
//   (d_{n+1} - d_n)/dt = theta v_{n+1} + (1 - theta) v_n,
//   rho (v_{n+1} - v_n)/dt + theta r(d_{n+1}) + (1 - theta) r(d_n) = theta f_{n+1} + (1-theta) f_n,
// with v_{n+1} eliminated. The unknown is the increment u = d_{n+1} - d_n (not d_{n+1}): for tiny
// steps the inertia term rho (u - dt v_n)/(theta dt^2) is then formed from small numbers, whose
// round-off is relative to |u| rather than to |d|. At one point, on the reference configuration:
//   f0 = rho/(theta dt^2) (u - dt v_n) - b - rho g          (b: nodal body force per volume)
//   f1 = theta P(F_{n+1}) + (1 - theta) P(F_n),   F_{n+1} = I + grad d_n + grad u,  P = F S
// Quasi-static: mass_coefficient = 0 and theta = 1. The residual of r_a = int N_a f0 + grad N_a.f1
// is internal minus external force; tractions enter through src/structure's face terms.
#pragma once

#include "kernels/core/element_loop.hpp"

namespace biofsi {

constexpr int max_structure_blocks = 8;

enum StructureModel : int { SaintVenantKirchhoff = 0, NeoHooke = 1 };

// Per-block material data (Lame parameters, density, gravity per unit mass).
struct StructureMaterials {
  int model[max_structure_blocks] = {};
  Real lambda[max_structure_blocks] = {};
  Real mu[max_structure_blocks] = {};
  Real density[max_structure_blocks] = {};
  Real gravity[max_structure_blocks][3] = {};
};

// ---- small 3x3 helpers ----

KOKKOS_INLINE_FUNCTION Real det3(const Real a[3][3]) {
  return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
         a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
         a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

// Inverse of a symmetric positive definite C, given det C.
KOKKOS_INLINE_FUNCTION void inverse3(const Real a[3][3], Real det, Real inv[3][3]) {
  const Real s = 1.0 / det;
  inv[0][0] = (a[1][1] * a[2][2] - a[1][2] * a[2][1]) * s;
  inv[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) * s;
  inv[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) * s;
  inv[1][0] = (a[1][2] * a[2][0] - a[1][0] * a[2][2]) * s;
  inv[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) * s;
  inv[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) * s;
  inv[2][0] = (a[1][0] * a[2][1] - a[1][1] * a[2][0]) * s;
  inv[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) * s;
  inv[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) * s;
}

// F = I + grad d
KOKKOS_INLINE_FUNCTION void deformation_gradient(const Real g[3][3], Real f[3][3]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) f[i][j] = g[i][j] + (i == j ? 1.0 : 0.0);
}

// C = F^T F
KOKKOS_INLINE_FUNCTION void right_cauchy_green(const Real f[3][3], Real c[3][3]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) c[i][j] = f[0][i] * f[0][j] + f[1][i] * f[1][j] + f[2][i] * f[2][j];
}

// dE = sym(F^T dF), the Green-Lagrange strain's derivative along dF.
KOKKOS_INLINE_FUNCTION void strain_variation(const Real f[3][3], const Real df[3][3],
                                             Real de[3][3]) {
  Real a[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      a[i][j] = f[0][i] * df[0][j] + f[1][i] * df[1][j] + f[2][i] * df[2][j];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) de[i][j] = 0.5 * (a[i][j] + a[j][i]);
}

// ---- constitutive laws (2nd Piola-Kirchhoff stress S and its derivative along dF) ----
//
// St. Venant-Kirchhoff: W = lambda/2 (tr E)^2 + mu E:E, S = lambda tr(E) I + 2 mu E.
// Compressible Neo-Hooke with the isochoric/volumetric split of the deal.II code-gallery Cook's
// membrane (the reference of ../shared/reference/benchmarks.md), kappa = lambda + 2 mu / 3:
//   W = mu/2 (J^{-2/3} I1 - 3) + kappa/4 (J^2 - 1 - 2 ln J),
//   S = mu J^{-2/3} (I - I1/3 C^{-1}) + kappa/2 (J^2 - 1) C^{-1}.
// For J <= 0 the Neo-Hooke stress is NaN (log of a non-positive number): the Newton line search
// treats a non-finite residual as a failed trial and shortens the step.

// Which terms of the strain energy a quadrature rule integrates. Selective reduced integration
// splits W into its volumetric term (kappa/4 (J^2 - 1 - 2 ln J) for Neo-Hooke, lambda/2 (tr E)^2
// for St. Venant-Kirchhoff: the terms that grow without bound as nu -> 0.5) integrated at the
// element centre, and the rest at the 2x2x2 points; one volumetric constraint per element instead
// of eight is what removes hex8's volumetric locking.
enum class EnergyTerms : int { All = 0, AllButVolumetric = 1, Volumetric = 2 };

struct MaterialPoint {
  int model;
  Real lambda, mu;
  EnergyTerms terms = EnergyTerms::All;
  KOKKOS_INLINE_FUNCTION Real volumetric_weight() const {
    return terms == EnergyTerms::AllButVolumetric ? 0.0 : 1.0;
  }
  KOKKOS_INLINE_FUNCTION Real other_weight() const {
    return terms == EnergyTerms::Volumetric ? 0.0 : 1.0;
  }
};

// E = (G + G^T + G^T G)/2 from the displacement gradient G, never through C - I: at small strains
// that difference would lose eps/|G| of relative accuracy (1e-10 at strains of 1e-6).
KOKKOS_INLINE_FUNCTION void green_lagrange(const Real g[3][3], Real e[3][3]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      e[i][j] =
          0.5 * (g[i][j] + g[j][i] + g[0][i] * g[0][j] + g[1][i] * g[1][j] + g[2][i] * g[2][j]);
}

// The constitutive functions take the displacement gradient G (F = I + G) for that reason.
KOKKOS_INLINE_FUNCTION void second_piola_kirchhoff(const MaterialPoint& m, const Real g[3][3],
                                                   Real s[3][3]) {
  if (m.model == SaintVenantKirchhoff) {
    Real e[3][3];
    green_lagrange(g, e);
    const Real two_mu = 2.0 * m.mu * m.other_weight();
    const Real lambda_tr_e = m.lambda * m.volumetric_weight() * (e[0][0] + e[1][1] + e[2][2]);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) s[i][j] = two_mu * e[i][j] + (i == j ? lambda_tr_e : 0.0);
    return;
  }
  Real f[3][3], c[3][3];
  deformation_gradient(g, f);
  right_cauchy_green(f, c);
  const Real kappa = m.lambda + 2.0 * m.mu / 3.0;
  const Real det_c = det3(c);
  const Real j = math::sqrt(det_c);
  const Real log_j = math::log(j);
  const Real a = math::exp(-2.0 / 3.0 * log_j);  // J^{-2/3}
  Real ci[3][3];
  inverse3(c, det_c, ci);
  const Real i1 = c[0][0] + c[1][1] + c[2][2];
  const Real vol = 0.5 * kappa * (j * j - 1.0) * m.volumetric_weight();
  const Real mu_a = m.mu * a * m.other_weight();
  for (int p = 0; p < 3; ++p)
    for (int q = 0; q < 3; ++q)
      s[p][q] = mu_a * ((p == q ? 1.0 : 0.0) - i1 / 3.0 * ci[p][q]) + vol * ci[p][q];
}

// dS along dF (the consistent material tangent C : dE, dE = sym(F^T dF)).
KOKKOS_INLINE_FUNCTION void second_piola_kirchhoff_derivative(const MaterialPoint& m,
                                                              const Real g[3][3],
                                                              const Real df[3][3], Real ds[3][3]) {
  Real f[3][3], de[3][3];
  deformation_gradient(g, f);
  strain_variation(f, df, de);
  if (m.model == SaintVenantKirchhoff) {
    const Real two_mu = 2.0 * m.mu * m.other_weight();
    const Real lambda_tr = m.lambda * m.volumetric_weight() * (de[0][0] + de[1][1] + de[2][2]);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) ds[i][j] = two_mu * de[i][j] + (i == j ? lambda_tr : 0.0);
    return;
  }
  // With dC = 2 dE: dJ = J C^{-1}:dE, d(C^{-1}) = -2 C^{-1} dE C^{-1}, d(J^{-2/3}) = -2/3 J^{-2/3}
  // C^{-1}:dE, dI1 = 2 tr dE.
  const Real kappa = (m.lambda + 2.0 * m.mu / 3.0) * m.volumetric_weight();
  const Real mu = m.mu * m.other_weight();
  Real c[3][3], ci[3][3];
  right_cauchy_green(f, c);
  const Real det_c = det3(c);
  inverse3(c, det_c, ci);
  const Real j2 = det_c;
  const Real a = math::exp(-1.0 / 3.0 * math::log(det_c));  // J^{-2/3}
  const Real i1 = c[0][0] + c[1][1] + c[2][2];
  Real ci_de = 0, tr_de = de[0][0] + de[1][1] + de[2][2];
  for (int p = 0; p < 3; ++p)
    for (int q = 0; q < 3; ++q) ci_de += ci[p][q] * de[p][q];
  // C^{-1} dE C^{-1}
  Real t[3][3], cdc[3][3];
  for (int p = 0; p < 3; ++p)
    for (int q = 0; q < 3; ++q)
      t[p][q] = ci[p][0] * de[0][q] + ci[p][1] * de[1][q] + ci[p][2] * de[2][q];
  for (int p = 0; p < 3; ++p)
    for (int q = 0; q < 3; ++q)
      cdc[p][q] = t[p][0] * ci[0][q] + t[p][1] * ci[1][q] + t[p][2] * ci[2][q];
  const Real da = -2.0 / 3.0 * a * ci_de;
  const Real di1 = 2.0 * tr_de;
  for (int p = 0; p < 3; ++p)
    for (int q = 0; q < 3; ++q) {
      const Real id = p == q ? 1.0 : 0.0;
      const Real iso =
          da * (id - i1 / 3.0 * ci[p][q]) - a * (di1 / 3.0 * ci[p][q] - 2.0 * i1 / 3.0 * cdc[p][q]);
      const Real vol = kappa * j2 * ci_de * ci[p][q] - kappa * (j2 - 1.0) * cdc[p][q];
      ds[p][q] = mu * iso + vol;
    }
}

// Strain energy per reference volume (energy checks and output).
KOKKOS_INLINE_FUNCTION Real strain_energy_density(const MaterialPoint& m, const Real g[3][3]) {
  if (m.model == SaintVenantKirchhoff) {
    Real e[3][3], ee = 0;
    green_lagrange(g, e);
    const Real tr = e[0][0] + e[1][1] + e[2][2];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) ee += e[i][j] * e[i][j];
    return m.volumetric_weight() * 0.5 * m.lambda * tr * tr + m.other_weight() * m.mu * ee;
  }
  Real f[3][3], c[3][3];
  deformation_gradient(g, f);
  right_cauchy_green(f, c);
  const Real kappa = m.lambda + 2.0 * m.mu / 3.0;
  const Real det_c = det3(c);
  const Real log_j = 0.5 * math::log(det_c);
  const Real a = math::exp(-2.0 / 3.0 * log_j);
  const Real i1 = c[0][0] + c[1][1] + c[2][2];
  return m.other_weight() * 0.5 * m.mu * (a * i1 - 3.0) +
         m.volumetric_weight() * 0.25 * kappa * (det_c - 1.0 - 2.0 * log_j);
}

// P = F S
KOKKOS_INLINE_FUNCTION void first_piola_kirchhoff(const MaterialPoint& m, const Real g[3][3],
                                                  Real p[3][3]) {
  Real s[3][3], f[3][3];
  second_piola_kirchhoff(m, g, s);
  deformation_gradient(g, f);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) p[i][j] = f[i][0] * s[0][j] + f[i][1] * s[1][j] + f[i][2] * s[2][j];
}

// dP = dF S + F dS
KOKKOS_INLINE_FUNCTION void first_piola_kirchhoff_derivative(const MaterialPoint& m,
                                                             const Real g[3][3],
                                                             const Real df[3][3], Real dp[3][3]) {
  Real s[3][3], ds[3][3], f[3][3];
  second_piola_kirchhoff(m, g, s);
  second_piola_kirchhoff_derivative(m, g, df, ds);
  deformation_gradient(g, f);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      Real v = 0;
      for (int k = 0; k < 3; ++k) v += df[i][k] * s[k][j] + f[i][k] * ds[k][j];
      dp[i][j] = v;
    }
}

// Cauchy stress sigma = J^{-1} P F^T.
KOKKOS_INLINE_FUNCTION void cauchy_stress(const MaterialPoint& m, const Real g[3][3],
                                          Real sigma[3][3]) {
  Real p[3][3], f[3][3];
  first_piola_kirchhoff(m, g, p);
  deformation_gradient(g, f);
  const Real j = det3(f);
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      sigma[i][k] = (p[i][0] * f[k][0] + p[i][1] * f[k][1] + p[i][2] * f[k][2]) / j;
}

KOKKOS_INLINE_FUNCTION Real von_mises(const Real s[3][3]) {
  const Real d01 = s[0][0] - s[1][1], d12 = s[1][1] - s[2][2], d20 = s[2][2] - s[0][0];
  return math::sqrt(0.5 * (d01 * d01 + d12 * d12 + d20 * d20) +
                    3.0 * (s[0][1] * s[0][1] + s[1][2] * s[1][2] + s[2][0] * s[2][0]));
}

// ---- element physics ----
//
// Auxiliary nodal data: [d_n (3), v_n (3), b (3)]; only d_n needs a gradient.
struct StructurePhysics {
  static constexpr int n_components = 3, n_aux = 9, n_aux_gradients = 3;
  // First columns of the auxiliary vectors (host code fills them by these names); the gradient
  // of d_n is grad_aux[0..2] (n_aux_gradients = 3 takes the first three columns).
  static constexpr int aux_displacement_old = 0, aux_velocity_old = 3, aux_body_force = 6;
  static_assert(aux_displacement_old == 0, "grad_aux holds the gradient of the first columns");
  // Hyperelastic: dP/dF has major symmetry, the mass term is diagonal, and neither couples
  // displacement values to gradients (the stored tangent keeps only what that leaves).
  static constexpr bool tangent_symmetric = true, tangent_couples_values_and_gradients = false;
  StructureMaterials materials;
  Real mass_coefficient = 0;  // 1/(theta dt^2); 0: quasi-static
  Real dt = 0;
  Real theta = 1;
  // Selective reduced integration binds this physics twice: the volumetric terms at the centre
  // point, everything else (inertia and loads included) at the 2x2x2 points.
  EnergyTerms terms = EnergyTerms::All;

  KOKKOS_INLINE_FUNCTION MaterialPoint material(int block) const {
    return {materials.model[block], materials.lambda[block], materials.mu[block], terms};
  }
  KOKKOS_INLINE_FUNCTION bool has_loads() const { return terms != EnergyTerms::Volumetric; }

  KOKKOS_INLINE_FUNCTION void residual(const QpData<9>& q, const Real u[3], const Real gu[3][3],
                                       Real f0[3], Real f1[3][3]) const {
    const MaterialPoint m = material(q.block);
    const Real rho = materials.density[q.block];
    Real g[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) g[i][j] = q.grad_aux[i][j] + gu[i][j];
    first_piola_kirchhoff(m, g, f1);
    if (theta < 1) {
      Real pn[3][3];
      first_piola_kirchhoff(m, q.grad_aux, pn);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) f1[i][j] = theta * f1[i][j] + (1.0 - theta) * pn[i][j];
    }
    for (int i = 0; i < 3; ++i)
      f0[i] = has_loads() ? rho * mass_coefficient * (u[i] - dt * q.aux[aux_velocity_old + i]) -
                                q.aux[aux_body_force + i] - rho * materials.gravity[q.block][i]
                          : 0.0;
  }

  KOKKOS_INLINE_FUNCTION void tangent(const QpData<9>& q, const Real[3], const Real gu[3][3],
                                      const Real du[3], const Real gdu[3][3], Real df0[3],
                                      Real df1[3][3]) const {
    const MaterialPoint m = material(q.block);
    const Real rho = materials.density[q.block];
    Real g[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) g[i][j] = q.grad_aux[i][j] + gu[i][j];
    first_piola_kirchhoff_derivative(m, g, gdu, df1);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) df1[i][j] *= theta;
    for (int i = 0; i < 3; ++i) df0[i] = has_loads() ? rho * mass_coefficient * du[i] : 0.0;
  }
};

// Dead-load traction on boundary faces: aux = the traction per reference area (already weighted
// theta t_{n+1} + (1 - theta) t_n by the host); it does not follow the deformation, so the tangent
// is zero.
struct DeadLoadTraction {
  static constexpr int n_components = 3, n_aux = 3;
  KOKKOS_INLINE_FUNCTION void residual(const Real aux[3], const Real[3], Real f0[3]) const {
    for (int i = 0; i < 3; ++i) f0[i] = -aux[i];
  }
  KOKKOS_INLINE_FUNCTION void tangent(const Real[3], const Real[3], const Real[3],
                                      Real df0[3]) const {
    df0[0] = df0[1] = df0[2] = 0;
  }
};

// Energy integrands (n_components = 1, so r_a = int N_a f0 and sum_a r_a = int f0): the strain
// energy of d = aux[0..2] and the kinetic energy of v = aux[3..5] with the consistent mass.
struct StructureEnergyIntegrand {
  static constexpr int n_components = 1, n_aux = 6, n_aux_gradients = 3;
  StructureMaterials materials;
  bool kinetic = false;
  EnergyTerms terms = EnergyTerms::All;  // of the strain energy (see StructurePhysics::terms)
  KOKKOS_INLINE_FUNCTION void residual(const QpData<6>& q, const Real[1], const Real[1][3],
                                       Real f0[1], Real f1[1][3]) const {
    f1[0][0] = f1[0][1] = f1[0][2] = 0;
    if (kinetic) {
      const Real* v = q.aux + 3;
      f0[0] = 0.5 * materials.density[q.block] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      return;
    }
    f0[0] = strain_energy_density(
        {materials.model[q.block], materials.lambda[q.block], materials.mu[q.block], terms},
        q.grad_aux);
  }
  KOKKOS_INLINE_FUNCTION void tangent(const QpData<6>&, const Real[1], const Real[1][3],
                                      const Real[1], const Real[1][3], Real df0[1],
                                      Real df1[1][3]) const {
    df0[0] = 0;
    df1[0][0] = df1[0][1] = df1[0][2] = 0;
  }
};

}  // namespace biofsi
