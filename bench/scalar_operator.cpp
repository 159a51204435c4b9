// Throughput of the scalar transport operator: the matrix-free tangent action (coloured and atomic
// scatter) against sparse matrix-vector products of the assembled matrix of the same operator
// (hypre's ParCSR matvec, and the kernels' own threaded Kokkos CSR product), plus the cost of
// BoomerAMG set-up and of one AMG-preconditioned FGMRES solve. Results are compared as ratios of
// variants measured in one run (bench/run_scalar_bench), never as absolute timings.
//
// The operator is the real one: transient one-step-theta (theta 0.66), convection everywhere with
// SUPG, per-block diffusivity, Monod consumption in the upper (biofilm) block.
#include <HYPRE.h>
#include <HYPRE_parcsr_ls.h>
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/bench_support.hpp"
#include "kernels/core/csr.hpp"
#include "kernels/core/element_loop.hpp"
#include "kernels/scalar/pointwise.hpp"
#include "mesh/mesh.hpp"
#include "solvers/solvers.hpp"

namespace biofsi {
namespace {

using bench::HypreCsr;

// inv_dt = 1: a long time step where diffusion and convection dominate the matrix (mass/diffusion
// ~ h^2/D <= 0.03 here), so AMG has real work; inv_dt = 100 gives the mass-dominated matrix of a
// short step, on which BoomerAMG finds no strong connections and stays on one level.
TransportPhysics bench_physics(double inv_dt) {
  TransportPhysics p;
  p.coef.diffusivity[0] = 1e-2;  // fluid
  p.coef.diffusivity[1] = 5e-3;  // biofilm
  p.coef.monod_rate[1] = 1.0;
  p.coef.monod_half_saturation[1] = 0.1;
  p.inv_dt = inv_dt;
  p.theta = 0.66;
  p.supg = true;
  return p;
}

// One box mesh with n nodes per direction and everything the variants need, built once per size:
// unit cube, fluid block below y = 1/2 and biofilm above, a shear flow with cross components.
struct Problem {
  int n_dofs = 0;
  double inv_dt = 0;
  Mesh mesh;
  DeviceMesh device;
  NodalView aux;
  std::unique_ptr<ElementOperator<TransportPhysics>> op;
  ElementGroups coloured, atomic;
  CsrMatrix matrix;
  std::unique_ptr<HypreCsr> hypre;
  Vector u, x, y;

  Problem(int n, double inv_dt_) : inv_dt(inv_dt_) {
    const int cells = n - 1;
    BoxSpec spec;
    spec.nx = spec.nz = cells;
    spec.blocks = {{"fluid", 0.0, 0.5, cells / 2, 1.0},
                   {"biofilm", 0.5, 1.0, cells - cells / 2, 1.0}};
    mesh = make_box_mesh(spec);
    n_dofs = mesh.n_nodes();
    device = to_device(mesh);
    aux = NodalView(std::string("bench::aux"), n_dofs, TransportPhysics::n_aux);
    auto ah = Kokkos::create_mirror_view(aux);
    for (int i = 0; i < n_dofs; ++i) {
      const auto& p = mesh.x[i];
      ah(i, 0) = 0.5 + 0.25 * std::sin(3 * p[0]) * std::cos(2 * p[1]);
      ah(i, 4) = p[1];
      ah(i, 5) = 0.1 * std::sin(4 * p[0]);
      ah(i, 6) = 0.2 * std::cos(3 * p[2]);
    }
    Kokkos::deep_copy(aux, ah);
    std::vector<int> all(mesh.n_elements());
    for (int e = 0; e < mesh.n_elements(); ++e) all[e] = e;
    coloured = make_element_groups(mesh, all, Scatter::Colored);
    atomic = make_element_groups(mesh, all, Scatter::Atomic);
    op = std::make_unique<ElementOperator<TransportPhysics>>(
        device.conn, device.x, device.element_block, aux, bench_physics(inv_dt));
    u = Vector(std::string("bench::u"), n_dofs);
    x = Vector(std::string("bench::x"), n_dofs);
    y = Vector(std::string("bench::y"), n_dofs);
    Kokkos::deep_copy(u, 0.4);
    Kokkos::deep_copy(x, 1.0);
    matrix = make_sparsity(mesh, all, 1);
    op->assemble(coloured, u, matrix);
    Kokkos::fence();
    hypre = std::make_unique<HypreCsr>(matrix);
  }
};

// One problem at a time: benchmarks are registered size by size, so each is built once and the
// largest never shares memory with another.
std::unique_ptr<Problem> current;
Problem& problem(int n, double inv_dt = 1.0) {
  if (!current || current->n_dofs != n * n * n || current->inv_dt != inv_dt) {
    current.reset();
    current = std::make_unique<Problem>(n, inv_dt);
  }
  return *current;
}

// Per-DoF costs (bench/README.md derives them). CSR: 8-byte value and 4-byte column per nonzero,
// the row pointer, x and y once; 2 flops per nonzero. Matrix-free: compulsory traffic only
// (connectivity and block id per element; coordinates, 4 aux fields, u, du, and y read and written
// per node) and 7720 flops per element, counted by running the tangent kernel with Real replaced by
// an operation-counting type (plus 32 sqrt/tanh, not counted).
constexpr double mf_bytes_per_element = 8 * 4 + 4,
                 mf_bytes_per_node = 3 * 8 + 4 * 8 + 8 + 8 + 2 * 8;
constexpr double mf_flops_per_element = 7720;

double mf_bytes_per_dof(const Problem& p) {
  return mf_bytes_per_node + mf_bytes_per_element * p.mesh.n_elements() / p.n_dofs;
}
double mf_flops_per_dof(const Problem& p) {
  return mf_flops_per_element * p.mesh.n_elements() / p.n_dofs;
}

void set_counters(benchmark::State& state, const Problem& p, double bytes, double flops) {
  state.counters["DoF"] = p.n_dofs;
  state.counters["MDoF/s"] =
      benchmark::Counter(1e-6 * p.n_dofs * state.iterations(), benchmark::Counter::kIsRate);
  state.counters["bytes/DoF"] = bytes;
  state.counters["flops/DoF"] = flops;
}

double csr_bytes_per_dof(const Problem& p) {
  return (12.0 * p.matrix.nnz() + 4.0 * (p.n_dofs + 1)) / p.n_dofs + 16;
}
double csr_flops_per_dof(const Problem& p) { return 2.0 * p.matrix.nnz() / p.n_dofs; }

void apply_matrix_free(benchmark::State& state, int n, Scatter scatter) {
  Problem& p = problem(n);
  const ElementGroups& groups = scatter == Scatter::Colored ? p.coloured : p.atomic;
  for (auto _ : state) {
    Kokkos::fence();
    // The tangent accumulates, so a Krylov apply zeroes first: part of the operator's cost.
    Kokkos::deep_copy(p.y, 0.0);
    p.op->apply_tangent(groups, p.u, p.x, p.y);
    Kokkos::fence();
  }
  set_counters(state, p, mf_bytes_per_dof(p), mf_flops_per_dof(p));
}

void apply_hypre_csr(benchmark::State& state, int n) {
  Problem& p = problem(n);
  for (auto _ : state) {
    Kokkos::fence();
    HYPRE_ParCSRMatrixMatvec(1.0, p.hypre->a, p.hypre->x, 0.0, p.hypre->y);
    Kokkos::fence();
  }
  set_counters(state, p, csr_bytes_per_dof(p), csr_flops_per_dof(p));
}

void apply_kokkos_csr(benchmark::State& state, int n) {
  Problem& p = problem(n);
  for (auto _ : state) {
    Kokkos::fence();
    csr_multiply(p.matrix, p.x, p.y);
    Kokkos::fence();
  }
  set_counters(state, p, csr_bytes_per_dof(p), csr_flops_per_dof(p));
}

// Assembly of the same operator into the fixed pattern (what a CSR tangent costs to refresh).
void assemble_csr(benchmark::State& state, int n, Scatter scatter) {
  Problem& p = problem(n);
  const ElementGroups& groups = scatter == Scatter::Colored ? p.coloured : p.atomic;
  for (auto _ : state) {
    Kokkos::fence();
    Kokkos::deep_copy(p.matrix.val, 0.0);
    p.op->assemble(groups, p.u, p.matrix);
    Kokkos::fence();
  }
  state.counters["DoF"] = p.n_dofs;
  state.counters["MDoF/s"] =
      benchmark::Counter(1e-6 * p.n_dofs * state.iterations(), benchmark::Counter::kIsRate);
}

void amg_setup(benchmark::State& state, int n, double inv_dt) {
  Problem& p = problem(n, inv_dt);
  BoomerAmg amg;
  for (auto _ : state) {
    Kokkos::fence();
    amg.setup(p.matrix);
    Kokkos::fence();
  }
  state.counters["DoF"] = p.n_dofs;
  state.counters["levels"] = amg.levels();
  state.counters["MDoF/s"] =
      benchmark::Counter(1e-6 * p.n_dofs * state.iterations(), benchmark::Counter::kIsRate);
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
        p.op->apply_tangent(p.coloured, p.u, v, w);
      })
                  : ApplyFn([&p](ConstVector v, Vector w) { csr_multiply(p.matrix, v, w); });
  Vector b(std::string("bench::b"), p.n_dofs), sol(std::string("bench::sol"), p.n_dofs);
  apply(p.x, b);  // the exact solution is x = 1
  KrylovOptions opt;
  opt.rel_tol = 1e-8;
  opt.restart = 50;
  KrylovResult res;
  for (auto _ : state) {
    Kokkos::fence();
    Kokkos::deep_copy(sol, 0.0);
    res = fgmres(apply, amg.as_function(), b, sol, opt);
    Kokkos::fence();
  }
  if (!res.converged) state.SkipWithError(("FGMRES did not converge: " + res.reason).c_str());
  state.counters["DoF"] = p.n_dofs;
  state.counters["iterations"] = res.iterations;
  state.counters["MDoF/s"] =
      benchmark::Counter(1e-6 * p.n_dofs * state.iterations(), benchmark::Counter::kIsRate);
}

}  // namespace

// Sizes in nodes per direction: 21^3 ~ 9e3 to 127^3 ~ 2.05e6 DoF; AMG on the smaller ones.
void register_scalar_operator_benchmarks() {
  const int sizes[] = {21, 41, 81, 127};
  for (int n : sizes) {
    const std::string s = "/" + std::to_string(n) + "^3";
    auto reg = [](benchmark::internal::Benchmark* b) {
      b->UseRealTime()->Unit(benchmark::kMillisecond);
    };
    // Applies are cheap: the median of 5 repetitions damps other work on a shared machine.
    auto reg_apply = [&](benchmark::internal::Benchmark* b) {
      reg(b);
      b->Repetitions(5)->ReportAggregatesOnly(true);
    };
    reg_apply(benchmark::RegisterBenchmark(("apply/matrix_free_coloured" + s).c_str(),
                                           apply_matrix_free, n, Scatter::Colored));
    reg_apply(benchmark::RegisterBenchmark(("apply/matrix_free_atomic" + s).c_str(),
                                           apply_matrix_free, n, Scatter::Atomic));
    reg_apply(benchmark::RegisterBenchmark(("apply/hypre_parcsr" + s).c_str(), apply_hypre_csr, n));
    reg_apply(benchmark::RegisterBenchmark(("apply/kokkos_csr" + s).c_str(), apply_kokkos_csr, n));
    reg(benchmark::RegisterBenchmark(("assemble/coloured" + s).c_str(), assemble_csr, n,
                                     Scatter::Colored));
    reg(benchmark::RegisterBenchmark(("assemble/atomic" + s).c_str(), assemble_csr, n,
                                     Scatter::Atomic));
    if (n > 81) continue;
    for (double inv_dt : {1.0, 100.0}) {
      const std::string t = s + (inv_dt == 1.0 ? "/inv_dt:1" : "/inv_dt:100");
      reg(benchmark::RegisterBenchmark(("amg/setup" + t).c_str(), amg_setup, n, inv_dt));
      reg(benchmark::RegisterBenchmark(("amg/fgmres_matrix_free" + t).c_str(), amg_fgmres_solve, n,
                                       inv_dt, true));
      reg(benchmark::RegisterBenchmark(("amg/fgmres_csr" + t).c_str(), amg_fgmres_solve, n, inv_dt,
                                       false));
    }
  }
}

void release_scalar_operator_benchmarks() { current.reset(); }

}  // namespace biofsi
