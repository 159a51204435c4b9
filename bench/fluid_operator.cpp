// Cost of the fluid field (kernels/fluid, src/fluid): the matrix-free tangent action of the
// stabilised Navier-Stokes operator (4 unknowns per node) against sparse matrix-vector products
// with its assembled Jacobian (hypre ParCSR and the kernels' Kokkos CSR), and, per preconditioner
// (monolithic systems BoomerAMG, SIMPLE, SIMPLEC), the set-up time and the Krylov iterations per
// Newton step of a steady lid-driven cavity (Re 100, pseudo-2-D) under mesh refinement.
// bench/run_fluid_bench runs it at 1 and 2 threads and writes bench/results/fluid_operator.md.
#include <HYPRE.h>
#include <HYPRE_parcsr_ls.h>
#include <benchmark/benchmark.h>
#include <mpi.h>

#include <Kokkos_Core.hpp>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/bench_support.hpp"
#include "fluid/fluid.hpp"
#include "kernels/fluid/pointwise.hpp"
#include "mesh/mesh.hpp"

namespace biofsi {
namespace {

using bench::HypreCsr;

// Unit cube with n nodes per direction, a transient step (theta 0.66, dt 0.1, Re ~ 100) at a
// smooth 3-D state with every stabilisation term active.
struct Problem {
  int n = 0, n_dofs = 0;
  Mesh mesh;
  DeviceMesh device;
  NodalView aux;
  std::unique_ptr<ElementOperator<FluidPhysics>> op;
  ElementGroups coloured;
  CsrMatrix matrix;
  std::unique_ptr<HypreCsr> hypre;
  Vector u, x, y;

  explicit Problem(int n_) : n(n_) {
    BoxSpec spec;
    spec.nx = spec.nz = n - 1;
    spec.blocks = {{"fluid", 0.0, 1.0, n - 1, 1.0}};
    mesh = make_box_mesh(spec);
    n_dofs = 4 * mesh.n_nodes();
    device = to_device(mesh);
    aux = NodalView(std::string("bench::fluid_aux"), mesh.n_nodes(), FluidPhysics::n_aux);
    auto ah = Kokkos::create_mirror_view(aux);
    std::vector<double> uh(n_dofs);
    for (int i = 0; i < mesh.n_nodes(); ++i) {
      const auto& p = mesh.x[i];
      const double v[4] = {std::sin(3 * p[1]) + 0.2, 0.3 * std::cos(2 * p[0]),
                           0.2 * std::sin(2 * p[2]), p[0] - 0.5};
      for (int c = 0; c < 4; ++c) uh[4 * i + c] = v[c];
      for (int c = 0; c < 3; ++c) ah(i, c) = 0.9 * v[c];
    }
    Kokkos::deep_copy(aux, ah);
    std::vector<int> all(mesh.n_elements());
    for (int e = 0; e < mesh.n_elements(); ++e) all[e] = e;
    coloured = make_element_groups(mesh, all, Scatter::Colored);
    FluidPhysics phys;
    phys.density = 1;
    phys.viscosity = 1e-2;
    phys.inv_dt = 10;
    phys.theta = 0.66;
    op = std::make_unique<ElementOperator<FluidPhysics>>(device.conn, device.x,
                                                         device.element_block, aux, phys);
    u = Vector(std::string("bench::u"), n_dofs);
    auto uhv = Kokkos::create_mirror_view(u);
    for (int i = 0; i < n_dofs; ++i) uhv(i) = uh[i];
    Kokkos::deep_copy(u, uhv);
    x = Vector(std::string("bench::x"), n_dofs);
    y = Vector(std::string("bench::y"), n_dofs);
    Kokkos::deep_copy(x, 1.0);
    matrix = make_sparsity(mesh, all, 4);
    op->assemble(coloured, u, matrix);
    Kokkos::fence();
    hypre = std::make_unique<HypreCsr>(matrix);
  }
};

std::unique_ptr<Problem> current;
Problem& problem(int n) {
  if (!current || current->n != n) {
    current.reset();
    current = std::make_unique<Problem>(n);
  }
  return *current;
}

void set_rate(benchmark::State& state, const Problem& p) {
  state.counters["DoF"] = p.n_dofs;
  state.counters["nnz/row"] = double(p.matrix.nnz()) / p.n_dofs;
  state.counters["MDoF/s"] =
      benchmark::Counter(1e-6 * p.n_dofs * state.iterations(), benchmark::Counter::kIsRate);
}

void apply_matrix_free(benchmark::State& state, int n) {
  Problem& p = problem(n);
  for (auto _ : state) {
    Kokkos::fence();
    Kokkos::deep_copy(p.y, 0.0);  // the tangent accumulates: zeroing is part of an apply
    p.op->apply_tangent(p.coloured, p.u, p.x, p.y);
    Kokkos::fence();
  }
  set_rate(state, p);
}

void apply_hypre_csr(benchmark::State& state, int n) {
  Problem& p = problem(n);
  for (auto _ : state) {
    Kokkos::fence();
    HYPRE_ParCSRMatrixMatvec(1.0, p.hypre->a, p.hypre->x, 0.0, p.hypre->y);
    Kokkos::fence();
  }
  set_rate(state, p);
}

void apply_kokkos_csr(benchmark::State& state, int n) {
  Problem& p = problem(n);
  for (auto _ : state) {
    Kokkos::fence();
    csr_multiply(p.matrix, p.x, p.y);
    Kokkos::fence();
  }
  set_rate(state, p);
}

void assemble(benchmark::State& state, int n) {
  Problem& p = problem(n);
  for (auto _ : state) {
    Kokkos::fence();
    Kokkos::deep_copy(p.matrix.val, 0.0);
    p.op->assemble(p.coloured, p.u, p.matrix);
    Kokkos::fence();
  }
  set_rate(state, p);
}

// Steady lid-driven cavity, Re 100, pseudo-2-D n x n: one full Newton solve per iteration of the
// benchmark; counters per Newton step.
void cavity_solve(benchmark::State& state, int n, FluidPreconditioner pc) {
  current.reset();
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

void register_benchmarks() {
  auto reg = [](benchmark::internal::Benchmark* b) {
    b->UseRealTime()->Unit(benchmark::kMillisecond);
  };
  for (int n : {17, 33}) {
    const std::string s = "/" + std::to_string(n) + "^3";
    auto rep = [&](benchmark::internal::Benchmark* b) {
      reg(b);
      b->Repetitions(5)->ReportAggregatesOnly(true);
    };
    rep(benchmark::RegisterBenchmark(("apply/matrix_free" + s).c_str(), apply_matrix_free, n));
    rep(benchmark::RegisterBenchmark(("apply/hypre_parcsr" + s).c_str(), apply_hypre_csr, n));
    rep(benchmark::RegisterBenchmark(("apply/kokkos_csr" + s).c_str(), apply_kokkos_csr, n));
    reg(benchmark::RegisterBenchmark(("assemble" + s).c_str(), assemble, n));
  }
  const std::pair<const char*, FluidPreconditioner> pcs[] = {
      {"monolithic_amg", FluidPreconditioner::MonolithicAmg},
      {"simple", FluidPreconditioner::Simple},
      {"simplec", FluidPreconditioner::SimpleC}};
  for (int n : {16, 32, 64})
    for (const auto& [name, pc] : pcs)
      reg(benchmark::RegisterBenchmark(
              ("cavity/" + std::string(name) + "/" + std::to_string(n) + "^2").c_str(),
              cavity_solve, n, pc)
              ->Iterations(1));
}

}  // namespace
}  // namespace biofsi

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  Kokkos::initialize(argc, argv);
  int rc = 0;
  {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) {
      rc = 1;
    } else {
      benchmark::AddCustomContext("kokkos_concurrency",
                                  std::to_string(Kokkos::DefaultExecutionSpace().concurrency()));
      biofsi::register_benchmarks();
      benchmark::RunSpecifiedBenchmarks();
      benchmark::Shutdown();
    }
    biofsi::current.reset();
  }
  Kokkos::finalize();
  MPI_Finalize();
  return rc;
}
