// The fluid field's costs beyond the tangent apply (bench_operator has that): the assembly of the
// stabilised Navier-Stokes Jacobian (4 unknowns per node) and, per preconditioner (monolithic
// systems BoomerAMG, SIMPLE, SIMPLEC, sparse LU), the set-up time and the Krylov iterations per
// Newton step of a steady lid-driven cavity (Re 100, pseudo-2-D) under mesh refinement. bench/run
// fluid runs it at 1 and 2 threads and writes bench/results/fluid_operator.md.
//
// The assembled operator: bench/deformed_cube.hpp's fluid_physics and state on the plain cube, a
// transient step (theta 0.66, dt 0.1) with every stabilisation term active.
#include <benchmark/benchmark.h>

#include <Kokkos_Core.hpp>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "bench/bench_main.hpp"
#include "bench/bench_support.hpp"
#include "bench/deformed_cube.hpp"
#include "fluid/fluid.hpp"

namespace biofsi {
namespace bench {
namespace {

OneAtATime current;

void assemble(benchmark::State& state, int n) {
  auto& p =
      current.get<AssembledField<FluidPhysics>>(std::to_string(n), n, fluid_physics(10.0), plain);
  fenced(state, [&] {
    Kokkos::deep_copy(p.matrix.val, 0.0);
    p.op->assemble(p.groups, p.u, p.matrix);
  });
  set_rate_counters(state, p.n_dofs);
  state.counters["nnz/row"] = double(p.matrix.nnz()) / p.n_dofs;
}

// Steady lid-driven cavity, Re 100, pseudo-2-D n x n: one full Newton solve per iteration of the
// benchmark; counters per Newton step.
void cavity_solve(benchmark::State& state, int n, FluidPreconditioner pc) {
  current.release();  // the operator's problem is not needed any more
  BoxSpec spec;
  spec.nx = n;
  spec.nz = 1;
  spec.z1 = 1.0 / n;
  spec.blocks = {{"fluid", 0.0, 1.0, n, 1.0}};
  Mesh mesh = make_box_mesh(spec);
  std::vector<int> pin;
  for (int i = 0; i < mesh.n_nodes(); ++i)
    if (std::abs(mesh.x[i][0] - 0.5) < 1e-12 && mesh.x[i][1] == 0.0) pin.push_back(i);
  mesh.node_sets["pin"] = pin;
  FluidSettings s;
  s.density = 1;
  s.viscosity = 1e-2;
  s.pseudo_2d = true;
  s.preconditioner = pc;
  s.newton_options.rel_tol = 1e-8;
  // Capped so that a preconditioner that stagnates shows as a failed solve within a minute.
  s.newton_options.max_iterations = 10;
  s.newton_options.krylov.max_iterations = 300;
  s.pseudo_transient_steps = 0;
  auto zero = [](const Point&, double) { return 0.0; };
  auto one = [](const Point&, double) { return 1.0; };
  std::vector<FluidBoundaryCondition> bcs = {
      fluid_no_slip("left"), fluid_no_slip("right"), fluid_no_slip("bottom"),
      fluid_velocity("top", one, zero, zero), fluid_pressure("pin", zero)};
  FluidStats stats;
  int newton = 0, krylov = 0;
  for (auto _ : state) {
    FluidField field(mesh, s, bcs);
    field.set_initial(nullptr, nullptr, 0.0);
    try {
      const NewtonResult r = field.solve_steady("cavity");
      newton = r.iterations;
      krylov = r.krylov_iterations;
    } catch (const SolveError& e) {
      state.SkipWithError(e.what());
      return;
    }
    stats = field.stats();
  }
  state.counters["DoF"] = 4 * mesh.n_nodes();
  state.counters["newton"] = newton;
  state.counters["krylov_per_newton"] = double(krylov) / std::max(1, newton);
  state.counters["setup_s_per_newton"] =
      (stats.seconds_assembly + stats.seconds_preconditioner_setup) / std::max(1, newton);
  state.counters["solve_s"] = stats.seconds_solve;
}

}  // namespace

void register_benchmarks(Options&) {
  for (int n : {17, 33})
    add("assemble" + cube_size(n), [n](benchmark::State& s) { assemble(s, n); });
  const std::pair<const char*, FluidPreconditioner> pcs[] = {
      {"monolithic_amg", FluidPreconditioner::MonolithicAmg},
      {"simple", FluidPreconditioner::Simple},
      {"simplec", FluidPreconditioner::SimpleC},
      {"direct", FluidPreconditioner::Direct}};
  for (int n : {16, 32, 64})
    for (const auto& [name, pc] : pcs) {
      const FluidPreconditioner preconditioner = pc;
      const std::string size = "/" + std::to_string(n) + "^2";
      add("cavity/" + std::string(name) + size, [n, preconditioner](benchmark::State& s) {
        cavity_solve(s, n, preconditioner);
      })->Iterations(1);
    }
}

void release_benchmarks() { current.release(); }

}  // namespace bench
}  // namespace biofsi
