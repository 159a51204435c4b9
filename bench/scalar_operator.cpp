// The scalar transport operator's scatter policies and its AMG-preconditioned solve: the on-the-fly
// matrix-free tangent apply and the assembly into the CSR pattern with coloured against atomic
// scatter, BoomerAMG set-up, and one AMG-preconditioned FGMRES solve with the matrix-free tangent
// against the same solve with the assembled matrix. Results are compared as ratios of variants
// measured in one run (bench/run scalar), never as absolute timings; bench_operator has the
// apply against CSR.
//
// The operator is the real one (bench/deformed_cube.hpp's scalar_physics on the plain cube, at the
// constant state 0.4): transient one-step-theta (theta 0.66), convection everywhere with SUPG,
// per-block diffusivity, Monod consumption in the upper (biofilm) block.
#include <benchmark/benchmark.h>

#include <Kokkos_Core.hpp>
#include <string>
#include <utility>

#include "bench/bench_main.hpp"
#include "bench/bench_support.hpp"
#include "bench/deformed_cube.hpp"
#include "solvers/solvers.hpp"

namespace biofsi {
namespace bench {
namespace {

// The operator on the plain cube with both scatter policies, x = 1 and y to apply into. inv_dt = 1:
// a long time step where diffusion and convection dominate the matrix (mass/diffusion ~ h^2/D <=
// 0.03 here), so AMG has real work; inv_dt = 100 gives the mass-dominated matrix of a short step,
// on which BoomerAMG finds no strong connections and stays on one level.
struct Problem : AssembledField<TransportPhysics> {
  ElementGroups atomic;
  Vector x, y;

  Problem(int n, double inv_dt)
      : AssembledField(n, scalar_physics(inv_dt), plain, [](int, const Point&) { return 0.4; }) {
    atomic = make_element_groups(mesh, all_elements(mesh), Scatter::Atomic);
    x = Vector(std::string("bench::x"), n_dofs);
    y = Vector(std::string("bench::y"), n_dofs);
    Kokkos::deep_copy(x, 1.0);
  }
  const ElementGroups& scattered(Scatter scatter) const {
    return scatter == Scatter::Colored ? groups : atomic;
  }
};

OneAtATime current;
Problem& problem(int n, double inv_dt = 1.0) {
  return current.get<Problem>(std::to_string(n) + "/" + std::to_string(inv_dt), n, inv_dt);
}

// Per-DoF costs of the matrix-free apply (bench/README.md derives them): compulsory traffic only
// (connectivity and block id per element; coordinates, 4 aux fields, u, du, and y read and written
// per node) and 7720 flops per element, counted by running the tangent kernel with Real replaced by
// an operation-counting type (plus 32 sqrt/tanh, not counted).
constexpr double mf_bytes_per_element = 8 * 4 + 4,
                 mf_bytes_per_node = 3 * 8 + 4 * 8 + 8 + 8 + 2 * 8;
constexpr double mf_flops_per_element = 7720;

void apply_matrix_free(benchmark::State& state, int n, Scatter scatter) {
  Problem& p = problem(n);
  fenced(state, [&] {
    // The tangent accumulates, so a Krylov apply zeroes first: part of the operator's cost.
    Kokkos::deep_copy(p.y, 0.0);
    p.op->apply_tangent(p.scattered(scatter), p.u, p.x, p.y);
  });
  set_rate_counters(state, p.n_dofs);
  const double elements_per_dof = double(p.mesh.n_elements()) / p.n_dofs;
  state.counters["bytes/DoF"] = mf_bytes_per_node + mf_bytes_per_element * elements_per_dof;
  state.counters["flops/DoF"] = mf_flops_per_element * elements_per_dof;
}

// Assembly of the same operator into the fixed pattern (what a CSR tangent costs to refresh).
void assemble_csr(benchmark::State& state, int n, Scatter scatter) {
  Problem& p = problem(n);
  fenced(state, [&] {
    Kokkos::deep_copy(p.matrix.val, 0.0);
    p.op->assemble(p.scattered(scatter), p.u, p.matrix);
  });
  set_rate_counters(state, p.n_dofs);
}

void amg_setup(benchmark::State& state, int n, double inv_dt) {
  Problem& p = problem(n, inv_dt);
  BoomerAmg amg;
  fenced(state, [&] { amg.setup(p.matrix); });
  set_rate_counters(state, p.n_dofs);
  state.counters["levels"] = amg.levels();
}

// What a Newton step does: FGMRES on the matrix-free tangent (or, for comparison, on the assembled
// matrix), preconditioned by one BoomerAMG V-cycle on the assembled matrix, to 1e-8 relative.
void amg_fgmres_solve(benchmark::State& state, int n, double inv_dt, bool matrix_free) {
  Problem& p = problem(n, inv_dt);
  BoomerAmg amg;
  amg.setup(p.matrix);
  const ApplyFn apply =
      matrix_free ? ApplyFn([&p](ConstVector v, Vector w) {
        Kokkos::deep_copy(w, 0.0);
        p.op->apply_tangent(p.groups, p.u, v, w);
      })
                  : ApplyFn([&p](ConstVector v, Vector w) { csr_multiply(p.matrix, v, w); });
  Vector b(std::string("bench::b"), p.n_dofs), sol(std::string("bench::sol"), p.n_dofs);
  apply(p.x, b);  // the exact solution is x = 1
  KrylovOptions opt;
  opt.rel_tol = 1e-8;
  opt.restart = 50;
  timed_fgmres(state, apply, amg, b, sol, opt);
  set_rate_counters(state, p.n_dofs);
}

}  // namespace

// Sizes in nodes per direction: 21^3 ~ 9e3 to 127^3 ~ 2.05e6 DoF; AMG on the smaller ones.
void register_benchmarks(Options&) {
  const std::pair<const char*, Scatter> scatters[] = {{"coloured", Scatter::Colored},
                                                      {"atomic", Scatter::Atomic}};
  for (int n : {21, 41, 81, 127}) {
    const std::string s = cube_size(n);
    for (auto [name, scatter] : scatters)
      repeated(add(std::string("apply/matrix_free_") + name + s,
                   [=](benchmark::State& st) { apply_matrix_free(st, n, scatter); }),
               5);
    for (auto [name, scatter] : scatters)
      add(std::string("assemble/") + name + s,
          [=](benchmark::State& st) { assemble_csr(st, n, scatter); });
    if (n > 81) continue;
    for (double inv_dt : {1.0, 100.0}) {
      const std::string t = s + (inv_dt == 1.0 ? "/inv_dt:1" : "/inv_dt:100");
      add("amg/setup" + t, [=](benchmark::State& st) { amg_setup(st, n, inv_dt); });
      add("amg/fgmres_matrix_free" + t,
          [=](benchmark::State& st) { amg_fgmres_solve(st, n, inv_dt, true); });
      add("amg/fgmres_csr" + t,
          [=](benchmark::State& st) { amg_fgmres_solve(st, n, inv_dt, false); });
    }
  }
}

void release_benchmarks() { current.release(); }

}  // namespace bench
}  // namespace biofsi
