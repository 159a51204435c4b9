// Level-1 vector operations on dof vectors, as Kokkos kernels in the execution space so that the
// Krylov and Newton loops never copy vectors to the host.
#include <cfloat>
#include <cmath>

#include "solvers/solvers.hpp"

namespace biofsi {

namespace {
using Policy = Kokkos::RangePolicy<ExecSpace>;

Policy range(const ConstVector& v) { return Policy(0, static_cast<int>(v.extent(0))); }
}  // namespace

Real dot(ConstVector a, ConstVector b) {
  Real s = 0;
  Kokkos::parallel_reduce(
      "biofsi::dot", range(a), KOKKOS_LAMBDA(int i, Real& acc) { acc += a(i) * b(i); }, s);
  return s;
}

Real norm2(ConstVector a) { return std::sqrt(dot(a, a)); }

Real max_abs(ConstVector a) {
  Real m = 0;
  Kokkos::parallel_reduce(
      "biofsi::max_abs", range(a),
      KOKKOS_LAMBDA(int i, Real& acc) {
        const Real v = a(i) < 0 ? -a(i) : a(i);
        if (v > acc) acc = v;
      },
      Kokkos::Max<Real>(m));
  return m;
}

bool all_finite(ConstVector a) {
  int bad = 0;
  // Two comparisons instead of isfinite: NaN fails both, +-inf fails one, and the test needs no
  // math function whose namespace differs between Kokkos 3.4 and 4.x.
  Kokkos::parallel_reduce(
      "biofsi::all_finite", range(a),
      KOKKOS_LAMBDA(int i, int& acc) {
        const Real v = a(i);
        if (!(v >= -DBL_MAX && v <= DBL_MAX)) ++acc;
      },
      bad);
  return bad == 0;
}

void axpy(Real alpha, ConstVector x, Vector y) {
  Kokkos::parallel_for(
      "biofsi::axpy", range(x), KOKKOS_LAMBDA(int i) { y(i) += alpha * x(i); });
}

void axpby(Real alpha, ConstVector x, Real beta, Vector y) {
  // beta == 0 overwrites y, so that uninitialised (or NaN) contents of y do not leak through 0*NaN.
  if (beta == 0) {
    Kokkos::parallel_for(
        "biofsi::axpby", range(x), KOKKOS_LAMBDA(int i) { y(i) = alpha * x(i); });
  } else {
    Kokkos::parallel_for(
        "biofsi::axpby", range(x), KOKKOS_LAMBDA(int i) { y(i) = alpha * x(i) + beta * y(i); });
  }
}

void scale(Real alpha, Vector x) {
  Kokkos::parallel_for(
      "biofsi::scale", range(x), KOKKOS_LAMBDA(int i) { x(i) *= alpha; });
}

void fill(Vector x, Real value) { Kokkos::deep_copy(x, value); }

void copy(ConstVector from, Vector to) { Kokkos::deep_copy(to, from); }

}  // namespace biofsi
