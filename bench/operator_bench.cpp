// Tangent-apply throughput of every field's operator on one deformed mesh, in one run: the
// on-the-fly matrix-free apply, the stored tangent (kernels/core/stored_tangent.hpp: what the
// fields use, the fluid's as point states, and for the fluid also the full stored map) in SIMD
// batches and with one element per batch, its linearisation, and the CSR matvec of the assembled
// matrix of the same operator (hypre ParCSR and the kernels' Kokkos CSR). bench/run operator runs
// it at 1 and 2 threads and prints the ratios; absolute rates depend on the machine's load.
// Mesh and states: bench/deformed_cube.hpp.
//
//   bench_operator [--dofs=N] [Google Benchmark flags]   (N: target DoF per field, default 1e6)
#include <benchmark/benchmark.h>

#include <Kokkos_Core.hpp>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <type_traits>

#include "bench/bench_main.hpp"
#include "bench/bench_support.hpp"
#include "bench/deformed_cube.hpp"
#include "kernels/core/stored_tangent.hpp"

namespace biofsi {
namespace bench {
namespace {

// Whether the fields store point states for this Physics (the fluid), not the map itself.
template <class Physics>
constexpr bool stores_point_states =
    std::is_same<FieldStoreOf<Physics>, StoredPointStates<Physics>>::value;

// One field's operator on the deformed cube, with everything each variant needs.
template <class Physics>
struct FieldProblem : AssembledField<Physics> {
  std::unique_ptr<HypreCsr> hypre;
  FieldStoreOf<Physics> packed;  // what the fields use
  FieldStoreOf<Physics, 1> single;
  StoredTangentOf<Physics> full_map;  // the map itself, where the fields store point states
  Vector x, y;

  FieldProblem(int n, const Physics& physics) : AssembledField<Physics>(n, physics) {
    x = nodal_vector(
        this->mesh, this->NC,
        [](int c, const Point& p) { return std::sin(3 * p[0] - p[1] + c) + 0.2 * p[2]; },
        "bench::x");
    y = Vector(std::string("bench::y"), this->n_dofs);
    hypre = std::make_unique<HypreCsr>(this->matrix);
    linearise(*this->op, this->groups, this->u, packed);
    linearise(*this->op, this->groups, this->u, single);
    if (stores_point_states<Physics>) linearise(*this->op, this->groups, this->u, full_map);
    Kokkos::fence();
  }
};

OneAtATime current;

template <class Physics>
void register_field(const std::string& field, double dofs, const Physics& physics) {
  using Problem = FieldProblem<Physics>;
  const int n = nodes_per_direction(dofs, Physics::n_components);
  auto get = [field, n, physics]() -> Problem& {
    return current.get<Problem>(field + std::to_string(n), n, physics);
  };
  // A variant times body(p) and reports MDoF/s, then what report(p, state) adds.
  using Report = std::function<void(const Problem&, benchmark::State&)>;
  auto reg = [&](const std::string& variant, auto body, Report report = {}) {
    repeated(add(field + "/" + variant + cube_size(n),
                 [get, body, report](benchmark::State& s) {
                   Problem& p = get();
                   fenced(s, [&] { body(p); });
                   set_rate_counters(s, p.n_dofs);
                   if (report) report(p, s);
                 }),
             3);
  };
  // The tangent accumulates, so a Krylov apply zeroes first: part of every matrix-free variant.
  reg("on_the_fly", [](Problem& p) {
    Kokkos::deep_copy(p.y, 0.0);
    p.op->apply_tangent(p.groups, p.u, p.x, p.y);
  });
  // A store's apply; with `bytes`, its bytes per DoF (with x, y and the node ids) reported.
  auto stored = [&](const std::string& variant, auto member, bool bytes) {
    const auto apply = [member](Problem& p) {
      Kokkos::deep_copy(p.y, 0.0);
      apply_stored(p.*member, p.x, p.y);
    };
    const auto report = [member](const Problem& p, benchmark::State& s) {
      s.counters["bytes/DoF"] = double((p.*member).bytes()) / p.n_dofs + 24;
    };
    reg(variant, apply, bytes ? Report(report) : Report());
  };
  stored("stored", &Problem::packed, true);
  stored("stored_one_lane", &Problem::single, false);
  if (stores_point_states<Physics>) stored("stored_full_map", &Problem::full_map, true);
  reg("linearise", [](Problem& p) { linearise(*p.op, p.groups, p.u, p.packed); });
  reg(
      "hypre_parcsr",
      [](Problem& p) { HYPRE_ParCSRMatrixMatvec(1.0, p.hypre->a, p.hypre->x, 0.0, p.hypre->y); },
      [](const Problem& p, benchmark::State& s) {
        s.counters["bytes/DoF"] = csr_bytes_per_row(p.matrix);
      });
  reg("kokkos_csr", [](Problem& p) { csr_multiply(p.matrix, p.x, p.y); });
}

}  // namespace

void register_benchmarks(Options& options) {
  const double dofs = options.positive("dofs", 1e6);
  register_field("scalar", dofs, scalar_physics());
  register_field("structure", dofs, structure_physics());
  register_field("fluid", dofs, fluid_physics());
  register_field("mesh_motion", dofs,
                 mesh_motion_physics(deformed_cube(nodes_per_direction(dofs, 3))));
}

void release_benchmarks() { current.release(); }

}  // namespace bench
}  // namespace biofsi
