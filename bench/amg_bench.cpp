// BoomerAMG set-up and one V-cycle as the fields configure them (BoomerAmg, src/solvers), on the
// matrix assembled on the deformed cube of bench/deformed_cube.hpp (about 1M DoF per field):
//   scalar: transient transport at a long step (diffusion-dominated), scalar AMG as
//     TransportSettings' default;
//   structure: St. Venant-Kirchhoff / Neo-Hooke at a long step (stiffness-dominated), systems AMG
//     with nodal coarsening as StructureAmg::Systems.
// Variants: `setup` is BoomerAmg::setup (the copy into hypre's IJ matrix and BoomerAMGSetup),
// `ij_copy` that copy alone (bench::HypreCsr builds the same IJ matrix), `vcycle` one
// BoomerAmg::apply. hypre's OpenMP regions take omp_get_max_threads() at each call, so one process
// measures every thread count (the benchmark argument `threads`, set with omp_set_num_threads):
// ratios between thread counts come from one run. Kokkos keeps the thread count it started with
// for its own copies around the V-cycle. The context's hypre_openmp says which hypre was linked;
// without OpenMP every thread count runs hypre on one thread. bench/run amg runs it.
//
//   bench_amg [--dofs=N] [--hypre-threads=1,2] [Google Benchmark flags]
//   (N: DoF per field, default 1e6; the thread counts hypre runs at, default 1 and 2)
#include <benchmark/benchmark.h>
#include <omp.h>

#include <Kokkos_Core.hpp>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bench/bench_main.hpp"
#include "bench/bench_support.hpp"
#include "bench/deformed_cube.hpp"
#include "solvers/solvers.hpp"

namespace biofsi {
namespace bench {
namespace {

// A field's matrix with a residual to cycle on, and the hierarchy last set up on it with the
// thread count it was set up at.
template <class Physics>
struct AmgProblem : AssembledField<Physics> {
  std::unique_ptr<BoomerAmg> amg;
  int amg_threads = 0;
  Vector r, z;

  AmgProblem(int n, const Physics& physics) : AssembledField<Physics>(n, physics) {
    r = Vector(std::string("bench::r"), this->n_dofs);
    z = Vector(std::string("bench::z"), this->n_dofs);
    csr_multiply(this->matrix, this->u, r);
    Kokkos::fence();
  }
};

// One field at a time: the structure's matrix and hierarchy take several GB.
OneAtATime current;

// Runs hypre on `threads` threads inside one benchmark and restores the default afterwards.
class ThreadScope {
 public:
  explicit ThreadScope(int threads) : previous_(omp_get_max_threads()) {
    omp_set_num_threads(threads);
  }
  ~ThreadScope() { omp_set_num_threads(previous_); }
  ThreadScope(const ThreadScope&) = delete;
  ThreadScope& operator=(const ThreadScope&) = delete;

 private:
  int previous_;
};

void set_counters(benchmark::State& state, const CsrMatrix& matrix) {
  state.counters["DoF"] = matrix.n_rows;
  state.counters["nnz/row"] = double(matrix.nnz()) / matrix.n_rows;
  state.counters["hypre_threads"] = omp_get_max_threads();
}

template <class Physics>
void register_field(const std::string& field, double dofs, const Physics& physics,
                    const AmgOptions& options, const std::vector<int>& threads) {
  using Problem = AmgProblem<Physics>;
  const int n = nodes_per_direction(dofs, Physics::n_components);
  auto get = [field, n, physics]() -> Problem& {
    return current.get<Problem>(field + std::to_string(n), n, physics);
  };
  auto reg = [&](const std::string& variant, std::function<void(benchmark::State&)> fn) {
    auto* b = add("amg/" + field + "/" + variant + cube_size(n), std::move(fn))->ArgName("threads");
    for (int t : threads) b->Arg(t);
  };
  reg("setup", [get, options](benchmark::State& s) {
    Problem& p = get();
    ThreadScope scope(s.range(0));
    for (auto _ : s) {
      s.PauseTiming();  // freeing the previous hierarchy is not part of a set-up
      p.amg.reset();
      s.ResumeTiming();
      p.amg = std::make_unique<BoomerAmg>(options);
      p.amg->setup(p.matrix);
    }
    p.amg_threads = s.range(0);
    s.counters["levels"] = p.amg->levels();
    set_counters(s, p.matrix);
  });
  reg("ij_copy", [get](benchmark::State& s) {
    Problem& p = get();
    ThreadScope scope(s.range(0));
    for (auto _ : s) HypreCsr copy(p.matrix);
    set_counters(s, p.matrix);
  });
  reg("vcycle", [get, options](benchmark::State& s) {
    Problem& p = get();
    ThreadScope scope(s.range(0));
    // The hierarchy is built at the thread count it is cycled at (hypre's threaded smoothers and
    // coarsening may depend on it); the set-up benchmark leaves one behind.
    if (!p.amg || p.amg_threads != s.range(0)) {
      p.amg = std::make_unique<BoomerAmg>(options);
      p.amg->setup(p.matrix);
      p.amg_threads = s.range(0);
    }
    for (auto _ : s) {
      p.amg->apply(p.r, p.z);
      Kokkos::fence();
    }
    s.counters["levels"] = p.amg->levels();
    set_counters(s, p.matrix);
  });
}

}  // namespace

void register_benchmarks(Options& options) {
  const double dofs = options.positive("dofs", 1e6);
  const std::vector<int> threads = options.positive_list("hypre-threads", {1, 2});
  register_field("scalar", dofs, scalar_physics(), AmgOptions{}, threads);
  // The structure at a long step (dt = 1): stiffness dominates the mass term, so AMG builds a real
  // hierarchy (at bench_operator's dt = 0.01 it stops after 3 levels).
  register_field("structure", dofs, structure_physics(1.0), systems_amg(), threads);
}

void release_benchmarks() { current.release(); }

}  // namespace bench
}  // namespace biofsi
