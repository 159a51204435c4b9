// Compressed sparse row matrix in the execution space's memory, with sorted column indices per row
// so that assembly finds an entry by binary search in a precomputed sparsity pattern.
#pragma once

#include "types.hpp"

namespace biofsi {

struct CsrMatrix {
  int n_rows = 0;
  Kokkos::View<int*, MemSpace> row_ptr;  // n_rows + 1
  Kokkos::View<int*, MemSpace> col;      // sorted within each row
  Kokkos::View<Real*, MemSpace> val;

  int nnz() const { return static_cast<int>(col.extent(0)); }
};

// Position of column c in row r, or -1 when the pattern has no such entry.
KOKKOS_INLINE_FUNCTION int csr_find(const int* row_ptr, const int* col, int r, int c) {
  int lo = row_ptr[r], hi = row_ptr[r + 1] - 1;
  while (lo <= hi) {
    const int mid = (lo + hi) / 2;
    if (col[mid] == c) return mid;
    if (col[mid] < c)
      lo = mid + 1;
    else
      hi = mid - 1;
  }
  return -1;
}

// y = beta y + alpha A x (beta = 0 overwrites y, whatever it held)
inline void csr_multiply_add(const CsrMatrix& a, Real alpha, ConstVector x, Real beta, Vector y) {
  auto rp = a.row_ptr;
  auto col = a.col;
  auto val = a.val;
  Kokkos::parallel_for(
      "biofsi::csr_multiply", Kokkos::RangePolicy<ExecSpace>(0, a.n_rows), KOKKOS_LAMBDA(int r) {
        Real s = 0;
        for (int k = rp(r); k < rp(r + 1); ++k) s += val(k) * x(col(k));
        y(r) = (beta == 0 ? Real(0) : beta * y(r)) + alpha * s;
      });
}

// y = A x
inline void csr_multiply(const CsrMatrix& a, ConstVector x, Vector y) {
  csr_multiply_add(a, 1, x, 0, y);
}

// Diagonal of A (zero where the pattern has no diagonal entry).
inline void csr_diagonal(const CsrMatrix& a, Vector d) {
  auto rp = a.row_ptr;
  auto col = a.col;
  auto val = a.val;
  Kokkos::parallel_for(
      "biofsi::csr_diagonal", Kokkos::RangePolicy<ExecSpace>(0, a.n_rows), KOKKOS_LAMBDA(int r) {
        const int k = csr_find(rp.data(), col.data(), r, r);
        d(r) = k >= 0 ? val(k) : Real(0);
      });
}

// Symmetric elimination of constrained dofs: their rows and columns become identity, so that an
// SPD operator stays SPD (CG) and the constrained increments stay zero.
inline void csr_eliminate_constrained(const CsrMatrix& a,
                                      Kokkos::View<const char*, MemSpace> fixed) {
  auto rp = a.row_ptr;
  auto col = a.col;
  auto val = a.val;
  Kokkos::parallel_for(
      "biofsi::csr_eliminate", Kokkos::RangePolicy<ExecSpace>(0, a.n_rows), KOKKOS_LAMBDA(int r) {
        for (int k = rp(r); k < rp(r + 1); ++k) {
          const int c = col(k);
          if (fixed(r) || fixed(c)) val(k) = (r == c) ? 1.0 : 0.0;
        }
      });
}

}  // namespace biofsi
