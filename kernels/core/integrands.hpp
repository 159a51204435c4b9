// Unit integrands: with the element and face drivers they give the nodal weights int N_a dV and
// int N_a dA (lumped volumes and areas), used for integrals of nodal fields and flux densities.
#pragma once

#include "element_loop.hpp"
#include "face.hpp"

namespace biofsi {

struct UnitVolumeIntegrand {
  static constexpr int n_components = 1, n_aux = 0;
  KOKKOS_INLINE_FUNCTION void residual(const QpData<0>&, const Real[1], const Real[1][3],
                                       Real f0[1], Real f1[1][3]) const {
    f0[0] = 1;
    f1[0][0] = f1[0][1] = f1[0][2] = 0;
  }
  KOKKOS_INLINE_FUNCTION void tangent(const QpData<0>&, const Real[1], const Real[1][3],
                                      const Real[1], const Real[1][3], Real df0[1],
                                      Real df1[1][3]) const {
    df0[0] = 0;
    df1[0][0] = df1[0][1] = df1[0][2] = 0;
  }
};

struct UnitAreaIntegrand {
  static constexpr int n_components = 1, n_aux = 0;
  KOKKOS_INLINE_FUNCTION void residual(const Real*, const Real[1], Real f0[1]) const { f0[0] = 1; }
  KOKKOS_INLINE_FUNCTION void tangent(const Real*, const Real[1], const Real[1],
                                      Real df0[1]) const {
    df0[0] = 0;
  }
};

}  // namespace biofsi
