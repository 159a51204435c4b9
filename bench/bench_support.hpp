// Pieces every bench program shares: registration with the common settings, the fenced timed loop,
// the rate counters, one problem alive at a time, hypre's ParCSR copy of an assembled matrix (the
// CSR baseline of bench_operator, the IJ copy of bench_amg) and BoomerAMG's systems settings.
#pragma once

#include <HYPRE.h>
#include <HYPRE_parcsr_ls.h>
#include <benchmark/benchmark.h>

#include <Kokkos_Core.hpp>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "kernels/core/csr.hpp"
#include "solvers/solvers.hpp"

namespace biofsi {
namespace bench {

inline void check(HYPRE_Int err, const char* what) {
  if (err == 0) return;
  HYPRE_ClearAllErrors();
  throw std::runtime_error(std::string("hypre: ") + what + " failed");
}

// The assembled matrix as hypre holds it (single rank).
struct HypreCsr {
  HYPRE_IJMatrix ij = nullptr;
  HYPRE_IJVector ij_x = nullptr, ij_y = nullptr;
  HYPRE_ParCSRMatrix a = nullptr;
  HYPRE_ParVector x = nullptr, y = nullptr;

  explicit HypreCsr(const CsrMatrix& m) {
    const int n = m.n_rows;
    auto rp = Kokkos::create_mirror_view_and_copy(HostSpace(), m.row_ptr);
    auto col = Kokkos::create_mirror_view_and_copy(HostSpace(), m.col);
    auto val = Kokkos::create_mirror_view_and_copy(HostSpace(), m.val);
    std::vector<HYPRE_Int> n_cols(n);
    std::vector<HYPRE_BigInt> rows(n), cols(col.data(), col.data() + col.extent(0));
    for (int r = 0; r < n; ++r) rows[r] = r, n_cols[r] = rp(r + 1) - rp(r);
    check(HYPRE_IJMatrixCreate(MPI_COMM_WORLD, 0, n - 1, 0, n - 1, &ij), "IJMatrixCreate");
    check(HYPRE_IJMatrixSetObjectType(ij, HYPRE_PARCSR), "IJMatrixSetObjectType");
    check(HYPRE_IJMatrixSetDiagOffdSizes(ij, n_cols.data(), std::vector<HYPRE_Int>(n, 0).data()),
          "IJMatrixSetDiagOffdSizes");
    check(HYPRE_IJMatrixInitialize(ij), "IJMatrixInitialize");
    check(HYPRE_IJMatrixSetValues(ij, n, n_cols.data(), rows.data(), cols.data(), val.data()),
          "IJMatrixSetValues");
    check(HYPRE_IJMatrixAssemble(ij), "IJMatrixAssemble");
    void* object = nullptr;
    check(HYPRE_IJMatrixGetObject(ij, &object), "IJMatrixGetObject");
    a = static_cast<HYPRE_ParCSRMatrix>(object);
    for (auto* v : {&ij_x, &ij_y}) {
      check(HYPRE_IJVectorCreate(MPI_COMM_WORLD, 0, n - 1, v), "IJVectorCreate");
      check(HYPRE_IJVectorSetObjectType(*v, HYPRE_PARCSR), "IJVectorSetObjectType");
      check(HYPRE_IJVectorInitialize(*v), "IJVectorInitialize");
    }
    std::vector<double> ones(n, 1.0);
    check(HYPRE_IJVectorSetValues(ij_x, n, rows.data(), ones.data()), "IJVectorSetValues");
    for (auto v : {ij_x, ij_y}) check(HYPRE_IJVectorAssemble(v), "IJVectorAssemble");
    check(HYPRE_IJVectorGetObject(ij_x, &object), "IJVectorGetObject");
    x = static_cast<HYPRE_ParVector>(object);
    check(HYPRE_IJVectorGetObject(ij_y, &object), "IJVectorGetObject");
    y = static_cast<HYPRE_ParVector>(object);
  }
  ~HypreCsr() {
    HYPRE_IJMatrixDestroy(ij);
    HYPRE_IJVectorDestroy(ij_x);
    HYPRE_IJVectorDestroy(ij_y);
  }
  HypreCsr(const HypreCsr&) = delete;
  HypreCsr& operator=(const HypreCsr&) = delete;
};

// Bytes a CSR matvec moves per row: 8-byte value and 4-byte column per nonzero, the row pointer,
// x and y (bench/README.md).
inline double csr_bytes_per_row(const CsrMatrix& a) {
  return (12.0 * a.nnz() + 4.0 * (a.n_rows + 1)) / a.n_rows + 16;
}

// MDoF/s as a rate counter, with the problem size beside it.
inline void set_rate_counters(benchmark::State& state, int n_dofs) {
  state.counters["DoF"] = n_dofs;
  state.counters["MDoF/s"] =
      benchmark::Counter(1e-6 * n_dofs * state.iterations(), benchmark::Counter::kIsRate);
}

// The benchmark loop with the execution space fenced on both sides of each timed body.
template <class Body>
void fenced(benchmark::State& state, Body&& body) {
  for (auto _ : state) {
    Kokkos::fence();
    body();
    Kokkos::fence();
  }
}

// A benchmark timed in real time (threads and hypre), reported in milliseconds.
inline benchmark::internal::Benchmark* add(const std::string& name,
                                           std::function<void(benchmark::State&)> fn) {
  return benchmark::RegisterBenchmark(name.c_str(), std::move(fn))
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
}

// Cheap benchmarks repeated, reported as the aggregates only: the median damps other work on a
// shared machine.
inline benchmark::internal::Benchmark* repeated(benchmark::internal::Benchmark* b, int times) {
  return b->Repetitions(times)->ReportAggregatesOnly(true);
}

// "/n^3", the size part of a benchmark's name.
inline std::string cube_size(int n) { return "/" + std::to_string(n) + "^3"; }

// One problem alive at a time (the largest take several GB): built at the first use of a key,
// replaced when another key is asked for, freed by release() before MPI and Kokkos go.
class OneAtATime {
 public:
  template <class Problem, class... Args>
  Problem& get(const std::string& key, const Args&... args) {
    if (key != key_) {
      release();
      object_ = std::make_shared<Problem>(args...);
      key_ = key;
    }
    return *static_cast<Problem*>(object_.get());
  }
  void release() {
    object_.reset();
    key_.clear();
  }

 private:
  std::string key_;
  std::shared_ptr<void> object_;
};

// Systems BoomerAMG over interleaved 3-vectors with nodal coarsening, as the structure configures
// it (StructureAmg::Systems).
inline AmgOptions systems_amg() {
  AmgOptions o;
  o.num_functions = 3;
  o.nodal_coarsening = true;
  return o;
}

// FGMRES from zero on `apply` with the AMG preconditioner, fenced and timed per iteration, after
// `setup` (timed with the solve) where one is given. Reports the iterations; fails the benchmark if
// the last solve did not converge.
inline void timed_fgmres(benchmark::State& state, const ApplyFn& apply, const BoomerAmg& amg,
                         ConstVector b, Vector sol, const KrylovOptions& options,
                         const std::function<void()>& setup = {}) {
  KrylovResult res;
  fenced(state, [&] {
    if (setup) setup();
    Kokkos::deep_copy(sol, 0.0);
    res = fgmres(apply, amg.as_function(), b, sol, options);
  });
  if (!res.converged) state.SkipWithError(("FGMRES did not converge: " + res.reason).c_str());
  state.counters["iterations"] = res.iterations;
}

}  // namespace bench
}  // namespace biofsi
