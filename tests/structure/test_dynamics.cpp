// Time integration of the structure field (one-step-theta on displacement and velocity): energy of
// free vibrations, and the range of time steps from 1e-6 to 1e3 natural periods.
//
// Tolerances, and why:
//  * theta = 0.5 (trapezoidal rule): for a linear system it conserves the energy
//    1/2 v.M v + 1/2 d.K d exactly; the finite-strain energy differs from that quadratic one at
//    the relative order of the strain. At strains ~1e-5 the drift over 1000 steps must stay below
//    1e-6 relative (the requirement); St. Venant-Kirchhoff at strains ~1e-6, Neo-Hooke at
//    ~1e-4 (its energy evaluation loses eps/strain^2 to cancellation: 1e-4 relative at 1e-6).
//  * theta > 0.5 on one free dof (all others held): the exact energy ratio per step of the theta
//    method on x'' = -w^2 x is |A|^2 = (1 + (1-theta)^2 w^2 dt^2) / (1 + theta^2 w^2 dt^2), with
//    w^2 = K_ii / M_ii from the assembled matrices. After 20 steps the measured ratio must match
//    |A|^40 to 1e-6 relative: the system is linear to 1e-8 (strain 1e-8), so what is left is
//    Newton's tolerance. The test also prints the decay so the number is on record.
//  * theta > 0.5 on the block: the energy never increases from one step to the next (beyond 1e-12
//    relative, round-off of the energy sums): every mode decays.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "kernels/core/csr.hpp"
#include "structure/structure_test_support.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

Mesh block() {
  Mesh m = box_mesh(2, 2, 1.0, {{"block", 0.0, 1.0, 2, 1.0}});
  distort(m, [](const Point& p) { return smooth_cube_map(p, 0.05); });
  return m;
}

double total_energy(const StructureField& f) { return f.kinetic_energy() + f.strain_energy(); }

// Clamped at the bottom, initial velocity a smooth sway and twist of size `v0`.
std::vector<double> vibrate(double theta, double v0, int steps, double dt, StructureModel model,
                            VolumetricIntegration volumetric = VolumetricIntegration::Full) {
  const Mesh mesh = block();
  StructureSettings s = tight_structure_settings({material(model, 1.0, 0.3, 1.0)}, false);
  s.theta = theta;
  s.volumetric_integration = volumetric;
  s.newton.rel_tol = 1e-10;
  s.newton.abs_tol = 1e-18 * v0;
  StructureField field(mesh, s, {clamp("bottom")});
  std::vector<Point> v(mesh.n_nodes());
  for (int n = 0; n < mesh.n_nodes(); ++n) {
    const Point& p = mesh.x[n];
    v[n] = {v0 * p[1] * (1 + 0.3 * p[2]), 0.2 * v0 * p[1] * p[0], -v0 * p[1] * (p[0] - 0.5)};
  }
  for (int n : mesh.node_sets.at("bottom")) v[n] = {0, 0, 0};
  field.set_state({}, v, 0.0);
  std::vector<double> e{total_energy(field)};
  for (int i = 0; i < steps; ++i) {
    field.step(dt, "step " + std::to_string(i + 1));
    e.push_back(total_energy(field));
  }
  return e;
}

}  // namespace

TEST(StructureDynamics, TrapezoidalRuleConservesEnergyOverThousandSteps) {
  for (StructureModel model : {SaintVenantKirchhoff, NeoHooke}) {
    // The block's lowest period is ~4 (E = rho = 1, size 1); dt = 0.05 resolves it with ~80 steps.
    // Neo-Hooke's energy is an O(1) expression whose O(strain^2) value loses eps/strain^2 to
    // cancellation, so it vibrates at strains 1e-4 (energy round-off 1e-8).
    const std::vector<double> e = vibrate(0.5, model == NeoHooke ? 1e-4 : 1e-6, 1000, 0.05, model);
    double drift = 0;
    for (double x : e) drift = std::max(drift, std::abs(x - e[0]) / e[0]);
    std::printf("[ measured ] theta = 0.5, %s: max |E_n - E_0|/E_0 over 1000 steps = %.2e\n",
                model == NeoHooke ? "Neo-Hooke" : "St.Venant-Kirchhoff", drift);
    EXPECT_LT(drift, 1e-6);
  }
  // With the volumetric term at the element centre the conserved energy is the one integrated by
  // the same two rules (StructureField::strain_energy); integrating it by one rule would not be.
  const std::vector<double> e =
      vibrate(0.5, 1e-6, 1000, 0.05, SaintVenantKirchhoff, VolumetricIntegration::Reduced);
  double drift = 0;
  for (double x : e) drift = std::max(drift, std::abs(x - e[0]) / e[0]);
  std::printf("[ measured ] theta = 0.5, St.Venant-Kirchhoff, reduced volumetric: drift %.2e\n",
              drift);
  EXPECT_LT(drift, 1e-6);
}

TEST(StructureDynamics, ThetaAboveHalfDecaysTheBlockMonotonically) {
  const std::vector<double> e = vibrate(0.66, 1e-5, 200, 0.05, SaintVenantKirchhoff);
  double worst = 0;
  for (size_t i = 1; i < e.size(); ++i) worst = std::max(worst, (e[i] - e[i - 1]) / e[0]);
  std::printf("[ measured ] theta = 0.66 block: E_200/E_0 = %.4f, largest step increase %.1e\n",
              e.back() / e[0], worst);
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT(e.back(), e[0]);
}

// One free dof: node 7's x displacement on a single element with every other dof held.
struct OneDof {
  Mesh mesh;
  double k = 0, m = 0;  // K_ii, M_ii
};

OneDof one_dof() {
  OneDof o;
  o.mesh = box_mesh(1, 1, 1.0, {{"cell", 0.0, 1.0, 1, 1.0}});
  o.mesh.node_sets["held"] = {0, 1, 2, 3, 4, 5, 6};
  o.mesh.node_sets["free"] = {7};
  return o;
}

std::vector<StructureDirichlet> one_dof_conditions() {
  return {clamp("held"), StructureDirichlet{"free", {nullptr, constant(0), constant(0)}}};
}

TEST(StructureDynamics, OneDofDecayMatchesThetaMethodAmplification) {
  OneDof o = one_dof();
  const StructureMaterial mat = material(SaintVenantKirchhoff, 1.0, 0.3, 1.0);
  const int dof = 3 * 7;
  // K_ii from the quasi-static tangent at rest, M_ii from the dynamic one:
  // A_ii = M_ii / (theta dt^2) + theta K_ii.
  {
    StructureField qs(o.mesh, tight_structure_settings({mat}, true), one_dof_conditions());
    qs.prepare_step(1.0);
    Vector zero(std::string("test::zero"), qs.n_dofs()), d(std::string("test::d"), qs.n_dofs());
    qs.assemble(zero, false);
    csr_diagonal(qs.matrix(), d);
    o.k = to_host(d)[dof];
  }
  const double theta = 0.66, dt = 0.3;  // w dt ~ 0.76: a decay of ~15% per step
  StructureSettings s = tight_structure_settings({mat}, false);
  s.theta = theta;
  // Newton to round-off (the field's own floor stops it there); a cut step, which would change dt
  // and so the decay, is excluded below.
  s.newton.rel_tol = 1e-15;
  s.newton.abs_tol = 0;
  StructureField field(o.mesh, s, one_dof_conditions());
  {
    field.prepare_step(dt);
    Vector zero(std::string("test::zero"), field.n_dofs()),
        d(std::string("test::d"), field.n_dofs());
    field.assemble(zero, false);
    csr_diagonal(field.matrix(), d);
    o.m = (to_host(d)[dof] - theta * o.k) * theta * dt * dt;
  }
  const double w2 = o.k / o.m, wdt2 = w2 * dt * dt;
  const double per_step = (1 + (1 - theta) * (1 - theta) * wdt2) / (1 + theta * theta * wdt2);
  std::vector<Point> d0(o.mesh.n_nodes(), Point{0, 0, 0});
  d0[7][0] = 1e-8;
  field.set_state(d0, {}, 0.0);
  const double e0 = total_energy(field);
  const int steps = 20;
  for (int i = 0; i < steps; ++i) field.step(dt, "one dof step " + std::to_string(i + 1));
  const double ratio = total_energy(field) / e0, expected = std::pow(per_step, steps);
  std::printf(
      "[ measured ] one dof, theta = %.2f, w dt = %.3f: E_%d/E_0 = %.8f, expected |A|^%d = %.8f "
      "(per step %.6f)\n",
      theta, std::sqrt(wdt2), steps, ratio, 2 * steps / 2, expected, per_step);
  EXPECT_NEAR(ratio / expected, 1.0, 1e-6);
  EXPECT_EQ(field.stats().cut_steps, 0);
}

TEST(StructureDynamics, TimeStepsFromMicroToKiloPeriods) {
  // Natural period of the one-dof system, then steps of 1e-6 to 1e3 periods: each must converge
  // and give finite states; with theta = 0.5 the energy is conserved at every size (to 1e-6), with
  // theta = 1 it decays and never grows.
  OneDof o = one_dof();
  const StructureMaterial mat = material(SaintVenantKirchhoff, 1.0, 0.3, 1.0);
  StructureField probe(o.mesh, tight_structure_settings({mat}, true), one_dof_conditions());
  probe.prepare_step(1.0);
  Vector zero(std::string("test::zero"), probe.n_dofs()), d(std::string("test::d"), probe.n_dofs());
  probe.assemble(zero, false);
  csr_diagonal(probe.matrix(), d);
  const double k = to_host(d)[21];
  // Consistent mass diagonal of a unit cube's corner node: rho V / 27.
  const double period = 2 * pi * std::sqrt((1.0 / 27.0) / k);
  for (double theta : {0.5, 1.0})
    for (double factor : {1e-6, 1e-3, 1.0, 1e3}) {
      StructureSettings s = tight_structure_settings({mat}, false);
      s.theta = theta;
      // For dt >> T the velocity is recovered from u/dt, where the inertia term is a fraction
      // (T/dt)^2 of the residual: conserving the energy there needs Newton near round-off.
      s.newton.rel_tol = 1e-15;
      s.newton.abs_tol = 0;
      StructureField field(o.mesh, s, one_dof_conditions());
      std::vector<Point> d0(o.mesh.n_nodes(), Point{0, 0, 0});
      d0[7][0] = 1e-6;
      field.set_state(d0, {}, 0.0);
      const double e0 = total_energy(field);
      for (int i = 0; i < 5; ++i) field.step(factor * period, "dt factor step");
      const double e = total_energy(field);
      std::printf("[ measured ] dt = %g T, theta = %.1f: E_5/E_0 = %.9f\n", factor, theta, e / e0);
      ASSERT_TRUE(std::isfinite(e));
      EXPECT_EQ(field.stats().cut_steps, 0);
      // For dt >> T the inertia term is a fraction 1/(theta w dt)^2 of the residual, so Newton's
      // round-off floor (~1e-14 of the residual) reaches the velocity amplified by (w dt)^2: the
      // conservation tolerance is 1e-6 or 1e3 eps (w dt)^2, whichever is larger (9e-6 at 1e3 T).
      const double wdt = 2 * pi * factor;
      const double tol = std::max(1e-6, 1e3 * 2.2e-16 * wdt * wdt);
      if (theta == 0.5)
        EXPECT_NEAR(e / e0, 1.0, tol);
      else
        EXPECT_LE(e / e0, 1.0 + 1e-9);
    }
}
