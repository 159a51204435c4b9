// kernels/core: the field-independent performance core of biofsi.
//
// What lives here: scalar and View types (types.hpp), the hex8 basis with sum factorisation and
// on-the-fly geometry (hex8.hpp), the boundary-face quadrature (face.hpp), the CSR matrix layout
// (csr.hpp), the generic element-loop drivers that turn pointwise physics into residual,
// tangent action, diagonal and assembled matrix (element_loop.hpp), and the tangent stored at the
// quadrature points, applied in SIMD batches of elements (stored_tangent.hpp, simd.hpp), which is
// what the fields' Krylov solves apply.
// What it may include: Kokkos only. No I/O, no MPI, no hypre, no std:: containers in kernels.
// Who depends on it: kernels/<field>/ pointwise physics and everything in src/.
#pragma once

#include <Kokkos_Core.hpp>

namespace biofsi {

using Real = double;
using ExecSpace = Kokkos::DefaultExecutionSpace;
using MemSpace = ExecSpace::memory_space;
using HostSpace = Kokkos::HostSpace;

// Flat dof vectors: dof = node * n_components + component (interleaved).
using Vector = Kokkos::View<Real*, MemSpace>;
using ConstVector = Kokkos::View<const Real*, MemSpace>;
using IndexView = Kokkos::View<int*, MemSpace>;
using ConstIndexView = Kokkos::View<const int*, MemSpace>;

// Mesh data as kernels see it: node coordinates and hex8 connectivity in VTK/XDMF node order.
using CoordView = Kokkos::View<Real* [3], MemSpace>;
using ConstCoordView = Kokkos::View<const Real* [3], MemSpace>;
using ConnView = Kokkos::View<int* [8], MemSpace>;
using ConstConnView = Kokkos::View<const int* [8], MemSpace>;

// Nodal auxiliary data (old solution, convective velocity, ...): one row per node.
using NodalView = Kokkos::View<Real**, Kokkos::LayoutRight, MemSpace>;
using ConstNodalView = Kokkos::View<const Real**, Kokkos::LayoutRight, MemSpace>;

// Device-callable math: Kokkos moved these from Kokkos::Experimental to Kokkos in 3.6.
namespace math {
#if KOKKOS_VERSION >= 30600
using Kokkos::atan;
using Kokkos::exp;
using Kokkos::fabs;
using Kokkos::log;
using Kokkos::sqrt;
using Kokkos::tanh;
#else
using Kokkos::Experimental::atan;
using Kokkos::Experimental::exp;
using Kokkos::Experimental::fabs;
using Kokkos::Experimental::log;
using Kokkos::Experimental::sqrt;
using Kokkos::Experimental::tanh;
#endif
}  // namespace math

}  // namespace biofsi
