// Pieces every operator benchmark shares: hypre's ParCSR copy of an assembled matrix (the CSR
// baseline each matrix-free variant is compared with) and the per-DoF counters.
#pragma once

#include <HYPRE.h>
#include <HYPRE_parcsr_ls.h>
#include <benchmark/benchmark.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "kernels/core/csr.hpp"

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

}  // namespace bench
}  // namespace biofsi
