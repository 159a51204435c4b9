// Google Benchmark entry for bench_structure_operator: MPI (hypre needs it) and Kokkos around the
// benchmarks, as bench/main.cpp does for the scalar operator (one program per operator, so each
// can be run and filtered on its own).
#include <benchmark/benchmark.h>
#include <mpi.h>

#include <Kokkos_Core.hpp>
#include <string>

namespace biofsi {
void register_structure_operator_benchmarks();
void release_structure_operator_benchmarks();
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
      biofsi::register_structure_operator_benchmarks();
      benchmark::RunSpecifiedBenchmarks();
      benchmark::Shutdown();
    }
    // hypre objects and Views must go before hypre's MPI and Kokkos are torn down.
    biofsi::release_structure_operator_benchmarks();
  }
  Kokkos::finalize();
  MPI_Finalize();
  return rc;
}
