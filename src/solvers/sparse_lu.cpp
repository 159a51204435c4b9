// SparseLu: an assembled CsrMatrix factored by UMFPACK (SuiteSparse's multifrontal LU); the
// symbolic analysis (ordering, elimination tree) is redone only when the sparsity pattern changes.
//
// UMFPACK takes compressed columns; a CSR matrix's arrays are the compressed columns of its
// transpose, so they are handed over as they are, Aᵀ is factored, and each solve asks for the
// transposed system (UMFPACK_At), which is A z = r: no copy into column storage.
#include <umfpack.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "solvers/solvers.hpp"

namespace biofsi {

struct SparseLu::Impl {
  std::vector<int> row_ptr, col;  // the pattern the analysis was made for
  std::vector<double> val;
  void* symbolic = nullptr;
  void* numeric = nullptr;
  double control[UMFPACK_CONTROL];
  double info[UMFPACK_INFO];
  mutable std::vector<double> rhs, solution;

  Impl() {
    umfpack_di_defaults(control);
    // As a preconditioner the factors are applied once per outer Krylov iteration; UMFPACK's
    // default iterative refinement (two steps, each a product with A and another pair of
    // triangular solves) triples that cost and buys accuracy the outer Krylov does not need.
    control[UMFPACK_IRSTEP] = 0;
  }
  ~Impl() {
    free_numeric();
    free_symbolic();
  }
  void free_numeric() {
    if (numeric) umfpack_di_free_numeric(&numeric);
    numeric = nullptr;
  }
  void free_symbolic() {
    if (symbolic) umfpack_di_free_symbolic(&symbolic);
    symbolic = nullptr;
  }
};

namespace {

[[noreturn]] void fail(const char* phase, int status, int rows) {
  std::string why = "UMFPACK status " + std::to_string(status);
  if (status == UMFPACK_WARNING_singular_matrix) why = "the matrix is singular";
  if (status == UMFPACK_ERROR_out_of_memory) why = "out of memory";
  if (status == UMFPACK_ERROR_invalid_matrix) why = "invalid matrix (unsorted or repeated columns)";
  throw std::runtime_error(std::string("sparse LU ") + phase + " failed (" + std::to_string(rows) +
                           " rows): " + why);
}

}  // namespace

SparseLu::SparseLu() : impl_(new Impl) {}
SparseLu::~SparseLu() { delete impl_; }

void SparseLu::setup(const CsrMatrix& a) {
  Impl& m = *impl_;
  std::vector<int> row_ptr = to_host(a.row_ptr), col = to_host(a.col);
  m.val = to_host(a.val);
  const int n = a.n_rows;
  m.free_numeric();
  if (!m.symbolic || row_ptr != m.row_ptr || col != m.col) {
    m.free_symbolic();
    m.row_ptr = std::move(row_ptr);
    m.col = std::move(col);
    const int status = umfpack_di_symbolic(n, n, m.row_ptr.data(), m.col.data(), m.val.data(),
                                           &m.symbolic, m.control, m.info);
    if (status != UMFPACK_OK) {
      m.free_symbolic();
      fail("analysis", status, n);
    }
  }
  const int status = umfpack_di_numeric(m.row_ptr.data(), m.col.data(), m.val.data(), m.symbolic,
                                        &m.numeric, m.control, m.info);
  if (status != UMFPACK_OK) {
    m.free_numeric();
    m.free_symbolic();  // analyse afresh next time
    fail("factorisation", status, n);
  }
  m.rhs.resize(n);
  m.solution.resize(n);
}

void SparseLu::apply(ConstVector r, Vector z) const {
  Impl& m = *impl_;
  const auto rh = Kokkos::create_mirror_view_and_copy(HostSpace(), r);
  for (size_t i = 0; i < m.rhs.size(); ++i) m.rhs[i] = rh(i);
  const int status =
      umfpack_di_solve(UMFPACK_At, m.row_ptr.data(), m.col.data(), m.val.data(), m.solution.data(),
                       m.rhs.data(), m.numeric, m.control, m.info);
  if (status != UMFPACK_OK) fail("solve", status, static_cast<int>(m.rhs.size()));
  auto zh = Kokkos::create_mirror_view(z);
  for (size_t i = 0; i < m.solution.size(); ++i) zh(i) = m.solution[i];
  Kokkos::deep_copy(z, zh);
}

long SparseLu::factor_nonzeros() const {
  int lnz = 0, unz = 0, rows = 0, cols = 0, diagonal = 0;
  if (!impl_->numeric) return 0;
  umfpack_di_get_lunz(&lnz, &unz, &rows, &cols, &diagonal, impl_->numeric);
  return static_cast<long>(lnz) + unz;
}

}  // namespace biofsi
