// Tangent-apply throughput of every field's operator on one deformed mesh, in one run: the
// on-the-fly matrix-free apply, the stored tangent (kernels/core/stored_tangent.hpp: what the
// fields use, the fluid's as point states, and for the fluid also the full stored map) in SIMD
// batches and with one element per batch, its linearisation, and the CSR matvec of the assembled
// matrix of the same operator (hypre ParCSR and the kernels' Kokkos CSR). bench/run_operator_bench
// runs it at 1 and 2 threads and prints the ratios; absolute rates depend on the machine's load.
// Mesh and states: bench/deformed_cube.hpp.
//
//   bench_operator [--dofs=N] [Google Benchmark flags]   (N: target DoF per field, default 1e6)
#include <benchmark/benchmark.h>
#include <mpi.h>

#include <Kokkos_Core.hpp>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "bench/bench_support.hpp"
#include "bench/deformed_cube.hpp"
#include "kernels/core/stored_tangent.hpp"

namespace biofsi {
namespace {

// One field's operator on the deformed cube, with everything each variant needs.
template <class Physics>
struct FieldProblem : bench::AssembledField<Physics> {
  std::unique_ptr<bench::HypreCsr> hypre;
  FieldStoreOf<Physics> packed;  // what the fields use
  FieldStoreOf<Physics, 1> single;
  StoredTangentOf<Physics> full_map;  // the map itself, where the fields store point states
  Vector x, y;

  FieldProblem(int n, const Physics& physics) : bench::AssembledField<Physics>(n, physics) {
    x = bench::nodal_vector(
        this->mesh, this->NC,
        [](int c, const Point& p) { return std::sin(3 * p[0] - p[1] + c) + 0.2 * p[2]; },
        "bench::x");
    y = Vector(std::string("bench::y"), this->n_dofs);
    hypre = std::make_unique<bench::HypreCsr>(this->matrix);
    linearise(*this->op, this->groups, this->u, packed);
    linearise(*this->op, this->groups, this->u, single);
    if (std::is_same<FieldStoreOf<Physics>, StoredPointStates<Physics>>::value)
      linearise(*this->op, this->groups, this->u, full_map);
    Kokkos::fence();
  }
};

// One problem alive at a time (the largest are several GB).
std::shared_ptr<void> current;
std::string current_key;
template <class Physics>
FieldProblem<Physics>& problem(const std::string& field, int n, const Physics& physics) {
  const std::string key = field + std::to_string(n);
  if (key != current_key) {
    current.reset();
    current = std::make_shared<FieldProblem<Physics>>(n, physics);
    current_key = key;
  }
  return *static_cast<FieldProblem<Physics>*>(current.get());
}

template <class P>
void timed(benchmark::State& state, const P& p, const std::function<void()>& body) {
  for (auto _ : state) {
    Kokkos::fence();
    body();
    Kokkos::fence();
  }
  bench::set_rate_counters(state, p.n_dofs);
}

template <class Physics>
void register_field(const std::string& field, double dofs, const Physics& physics) {
  using Problem = FieldProblem<Physics>;
  const int n = bench::nodes_per_direction(dofs, Physics::n_components);
  const std::string suffix = "/" + std::to_string(n) + "^3";
  auto get = [field, n, physics]() -> Problem& { return problem(field, n, physics); };
  auto reg = [&](const std::string& variant, std::function<void(benchmark::State&)> fn) {
    benchmark::RegisterBenchmark((field + "/" + variant + suffix).c_str(), fn)
        ->UseRealTime()
        ->Unit(benchmark::kMillisecond)
        ->Repetitions(3)
        ->ReportAggregatesOnly(true);
  };
  // The tangent accumulates, so a Krylov apply zeroes first: part of every matrix-free variant.
  reg("on_the_fly", [get](benchmark::State& s) {
    Problem& p = get();
    timed(s, p, [&] {
      Kokkos::deep_copy(p.y, 0.0);
      p.op->apply_tangent(p.groups, p.u, p.x, p.y);
    });
  });
  reg("stored", [get](benchmark::State& s) {
    Problem& p = get();
    timed(s, p, [&] {
      Kokkos::deep_copy(p.y, 0.0);
      apply_stored(p.packed, p.x, p.y);
    });
    s.counters["bytes/DoF"] = double(p.packed.bytes()) / p.n_dofs + 24;
  });
  reg("stored_one_lane", [get](benchmark::State& s) {
    Problem& p = get();
    timed(s, p, [&] {
      Kokkos::deep_copy(p.y, 0.0);
      apply_stored(p.single, p.x, p.y);
    });
  });
  if (std::is_same<FieldStoreOf<Physics>, StoredPointStates<Physics>>::value)
    reg("stored_full_map", [get](benchmark::State& s) {
      Problem& p = get();
      timed(s, p, [&] {
        Kokkos::deep_copy(p.y, 0.0);
        apply_stored(p.full_map, p.x, p.y);
      });
      s.counters["bytes/DoF"] = double(p.full_map.bytes()) / p.n_dofs + 24;
    });
  reg("linearise", [get](benchmark::State& s) {
    Problem& p = get();
    timed(s, p, [&] { linearise(*p.op, p.groups, p.u, p.packed); });
  });
  reg("hypre_parcsr", [get](benchmark::State& s) {
    Problem& p = get();
    timed(s, p, [&] { HYPRE_ParCSRMatrixMatvec(1.0, p.hypre->a, p.hypre->x, 0.0, p.hypre->y); });
    s.counters["bytes/DoF"] = bench::csr_bytes_per_row(p.matrix);
  });
  reg("kokkos_csr", [get](benchmark::State& s) {
    Problem& p = get();
    timed(s, p, [&] { csr_multiply(p.matrix, p.x, p.y); });
  });
}

}  // namespace
}  // namespace biofsi

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  Kokkos::initialize(argc, argv);
  int rc = 0;
  {
    double dofs = 1e6;
    std::vector<char*> args;
    for (int i = 0; i < argc; ++i) {
      if (std::strncmp(argv[i], "--dofs=", 7) == 0)
        dofs = std::atof(argv[i] + 7);
      else
        args.push_back(argv[i]);
    }
    int n_args = static_cast<int>(args.size());
    benchmark::Initialize(&n_args, args.data());
    if (benchmark::ReportUnrecognizedArguments(n_args, args.data()) || !(dofs > 0)) {
      rc = 2;
    } else {
      benchmark::AddCustomContext("kokkos_concurrency",
                                  std::to_string(Kokkos::DefaultExecutionSpace().concurrency()));
      benchmark::AddCustomContext("simd_width", std::to_string(biofsi::simd_width));
      using namespace biofsi;
      using namespace biofsi::bench;
      register_field("scalar", dofs, scalar_physics());
      register_field("structure", dofs, structure_physics());
      register_field("fluid", dofs, fluid_physics());
      const Mesh probe = deformed_cube(nodes_per_direction(dofs, 3));
      register_field("mesh_motion", dofs, mesh_motion_physics(probe));
      benchmark::RunSpecifiedBenchmarks();
      benchmark::Shutdown();
    }
    biofsi::current.reset();  // hypre objects and Views before MPI and Kokkos are torn down
  }
  Kokkos::finalize();
  MPI_Finalize();
  return rc;
}
