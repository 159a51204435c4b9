// Google Benchmark entry: MPI (hypre needs it) and Kokkos live around all benchmarks. Kokkos
// fixes its OpenMP thread count here, from OMP_NUM_THREADS, so thread scaling is measured by
// separate runs (bench/run_scalar_bench).
#include <benchmark/benchmark.h>
#include <mpi.h>

#include <Kokkos_Core.hpp>
#include <string>

namespace biofsi {
void register_scalar_operator_benchmarks();
void release_scalar_operator_benchmarks();
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
      benchmark::AddCustomContext("kokkos_execution_space", Kokkos::DefaultExecutionSpace::name());
      biofsi::register_scalar_operator_benchmarks();
      benchmark::RunSpecifiedBenchmarks();
      benchmark::Shutdown();
    }
    // hypre objects and Views must go before hypre's MPI and Kokkos are torn down.
    biofsi::release_scalar_operator_benchmarks();
  }
  Kokkos::finalize();
  MPI_Finalize();
  return rc;
}
