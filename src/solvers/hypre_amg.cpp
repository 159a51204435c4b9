// BoomerAMG preconditioner: copies a CsrMatrix into a hypre IJ/ParCSR matrix and runs V-cycles on
// it. hypre here is the CPU (MPI) build, so vectors cross to host memory at each application.
#include <HYPRE.h>
#include <HYPRE_parcsr_ls.h>
#include <mpi.h>

#include <chrono>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "solvers/solvers.hpp"

// Internal hypre headers: the public 2.26 API has no getter for the number of levels nor for a
// ParVector's local array (which apply() fills in place instead of going through IJ SetValues).
#include <_hypre_parcsr_ls.h>

namespace biofsi {

static_assert(std::is_same<HYPRE_Complex, Real>::value,
              "biofsi needs a double-precision, real-valued hypre build");

namespace {

using HostVector = Kokkos::View<Real*, HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>>;

void check(HYPRE_Int err, const char* what) {
  if (err == 0) return;
  char description[256] = {};
  HYPRE_DescribeError(err, description);
  // hypre's error flag is sticky: clear it, or every later hypre call would report it again.
  HYPRE_ClearAllErrors();
  throw std::runtime_error(std::string("hypre: ") + what + " failed: " + description);
}

void ensure_hypre_initialized() {
  // Once per process; HYPRE_Finalize is left to process exit because the program may still hold
  // solvers when main() tears MPI down (hypre's CPU build keeps no resources that need it).
  static const bool initialized = [] {
    check(HYPRE_Init(), "HYPRE_Init");
    return true;
  }();
  (void)initialized;
}

}  // namespace

struct BoomerAmg::Impl {
  HYPRE_BigInt ilower = 0, iupper = -1;  // this rank's rows, inclusive as hypre wants them
  int n_local = 0;
  int num_levels = 0;
  HYPRE_IJMatrix ij_matrix = nullptr;
  HYPRE_IJVector ij_b = nullptr, ij_x = nullptr;
  HYPRE_ParCSRMatrix par_matrix = nullptr;
  HYPRE_ParVector par_b = nullptr, par_x = nullptr;
  HYPRE_Solver solver = nullptr;
  // Interpolation vectors: hypre keeps pointers to the finest level's ones (the caller's input)
  // and never frees them, so they live here until the solver is gone.
  std::vector<HYPRE_IJVector> ij_interp;
  std::vector<HYPRE_ParVector> interp;

  ~Impl() { release(); }

  void release() {
    if (solver) HYPRE_BoomerAMGDestroy(solver);
    if (ij_matrix) HYPRE_IJMatrixDestroy(ij_matrix);
    if (ij_b) HYPRE_IJVectorDestroy(ij_b);
    if (ij_x) HYPRE_IJVectorDestroy(ij_x);
    for (auto v : ij_interp) HYPRE_IJVectorDestroy(v);
    ij_interp.clear();
    interp.clear();
    solver = nullptr;
    ij_matrix = nullptr;
    ij_b = ij_x = nullptr;
    par_matrix = nullptr;
    par_b = par_x = nullptr;
    num_levels = 0;
  }

  static Real* local_data(HYPRE_ParVector v) {
    return hypre_VectorData(hypre_ParVectorLocalVector(reinterpret_cast<hypre_ParVector*>(v)));
  }
};

BoomerAmg::BoomerAmg(const AmgOptions& opt) : impl_(new Impl), opt_(opt) {}

BoomerAmg::~BoomerAmg() { delete impl_; }

void BoomerAmg::setup(const CsrMatrix& a) {
  const auto start = std::chrono::steady_clock::now();
  ensure_hypre_initialized();
  if (opt_.num_functions < 1 || a.n_rows % opt_.num_functions != 0)
    throw std::invalid_argument(
        "BoomerAmg: " + std::to_string(a.n_rows) +
        " rows are not a multiple of num_functions = " + std::to_string(opt_.num_functions));
  HYPRE_ClearAllErrors();
  impl_->release();

  const MPI_Comm comm = MPI_COMM_WORLD;
  // Rows are numbered rank by rank; columns of the CsrMatrix are taken as global ids (equal to the
  // local ones on a single rank).
  HYPRE_BigInt n_local = a.n_rows, offset = 0;
  MPI_Exscan(&n_local, &offset, 1, HYPRE_MPI_BIG_INT, MPI_SUM, comm);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) offset = 0;  // MPI_Exscan leaves rank 0's result undefined
  impl_->ilower = offset;
  impl_->iupper = offset + n_local - 1;
  impl_->n_local = a.n_rows;

  auto row_ptr = Kokkos::create_mirror_view_and_copy(HostSpace(), a.row_ptr);
  auto col = Kokkos::create_mirror_view_and_copy(HostSpace(), a.col);
  auto val = Kokkos::create_mirror_view_and_copy(HostSpace(), a.val);

  const int n = a.n_rows;
  std::vector<HYPRE_Int> n_cols(n), diag_sizes(n), offd_sizes(n);
  std::vector<HYPRE_BigInt> rows(n), cols(a.nnz());
  for (int r = 0; r < n; ++r) {
    rows[r] = impl_->ilower + r;
    n_cols[r] = row_ptr(r + 1) - row_ptr(r);
    for (int k = row_ptr(r); k < row_ptr(r + 1); ++k) {
      cols[k] = col(k);
      if (cols[k] >= impl_->ilower && cols[k] <= impl_->iupper)
        ++diag_sizes[r];
      else
        ++offd_sizes[r];
    }
  }

  const HYPRE_BigInt lo = impl_->ilower, hi = impl_->iupper;
  check(HYPRE_IJMatrixCreate(comm, lo, hi, lo, hi, &impl_->ij_matrix), "IJMatrixCreate");
  check(HYPRE_IJMatrixSetObjectType(impl_->ij_matrix, HYPRE_PARCSR), "IJMatrixSetObjectType");
  // Exact preallocation: hypre otherwise grows its row storage while values arrive.
  check(HYPRE_IJMatrixSetDiagOffdSizes(impl_->ij_matrix, diag_sizes.data(), offd_sizes.data()),
        "IJMatrixSetDiagOffdSizes");
  check(HYPRE_IJMatrixInitialize(impl_->ij_matrix), "IJMatrixInitialize");
  if (n > 0)
    check(HYPRE_IJMatrixSetValues(impl_->ij_matrix, n, n_cols.data(), rows.data(), cols.data(),
                                  val.data()),
          "IJMatrixSetValues");
  check(HYPRE_IJMatrixAssemble(impl_->ij_matrix), "IJMatrixAssemble");
  void* object = nullptr;
  check(HYPRE_IJMatrixGetObject(impl_->ij_matrix, &object), "IJMatrixGetObject");
  impl_->par_matrix = static_cast<HYPRE_ParCSRMatrix>(object);

  for (auto* v : {&impl_->ij_b, &impl_->ij_x}) {
    check(HYPRE_IJVectorCreate(comm, lo, hi, v), "IJVectorCreate");
    check(HYPRE_IJVectorSetObjectType(*v, HYPRE_PARCSR), "IJVectorSetObjectType");
    check(HYPRE_IJVectorInitialize(*v), "IJVectorInitialize");
    check(HYPRE_IJVectorAssemble(*v), "IJVectorAssemble");
  }
  check(HYPRE_IJVectorGetObject(impl_->ij_b, &object), "IJVectorGetObject");
  impl_->par_b = static_cast<HYPRE_ParVector>(object);
  check(HYPRE_IJVectorGetObject(impl_->ij_x, &object), "IJVectorGetObject");
  impl_->par_x = static_cast<HYPRE_ParVector>(object);

  HYPRE_Solver& s = impl_->solver;
  check(HYPRE_BoomerAMGCreate(&s), "BoomerAMGCreate");
  HYPRE_BoomerAMGSetPrintLevel(s, opt_.print_level);
  // A fixed number of cycles from a zero guess is a fixed linear operator, which CG requires.
  HYPRE_BoomerAMGSetTol(s, 0.0);
  HYPRE_BoomerAMGSetMaxIter(s, opt_.cycles);
  HYPRE_BoomerAMGSetMaxLevels(s, opt_.max_levels);
  HYPRE_BoomerAMGSetStrongThreshold(s, opt_.strong_threshold);
  // HMIS coarsening with extended+i interpolation truncated to 4 entries per row: hypre's
  // recommended low-complexity combination for 3-D problems (classical Ruge-Stueben coarsening
  // grows the operator complexity badly on 3-D stencils).
  HYPRE_BoomerAMGSetCoarsenType(s, 10);
  HYPRE_BoomerAMGSetInterpType(s, 6);
  HYPRE_BoomerAMGSetPMaxElmts(s, 4);
  HYPRE_BoomerAMGSetAggNumLevels(s, opt_.aggressive_levels);
  // l1 Gauss-Seidel forward on the way down and backward on the way up keeps the V-cycle
  // symmetric (CG needs an SPD preconditioner); Gaussian elimination on the coarsest level.
  HYPRE_BoomerAMGSetCycleRelaxType(s, 13, 1);
  HYPRE_BoomerAMGSetCycleRelaxType(s, 14, 2);
  HYPRE_BoomerAMGSetCycleRelaxType(s, 9, 3);
  if (opt_.num_functions > 1) {
    HYPRE_BoomerAMGSetNumFunctions(s, opt_.num_functions);
    // Nodal coarsening on the Frobenius norm of each node's block: all components of a node share
    // one C/F choice, as the interleaved dof layout (dof = node * n + component) expects.
    if (opt_.nodal_coarsening) HYPRE_BoomerAMGSetNodal(s, 1);
  }
  if (!opt_.interpolation_vectors.empty()) {
    if (opt_.num_functions < 2)
      throw std::invalid_argument("BoomerAmg: interpolation vectors need num_functions > 1");
    for (const auto& v : opt_.interpolation_vectors) {
      if (static_cast<int>(v.size()) != n)
        throw std::invalid_argument("BoomerAmg: an interpolation vector has " +
                                    std::to_string(v.size()) + " entries for " + std::to_string(n) +
                                    " rows");
      HYPRE_IJVector ij = nullptr;
      check(HYPRE_IJVectorCreate(comm, lo, hi, &ij), "IJVectorCreate");
      impl_->ij_interp.push_back(ij);
      check(HYPRE_IJVectorSetObjectType(ij, HYPRE_PARCSR), "IJVectorSetObjectType");
      check(HYPRE_IJVectorInitialize(ij), "IJVectorInitialize");
      if (n > 0) check(HYPRE_IJVectorSetValues(ij, n, rows.data(), v.data()), "IJVectorSetValues");
      check(HYPRE_IJVectorAssemble(ij), "IJVectorAssemble");
      check(HYPRE_IJVectorGetObject(ij, &object), "IJVectorGetObject");
      impl_->interp.push_back(static_cast<HYPRE_ParVector>(object));
    }
    // hypre's recommended elasticity set-up (its new_ij driver, -rbm): nodal strength from the
    // row-sum norm of each node block with the diagonal kept, GM-2 interpolation vectors with at
    // most 4 entries per row, the vectors smoothed and the interpolation refined once.
    HYPRE_BoomerAMGSetNodal(s, 4);
    HYPRE_BoomerAMGSetNodalDiag(s, 1);
    HYPRE_BoomerAMGSetInterpVecVariant(s, 2);
    HYPRE_BoomerAMGSetInterpVecQMax(s, 4);
    HYPRE_BoomerAMGSetSmoothInterpVectors(s, 1);
    HYPRE_BoomerAMGSetInterpRefine(s, 1);
    HYPRE_BoomerAMGSetInterpVectors(s, static_cast<HYPRE_Int>(impl_->interp.size()),
                                    impl_->interp.data());
  }
  check(HYPRE_BoomerAMGSetup(s, impl_->par_matrix, impl_->par_b, impl_->par_x), "BoomerAMGSetup");
  impl_->num_levels = hypre_ParAMGDataNumLevels(reinterpret_cast<hypre_ParAMGData*>(s));

  setup_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void BoomerAmg::apply(ConstVector r, Vector z) const {
  if (!impl_->solver) throw std::logic_error("BoomerAmg::apply called before setup");
  const int n = impl_->n_local;
  if (static_cast<int>(r.extent(0)) != n || static_cast<int>(z.extent(0)) != n)
    throw std::invalid_argument("BoomerAmg::apply: vector length " + std::to_string(r.extent(0)) +
                                " does not match the " + std::to_string(n) +
                                " rows of the set-up matrix");
  HostVector b(Impl::local_data(impl_->par_b), n);
  HostVector x(Impl::local_data(impl_->par_x), n);
  Kokkos::deep_copy(b, r);
  Kokkos::deep_copy(x, 0.0);
  check(HYPRE_BoomerAMGSolve(impl_->solver, impl_->par_matrix, impl_->par_b, impl_->par_x),
        "BoomerAMGSolve");
  Kokkos::deep_copy(z, x);
}

ApplyFn BoomerAmg::as_function() const {
  // Captures this object: it must outlive the returned function (and see any later setup()).
  return [this](ConstVector r, Vector z) { apply(r, z); };
}

int BoomerAmg::levels() const { return impl_->num_levels; }

}  // namespace biofsi
