// The structure field's costs beyond the tangent apply (bench_operator has that): the assembly of
// its tangent (kernels/structure through the element loop, as StructureField binds it), and
// BoomerAMG set-up plus one AMG-preconditioned FGMRES solve for the scalar, systems and systems +
// rigid-body-mode variants. Ratios of variants in one run (bench/run structure) are the claim,
// never absolute timings.
//
// The state is a real one: a dynamic one-step-theta step (theta 0.66), St. Venant-Kirchhoff in the
// lower half of the plain unit cube and Neo-Hooke in the upper, bench/deformed_cube.hpp's
// displacement (strains ~0.1), the bottom clamped (constrained rows and columns eliminated in the
// matrix).
#include <benchmark/benchmark.h>

#include <Kokkos_Core.hpp>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "bench/bench_main.hpp"
#include "bench/bench_support.hpp"
#include "bench/deformed_cube.hpp"
#include "structure/structure.hpp"

namespace biofsi {
namespace bench {
namespace {

struct Problem {
  int n_dofs = 0;
  Mesh mesh;
  std::unique_ptr<StructureField> field;
  Vector u, x;

  explicit Problem(int n) : mesh(deformed_cube(n, plain)) {
    StructureSettings s;
    s.materials = {StructureMaterial::from_young(SaintVenantKirchhoff, 1.0, 0.3, 1.0),
                   StructureMaterial::from_young(NeoHooke, 0.5, 0.45, 1.2)};
    s.theta = 0.66;
    const auto zero = [](const Point&, double) { return 0.0; };
    field = std::make_unique<StructureField>(
        mesh, s, std::vector<StructureDirichlet>{{"bottom", {zero, zero, zero}}});
    std::vector<Point> d(mesh.n_nodes()), v(mesh.n_nodes());
    for (int i = 0; i < mesh.n_nodes(); ++i) {
      d[i] = structure_displacement(mesh.x[i]);
      v[i] = {0.1 * mesh.x[i][1], 0.0, -0.05 * mesh.x[i][1]};
    }
    field->set_state(d, v, 0.0);
    field->prepare_step(0.01);
    n_dofs = field->n_dofs();
    u = Vector(std::string("bench::u"), n_dofs);
    x = Vector(std::string("bench::x"), n_dofs);
    Kokkos::deep_copy(u, 1e-3);
    Kokkos::deep_copy(x, 1.0);
    field->assemble(u, true);
    Kokkos::fence();
  }
};

OneAtATime current;
Problem& problem(int n) { return current.get<Problem>(std::to_string(n), n); }

void assemble(benchmark::State& state, int n) {
  Problem& p = problem(n);
  fenced(state, [&] { p.field->assemble(p.u, true); });
  set_rate_counters(state, p.n_dofs);
  state.counters["nnz/row"] = static_cast<double>(p.field->matrix().nnz()) / p.n_dofs;
  state.counters["csr_bytes/DoF"] = csr_bytes_per_row(p.field->matrix());
}

// 0: scalar AMG; 1: systems AMG; 2: systems AMG with the rigid-body rotations about the centre.
AmgOptions amg_options(int variant, const Mesh& mesh) {
  if (variant == 0) return AmgOptions{};
  AmgOptions o = systems_amg();
  if (variant == 2) {
    const int nn = mesh.n_nodes();
    o.interpolation_vectors.assign(3, std::vector<Real>(3 * nn, 0.0));
    for (int i = 0; i < nn; ++i) {
      const double x = mesh.x[i][0] - 0.5, y = mesh.x[i][1] - 0.5, z = mesh.x[i][2] - 0.5;
      o.interpolation_vectors[0][3 * i] = -y, o.interpolation_vectors[0][3 * i + 1] = x;
      o.interpolation_vectors[1][3 * i + 1] = -z, o.interpolation_vectors[1][3 * i + 2] = y;
      o.interpolation_vectors[2][3 * i] = z, o.interpolation_vectors[2][3 * i + 2] = -x;
    }
  }
  return o;
}

// AMG set-up plus one FGMRES solve to 1e-8 on the matrix-free tangent, as a Newton step does.
void amg_solve(benchmark::State& state, int n, int variant) {
  Problem& p = problem(n);
  BoomerAmg amg(amg_options(variant, p.mesh));
  Vector b(std::string("bench::b"), p.n_dofs), sol(std::string("bench::sol"), p.n_dofs);
  p.field->apply_tangent(p.u, p.x, b);
  const ApplyFn apply = [&p](ConstVector v, Vector w) { p.field->apply_tangent(p.u, v, w); };
  KrylovOptions opt;
  opt.rel_tol = 1e-8;
  opt.restart = 100;
  opt.max_iterations = 2000;
  double setup = 0;
  try {
    timed_fgmres(state, apply, amg, b, sol, opt, [&] {
      amg.setup(p.field->matrix());
      setup += amg.setup_seconds();
    });
  } catch (const std::exception& e) {
    // The rigid-body variant fails in hypre 2.26's set-up on this 3-D cube (bench/README.md).
    state.SkipWithError(e.what());
    return;
  }
  state.counters["DoF"] = p.n_dofs;
  state.counters["levels"] = amg.levels();
  state.counters["setup_s"] = setup / state.iterations();
}

}  // namespace

// Nodes per direction: 15^3 * 3 ~ 1e4 DoF to 89^3 * 3 ~ 2.1e6 DoF; AMG up to 31^3.
void register_benchmarks(Options&) {
  const char* amg_variants[] = {"scalar", "systems", "systems_rbm"};
  for (int n : {15, 31, 63, 89}) {
    const std::string s = cube_size(n);
    add("assemble" + s, [n](benchmark::State& st) { assemble(st, n); })->Iterations(1);
    if (n > 31) continue;
    for (int v = 0; v < 3; ++v)
      add(std::string("amg_fgmres/") + amg_variants[v] + s, [n, v](benchmark::State& st) {
        amg_solve(st, n, v);
      })->Iterations(1);
  }
}

void release_benchmarks() { current.release(); }

}  // namespace bench
}  // namespace biofsi
