// Coupled solves on the elastic layer under a shear flow (fsi_test_support.hpp): the interface
// conditions hold in the converged state (checked with each field's own operators, not through
// the condensed residual), Newton converges at the extremes the issue names (biofilm density
// equal to the fluid's, a very soft layer deforming by a large fraction of its thickness), the
// inexact Newton without shape derivatives converges but needs more iterations, and a failed
// solve reports its field, step and residual history.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include "coupling/fsi_test_support.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

double max_abs_component(const std::vector<Point>& v, int c) {
  double m = 0;
  for (const auto& p : v) m = std::max(m, std::abs(p[c]));
  return m;
}

// Traction equilibrium on Γ: at every unconstrained structure node the structure's internal
// force (its unconstrained residual at the converged displacement, quasi-static) equals the
// force of the fluid on the wall from the fluid's consistent reaction, and vanishes inside.
// Returns max |r_s - f_fluid| / max |f_fluid|.
double traction_mismatch(LayerProblem& lp) {
  StructureField& s = *lp.structure;
  s.begin_step(0.0);  // quasi-static: zero increment from the converged displacement
  Vector r("r", s.n_dofs());
  s.residual_unconstrained(s.increment(), r);
  const std::vector<double> rs = to_host_vector(r);
  const std::vector<char> fixed = to_host(s.constrained_mask());
  std::vector<Point> fluid_force(lp.mesh.n_nodes(), Point{0, 0, 0});
  const BoundaryTraction t = lp.fluid->boundary_traction("solid_fluid");
  for (size_t i = 0; i < t.nodes.size(); ++i) fluid_force[t.nodes[i]] = t.force[i];
  double worst = 0, scale = 0;
  for (int n : s.active_nodes())
    for (int c = 0; c < 2; ++c) {  // in-plane components (w = 0 is constrained)
      scale = std::max(scale, std::abs(fluid_force[n][c]));
      if (!fixed[3 * n + c]) worst = std::max(worst, std::abs(rs[3 * n + c] - fluid_force[n][c]));
    }
  return worst / scale;
}

// Kinematic condition on Γ: fluid velocity = structure velocity, and the fluid mesh sits where
// the structure is. Returns the largest difference of either.
double interface_mismatch(const LayerProblem& lp) {
  const auto uf = lp.fluid->velocity();
  const auto vs = lp.structure->velocity();
  const auto ds = lp.structure->displacement();
  const auto dg = lp.fsi->mesh_displacement();
  double worst = 0;
  for (int n : lp.mesh.node_sets.at("solid_fluid"))
    for (int c = 0; c < 3; ++c)
      worst = std::max({worst, std::abs(uf[n][c] - vs[n][c]), std::abs(dg[n][c] - ds[n][c])});
  return worst;
}

// The layer problem with the fluid at rest at t = 0.
LayerProblem make_started_layer(const LayerParameters& p) {
  LayerProblem lp = make_layer_problem(p);
  lp.fluid->set_initial(nullptr, nullptr, 0.0);
  return lp;
}

// 12 x (3 + 8) elements: enough for the flow to shear the layer visibly, small enough for CI.
LayerParameters resolved_layer() {
  LayerParameters p;
  p.nx = 12;
  p.ny_solid = 3;
  p.ny_fluid = 8;
  return p;
}

double min_scaled_jacobian(const Mesh& mesh) {
  double q = 1;
  for (const QualityRange& r : mesh_quality_by_block(mesh)) q = std::min(q, r.min);
  return q;
}

// The smallest stretch of the layer's surface along the flow: current over reference length of
// each interface edge in the z = 0 plane (< 1: compressed). Returns {stretch, reference x of the
// edge's centre}.
std::pair<double, double> min_surface_stretch(const LayerProblem& lp) {
  std::vector<int> nodes;
  for (int n : lp.mesh.node_sets.at("solid_fluid"))
    if (lp.mesh.x[n][2] == 0) nodes.push_back(n);
  std::sort(nodes.begin(), nodes.end(),
            [&](int a, int b) { return lp.mesh.x[a][0] < lp.mesh.x[b][0]; });
  const auto d = lp.fsi->displacement();
  std::pair<double, double> worst{std::numeric_limits<double>::infinity(), 0};
  for (size_t i = 1; i < nodes.size(); ++i) {
    const Point &a = lp.mesh.x[nodes[i - 1]], &b = lp.mesh.x[nodes[i]];
    const Point &da = d[nodes[i - 1]], &db = d[nodes[i]];
    const double reference = std::hypot(b[0] - a[0], b[1] - a[1]);
    const double current = std::hypot(b[0] + db[0] - a[0] - da[0], b[1] + db[1] - a[1] - da[1]);
    if (current / reference < worst.first) worst = {current / reference, 0.5 * (a[0] + b[0])};
  }
  return worst;
}

}  // namespace

TEST(FsiSolve, SteadyInterfaceConditionsAndQuadraticNewton) {
  LayerParameters p = resolved_layer();
  p.quasi_static = true;
  LayerProblem lp = make_started_layer(p);
  const NewtonResult r = lp.fsi->solve_steady("steady");
  ASSERT_TRUE(r.converged) << r.reason;
  const auto& h = lp.fsi->stats().last_residuals;
  std::printf("[ measured ] steady layer: %d Newton, %d Krylov; fluid residual:", r.iterations,
              r.krylov_iterations);
  for (const auto& n : h) std::printf(" %.2e", n[1]);
  std::printf("\n");
  // The exact Jacobian (shape derivatives included) and a forcing term that tightens with the
  // residual: measured 4-5 iterations; 8 leaves room for a different BLAS/thread count.
  EXPECT_LE(r.iterations, 8);
  // Quadratic at the end: the last contraction of the fluid residual well below the first.
  ASSERT_GE(h.size(), 3u);
  EXPECT_LT(h[h.size() - 1][1] / h[h.size() - 2][1], 1e-2);
  // The flow drags the layer downstream: a real deformation, not the undeformed state.
  const double dx = max_abs_component(lp.fsi->displacement(), 0);
  EXPECT_GT(dx, 1e-4);
  // The tolerances: rel_tol 1e-10 on each field's residual; what remains of the mismatch is the
  // Newton residual itself, far below 1e-6 of the interface force.
  const double tm = traction_mismatch(lp);
  std::printf("[ measured ] max |d_x| %.3e; traction mismatch %.2e; kinematic mismatch %.2e\n", dx,
              tm, interface_mismatch(lp));
  EXPECT_LT(tm, 1e-6);
  EXPECT_LT(interface_mismatch(lp), 1e-12);
}

// Strong added mass: solid density equal to the fluid's, a light layer in a transient flow
// started impulsively. Partitioned Dirichlet-Neumann iterations diverge in this regime (Causin,
// Gerbeau & Nobile 2005); the monolithic Newton must converge at every step, without step cuts.
TEST(FsiSolve, AddedMassDensityRatioOneConverges) {
  LayerParameters p = resolved_layer();
  p.fluid_density = 1;
  p.solid_density = 1;
  p.youngs_modulus = 5;  // soft enough that the layer moves with the flow it carries
  LayerProblem lp = make_started_layer(p);
  int worst = 0;
  for (int i = 1; i <= 12; ++i) {
    const NewtonResult r = lp.fsi->step(0.05, "step " + std::to_string(i));
    ASSERT_TRUE(r.converged) << "step " << i << ": " << r.reason;
    worst = std::max(worst, r.iterations);
    // Kinematic condition with the structure's one-step-theta velocity, every step.
    ASSERT_LT(interface_mismatch(lp), 1e-9) << "step " << i;
  }
  std::printf("[ measured ] rho_s = rho_f: worst step %d Newton; %d cut steps; max |d_x| %.3e\n",
              worst, lp.fsi->stats().cut_steps, max_abs_component(lp.fsi->displacement(), 0));
  EXPECT_EQ(lp.fsi->stats().cut_steps, 0);
  EXPECT_LE(worst, 8);  // measured 3-7
  EXPECT_GT(max_abs_component(lp.fsi->displacement(), 0), 1e-3);
}

// A very soft Neo-Hooke layer (E two orders below the layer of the first test, about 7 times the
// wall shear stress) sheared by a large fraction of its thickness 0.25: Newton with line search
// must converge and no element may invert. Measured limit: at E = 0.05 (shear strain ~3) the
// outer FGMRES stagnates (400 iterations) from the third Newton step on: the block Gauss-Seidel
// preconditioner leaves out how the structure's motion changes the fluid (through the geometry
// only, in a steady problem), which dominates once the structure is that soft.
TEST(FsiSolve, VerySoftLayerLargeDeformation) {
  LayerParameters p = resolved_layer();
  p.quasi_static = true;
  p.model = NeoHooke;
  p.youngs_modulus = 0.5;
  LayerProblem lp = make_started_layer(p);
  const NewtonResult r = lp.fsi->solve_steady("soft");
  ASSERT_TRUE(r.converged) << r.reason;
  const double dx = max_abs_component(lp.fsi->displacement(), 0);
  const double q = min_scaled_jacobian(lp.fsi->current_mesh());
  std::printf(
      "[ measured ] soft layer: %d Newton, %d Krylov, max |d_x| %.3f (%.0f%% of the "
      "thickness), min scaled Jacobian %.3f\n",
      r.iterations, r.krylov_iterations, dx, 100 * dx / 0.25, q);
  EXPECT_GT(dx, 0.2 * 0.25);
  EXPECT_GT(q, 0.0);
  EXPECT_LT(traction_mismatch(lp), 1e-6);
}

// Softer still, in time: the E = 0.15 layer (about twice the wall shear stress, where the steady
// solve above fails; see the diagnostic at the end of this file) started from rest with a dynamic
// structure. Every step must converge without cuts while the layer is sheared by ~40% of its
// thickness and its surface is compressed past the creasing threshold (stretch < 0.65), the
// large-deformation regime a very soft biofilm reaches; no element may invert on the way.
TEST(FsiSolve, VerySoftLayerConvergesInTime) {
  LayerParameters p = resolved_layer();
  p.model = NeoHooke;
  p.youngs_modulus = 0.15;
  LayerProblem lp = make_started_layer(p);
  int worst = 0;
  double largest = 0;
  for (int i = 1; i <= 30; ++i) {
    const NewtonResult r = lp.fsi->step(0.05, "soft step " + std::to_string(i));
    ASSERT_TRUE(r.converged) << "step " << i << ": " << r.reason;
    worst = std::max(worst, r.iterations);
    largest = std::max(largest, max_abs_component(lp.fsi->displacement(), 0));
    ASSERT_GT(min_scaled_jacobian(lp.fsi->current_mesh()), 0.0) << "step " << i;
  }
  const auto stretch = min_surface_stretch(lp);
  std::printf(
      "[ measured ] E = 0.15 in time: worst step %d Newton, %d cut steps, largest |d_x| %.3f "
      "(%.0f%% of the thickness), surface stretch %.3f, min scaled Jacobian %.3f\n",
      worst, lp.fsi->stats().cut_steps, largest, 100 * largest / 0.25, stretch.first,
      min_scaled_jacobian(lp.fsi->current_mesh()));
  EXPECT_EQ(lp.fsi->stats().cut_steps, 0);
  EXPECT_LE(worst, 8);  // measured 3-4
  EXPECT_GT(largest, 0.35 * 0.25);
  EXPECT_LT(stretch.first, 0.65);
}

// Without the shape derivatives the Jacobian misses the fluid's dependence on the mesh motion:
// on the stiff layer (deformation 0.3% of the thickness) Newton still converges, linearly; the
// test pins that it converges, to the same solution, and costs more iterations. Measured on the
// soft layer of the previous test (E = 0.5, deformation ~30% of the thickness): without them the
// line search fails after 23 iterations with the residual down by only 1e-3, while the exact
// Jacobian converges quadratically. That is why the shape derivatives are the default.
TEST(FsiSolve, InexactNewtonWithoutShapeDerivatives) {
  LayerParameters p = resolved_layer();
  p.quasi_static = true;
  LayerProblem exact = make_started_layer(p);
  const NewtonResult re = exact.fsi->solve_steady("exact");
  p.shape = ShapeDerivatives::None;
  LayerProblem inexact = make_started_layer(p);
  const NewtonResult ri = inexact.fsi->solve_steady("inexact");
  ASSERT_TRUE(re.converged) << re.reason;
  ASSERT_TRUE(ri.converged) << ri.reason;
  std::printf(
      "[ measured ] Newton iterations with shape derivatives %d (%d Krylov), without %d "
      "(%d Krylov)\n",
      re.iterations, re.krylov_iterations, ri.iterations, ri.krylov_iterations);
  EXPECT_GT(ri.iterations, re.iterations);
  // Both solve the same equations: the same displacement to the Newton tolerance.
  const auto de = exact.fsi->displacement(), di = inexact.fsi->displacement();
  double diff = 0;
  for (size_t n = 0; n < de.size(); ++n) diff = std::max(diff, std::abs(de[n][0] - di[n][0]));
  EXPECT_LT(diff, 1e-6 * max_abs_component(de, 0));
}

TEST(FsiSolve, FailedSolveReportsFieldStepAndHistory) {
  LayerParameters p;
  p.max_iterations = 1;  // cannot reach rel_tol 1e-10 in one iteration
  p.max_step_cuts = 1;
  LayerProblem lp = make_started_layer(p);
  const auto d_before = lp.fsi->displacement();
  try {
    lp.fsi->step(0.05, "inner step 7");
    FAIL() << "a one-iteration Newton cannot converge to 1e-10";
  } catch (const SolveError& e) {
    const std::string what = e.what();
    std::printf("[ message ] %s\n", what.c_str());
    EXPECT_NE(what.find("fsi"), std::string::npos);
    EXPECT_NE(what.find("inner step 7"), std::string::npos);
    EXPECT_NE(what.find("structure"), std::string::npos);  // the residual history per field
    EXPECT_NE(what.find("fluid"), std::string::npos);
  }
  // The state is the last valid one.
  const auto d_after = lp.fsi->displacement();
  for (size_t n = 0; n < d_before.size(); ++n) ASSERT_EQ(d_after[n][0], d_before[n][0]);
}

// Diagnostic, not in any suite (run with --gtest_also_run_disabled_tests
// --gtest_filter=*SoftLayerInTime*, 15 s): is there a steady state where the steady solve fails?
// The E = 0.15 layer of VerySoftLayerLargeDeformation in time (dynamic structure, theta 0.66,
// dt 0.05, from rest). Measured: every step converges (3-4 Newton, 16-31 Krylov, no cuts); the
// layer creeps downstream to |d_x| = 0.20 (80% of its thickness) by t = 4.5, compressed against
// its clamped downstream side, and its surface folds there: the solid's top element and the
// fluid's bottom element at x ~ 0.8 degrade together (fluid 0.84 -> 0.31 -> -0.14 scaled
// Jacobian at t = 3.05, 4.05, 4.55; solid 0.45 at 4.55, 0.02 at 5.05) while Newton still
// converges at the quadrature points. A stiffer fluid mesh motion does not help (stiffening
// exponent 0, 1, 2: the same numbers; the layer's fluid cells are uniform, and the one that
// inverts has the interface as its bottom face). What it looks like is a compressed soft layer
// creasing at its free surface, and the surface strain printed each step says so: the surface
// edge at x ~ 0.88 is compressed to a stretch of 0.65 by t ~ 0.9 (the creasing threshold of a
// neo-Hookean half-space in plane strain, Hong, Zhao & Suo 2009), holds near 0.53-0.55 from t =
// 1.2 to 2.2 (Biot's linear surface instability is at 0.544), then falls to 0.25 by t = 4.3 as the
// fold forms. (Both thresholds are for an incompressible half-space; this layer has nu = 0.3, so
// they indicate, not predict.) The compression beyond both thresholds comes 3 s before any cell
// inverts: a mesh resolving the crease is needed, not a stronger coupled solver. Prints the
// history; asserts only that the steps converge.
TEST(FsiSolve, DISABLED_SoftLayerInTimeFoldsAtItsSurface) {
  LayerParameters p = resolved_layer();
  p.model = NeoHooke;
  p.youngs_modulus = 0.15;
  LayerProblem lp = make_started_layer(p);
  for (int i = 1; i <= 100; ++i) {
    const NewtonResult r = lp.fsi->step(0.05, "soft step " + std::to_string(i));
    ASSERT_TRUE(r.converged) << r.reason;
    const Mesh current = lp.fsi->current_mesh();
    const auto q = mesh_quality_by_block(current);
    std::printf("t %.2f: %d Newton, %d Krylov, max |d_x| %.4f, quality", 0.05 * i, r.iterations,
                r.krylov_iterations, max_abs_component(lp.fsi->displacement(), 0));
    for (size_t b = 0; b < q.size(); ++b) {
      Point c{0, 0, 0};  // the worst element's reference centre
      for (int k = 0; k < 8; ++k)
        for (int d = 0; d < 3; ++d) c[d] += lp.mesh.x[lp.mesh.conn[q[b].worst_element][k]][d] / 8;
      std::printf(" %s %.3f at (%.2f, %.2f)", lp.mesh.block_names[b].c_str(), q[b].min, c[0], c[1]);
    }
    const auto stretch = min_surface_stretch(lp);
    std::printf("; surface stretch %.3f at x %.2f\n", stretch.first, stretch.second);
  }
}
