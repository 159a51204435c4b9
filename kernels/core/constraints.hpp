// Dirichlet constraints on flat dof vectors, given as a list of constrained dofs (and values).
// Fields keep constrained rows as identity: residual r_c = u_c - g_c, tangent y_c = du_c, and the
// free rows see du with its constrained entries zeroed (symmetric elimination).
#pragma once

#include "types.hpp"

namespace biofsi {

// x_c = g_c
inline void set_constrained(ConstIndexView dofs, ConstVector values, Vector x) {
  Kokkos::parallel_for(
      "biofsi::set_constrained", Kokkos::RangePolicy<ExecSpace>(0, dofs.extent(0)),
      KOKKOS_LAMBDA(int i) { x(dofs(i)) = values(i); });
}

// r_c = u_c - g_c
inline void constrained_residual(ConstIndexView dofs, ConstVector values, ConstVector u, Vector r) {
  Kokkos::parallel_for(
      "biofsi::constrained_residual", Kokkos::RangePolicy<ExecSpace>(0, dofs.extent(0)),
      KOKKOS_LAMBDA(int i) { r(dofs(i)) = u(dofs(i)) - values(i); });
}

// to_c = from_c
inline void copy_constrained(ConstIndexView dofs, ConstVector from, Vector to) {
  Kokkos::parallel_for(
      "biofsi::copy_constrained", Kokkos::RangePolicy<ExecSpace>(0, dofs.extent(0)),
      KOKKOS_LAMBDA(int i) { to(dofs(i)) = from(dofs(i)); });
}

// x_c = 0
inline void zero_constrained(ConstIndexView dofs, Vector x) {
  Kokkos::parallel_for(
      "biofsi::zero_constrained", Kokkos::RangePolicy<ExecSpace>(0, dofs.extent(0)),
      KOKKOS_LAMBDA(int i) { x(dofs(i)) = 0; });
}

}  // namespace biofsi
