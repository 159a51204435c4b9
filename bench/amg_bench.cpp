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
// without OpenMP every thread count runs hypre on one thread. bench/run_amg_bench runs it.
//
//   bench_amg [--dofs=N] [--hypre-threads=1,2] [Google Benchmark flags]
//   (N: DoF per field, default 1e6; the thread counts hypre runs at, default 1 and 2)
#include <HYPRE_config.h>
#include <benchmark/benchmark.h>
#include <mpi.h>
#include <omp.h>

#include <Kokkos_Core.hpp>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_support.hpp"
#include "bench/deformed_cube.hpp"
#include "biofsi_version.hpp"
#include "solvers/solvers.hpp"

namespace biofsi {
namespace {

// The structure's operator at a long step (dt = 1): stiffness dominates the mass term, so AMG
// builds a real hierarchy (at operator_bench's dt = 0.01 it stops after 3 levels).
StructurePhysics elasticity_physics() {
  StructurePhysics p = bench::structure_physics();
  p.dt = 1.0;
  p.mass_coefficient = 1.0 / (p.theta * p.dt * p.dt);
  return p;
}

AmgOptions systems_amg() {
  AmgOptions o;
  o.num_functions = 3;
  o.nodal_coarsening = true;
  return o;
}

// The field alive now (one at a time: the structure's matrix and hierarchy take several GB) and
// the hierarchy last set up on it, with the thread count it was set up at.
struct Current {
  std::string key;
  std::shared_ptr<void> field;
  const CsrMatrix* matrix = nullptr;
  std::unique_ptr<BoomerAmg> amg;
  int amg_threads = 0;
  Vector r, z;
};
Current current;

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

template <class Physics>
void make_current(const std::string& field, int n, const Physics& physics) {
  const std::string key = field + std::to_string(n);
  if (key == current.key) return;
  current = Current{};
  auto f = std::make_shared<bench::AssembledField<Physics>>(n, physics);
  current.matrix = &f->matrix;
  current.r = Vector(std::string("bench::r"), f->n_dofs);
  current.z = Vector(std::string("bench::z"), f->n_dofs);
  csr_multiply(f->matrix, f->u, current.r);
  Kokkos::fence();
  current.field = f;
  current.key = key;
}

void set_counters(benchmark::State& state) {
  state.counters["DoF"] = current.matrix->n_rows;
  state.counters["nnz/row"] = double(current.matrix->nnz()) / current.matrix->n_rows;
  state.counters["hypre_threads"] = omp_get_max_threads();
}

template <class Physics>
void register_field(const std::string& field, double dofs, const Physics& physics,
                    const AmgOptions& options, const std::vector<int>& threads) {
  const int n = bench::nodes_per_direction(dofs, Physics::n_components);
  const std::string suffix = "/" + std::to_string(n) + "^3";
  auto prepare = [field, n, physics] { make_current(field, n, physics); };
  auto reg = [&](const std::string& variant, std::function<void(benchmark::State&)> fn) {
    auto* b = benchmark::RegisterBenchmark(("amg/" + field + "/" + variant + suffix).c_str(), fn);
    b->UseRealTime()->Unit(benchmark::kMillisecond)->ArgName("threads");
    for (int t : threads) b->Arg(t);
  };
  reg("setup", [prepare, options](benchmark::State& s) {
    prepare();
    ThreadScope scope(s.range(0));
    for (auto _ : s) {
      s.PauseTiming();  // freeing the previous hierarchy is not part of a set-up
      current.amg.reset();
      s.ResumeTiming();
      current.amg = std::make_unique<BoomerAmg>(options);
      current.amg->setup(*current.matrix);
    }
    current.amg_threads = s.range(0);
    s.counters["levels"] = current.amg->levels();
    set_counters(s);
  });
  reg("ij_copy", [prepare](benchmark::State& s) {
    prepare();
    ThreadScope scope(s.range(0));
    for (auto _ : s) bench::HypreCsr copy(*current.matrix);
    set_counters(s);
  });
  reg("vcycle", [prepare, options](benchmark::State& s) {
    prepare();
    ThreadScope scope(s.range(0));
    // The hierarchy is built at the thread count it is cycled at (hypre's threaded smoothers and
    // coarsening may depend on it); the set-up benchmark leaves one behind.
    if (!current.amg || current.amg_threads != s.range(0)) {
      current.amg = std::make_unique<BoomerAmg>(options);
      current.amg->setup(*current.matrix);
      current.amg_threads = s.range(0);
    }
    for (auto _ : s) {
      current.amg->apply(current.r, current.z);
      Kokkos::fence();
    }
    s.counters["levels"] = current.amg->levels();
    set_counters(s);
  });
}

// "1,2" -> {1, 2}; empty if any entry is not a positive integer.
std::vector<int> parse_threads(const char* text) {
  std::vector<int> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const long t = std::strtol(item.c_str(), &end, 10);
    if (item.empty() || *end != '\0' || t < 1) return {};
    out.push_back(static_cast<int>(t));
  }
  return out;
}

}  // namespace
}  // namespace biofsi

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  Kokkos::initialize(argc, argv);
  int rc = 0;
  {
    double dofs = 1e6;
    std::vector<int> threads = {1, 2};
    std::vector<char*> args;
    for (int i = 0; i < argc; ++i) {
      if (std::strncmp(argv[i], "--dofs=", 7) == 0)
        dofs = std::atof(argv[i] + 7);
      else if (std::strncmp(argv[i], "--hypre-threads=", 16) == 0)
        threads = biofsi::parse_threads(argv[i] + 16);
      else
        args.push_back(argv[i]);
    }
    int n_args = static_cast<int>(args.size());
    benchmark::Initialize(&n_args, args.data());
    if (benchmark::ReportUnrecognizedArguments(n_args, args.data()) || !(dofs > 0) ||
        threads.empty()) {
      rc = 2;
    } else {
      using namespace biofsi;
      benchmark::AddCustomContext("kokkos_concurrency",
                                  std::to_string(Kokkos::DefaultExecutionSpace().concurrency()));
      benchmark::AddCustomContext("hypre_version", HYPRE_RELEASE_VERSION);
      benchmark::AddCustomContext("hypre_location", BIOFSI_HYPRE_LOCATION);
      benchmark::AddCustomContext("hypre_openmp", BIOFSI_HYPRE_OPENMP ? "yes" : "no");
      register_field("scalar", dofs, bench::scalar_physics(), AmgOptions{}, threads);
      register_field("structure", dofs, elasticity_physics(), systems_amg(), threads);
      benchmark::RunSpecifiedBenchmarks();
      benchmark::Shutdown();
    }
    biofsi::current = biofsi::Current{};  // hypre objects and Views before MPI and Kokkos go
  }
  Kokkos::finalize();
  MPI_Finalize();
  return rc;
}
