// Smooth nodal fields and the fluid and structure states that the kernel tests share
// (test_field_kernels, test_stored_tangent): built on the host from the small mesh's coordinates
// and copied to the device. Kernel code only, like small_mesh.hpp, so the CUDA preset builds them.
#pragma once

#include <cmath>
#include <string>

#include "kernels/fluid/pointwise.hpp"
#include "kernels/structure/pointwise.hpp"
#include "small_mesh.hpp"

namespace biofsi {
namespace test {

// A nodal field with `nc` components: value c of node n is f(c, x, y, z).
template <class F>
Vector nodal(const SmallMesh& m, int nc, F f, const std::string& label) {
  Vector v(label, nc * m.n_nodes());
  auto h = Kokkos::create_mirror_view(v);
  for (int n = 0; n < m.n_nodes(); ++n)
    for (int c = 0; c < nc; ++c)
      h(nc * n + c) = f(c, m.x_host(n, 0), m.x_host(n, 1), m.x_host(n, 2));
  Kokkos::deep_copy(v, h);
  return v;
}

// Auxiliary data with `na` columns (one unused column when na = 0).
template <class F>
NodalView auxiliary(const SmallMesh& m, int na, F f) {
  NodalView a(std::string("test::aux"), m.n_nodes(), na > 0 ? na : 1);
  auto h = Kokkos::create_mirror_view(a);
  for (int n = 0; n < m.n_nodes(); ++n)
    for (int c = 0; c < na; ++c) h(n, c) = f(c, m.x_host(n, 0), m.x_host(n, 1), m.x_host(n, 2));
  Kokkos::deep_copy(a, h);
  return a;
}

// The direction du of the tangent checks.
inline Vector direction(const SmallMesh& m, int nc) {
  return nodal(
      m, nc, [](int c, double x, double y, double z) { return std::sin(3 * x - y + c) + 0.2 * z; },
      "test::du");
}

// The fluid's aux (u_n, u_grid, b): a convective velocity of order 0.5, so that with viscosity
// 0.01 the element Reynolds number is ~10 and convection and SUPG matter.
inline NodalView fluid_aux(const SmallMesh& m) {
  return auxiliary(m, FluidPhysics::n_aux, [](int c, double x, double y, double z) {
    if (c < 3) return 0.5 * std::sin(1.3 * x + c) * std::cos(y - 0.4 * z);
    if (c < 6) return 0.1 * std::cos(x + 2 * y + c);
    return 0.3 * (c - 7);
  });
}

inline Vector fluid_state(const SmallMesh& m) {
  return nodal(
      m, 4,
      [](int c, double x, double y, double z) {
        return c < 3 ? std::cos(2 * x + c) * std::sin(1 + y + 0.5 * z) : x * y - z;
      },
      "test::u");
}

// Two blocks of one material model with different stiffness, one-step-theta dynamics.
inline StructurePhysics structure_physics(int model) {
  StructurePhysics p;
  for (int b = 0; b < 2; ++b) {
    p.materials.model[b] = model;
    p.materials.lambda[b] = 1.0 + b;
    p.materials.mu[b] = 0.5;
    p.materials.density[b] = 2.0;
  }
  p.mass_coefficient = 10.0;
  p.dt = 0.1;
  p.theta = 0.66;
  return p;
}

// The structure's aux (d_n, v_n, b): d_n of order `strain` with a shear `shear` z in x.
inline NodalView structure_aux(const SmallMesh& m, double strain, double shear) {
  return auxiliary(m, StructurePhysics::n_aux, [=](int c, double x, double y, double z) {
    if (c < 3) return strain * std::sin(x + 2 * y + c) + shear * z * (c == 0);
    return 0.1 * std::cos(x - y + c);
  });
}

// A displacement of order `amplitude` with a z term `tilt`.
inline Vector structure_state(const SmallMesh& m, double amplitude, double tilt) {
  return nodal(
      m, 3,
      [=](int c, double x, double y, double z) {
        return amplitude * std::cos(2 * x + c) * (1 + y) - tilt * z;
      },
      "test::u");
}

}  // namespace test
}  // namespace biofsi
