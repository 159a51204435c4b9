// The unit cube and each field's operator on it, with a state of its own physics and the assembled
// matrix: the problems every bench program measures.
//
// The mesh is the unit cube with n nodes per direction, two blocks (y < 1/2, y > 1/2). Deformed
// (bench_operator, bench_amg), its interior nodes are moved by up to 20% of h in each direction (a
// deterministic hash, so every run sees the same mesh) and every element is a general trilinear
// hex; plain (the per-field programs), it is the box. The states are real ones, each field's own
// physics:
//   scalar: transient transport with SUPG, two diffusivities, Monod consumption in the upper block;
//   structure: dynamic St. Venant-Kirchhoff (lower) and Neo-Hooke (upper), strains ~0.1;
//   fluid: transient stabilised Navier-Stokes (SUPG/PSPG/grad-div), element Reynolds number ~10;
//   mesh motion: pseudo-elasticity with Jacobian stiffening.
#pragma once

#include <Kokkos_Core.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "kernels/ale/pointwise.hpp"
#include "kernels/fluid/pointwise.hpp"
#include "kernels/scalar/pointwise.hpp"
#include "kernels/structure/pointwise.hpp"
#include "mesh/mesh.hpp"

namespace biofsi {
namespace bench {

// A reproducible number in [-1, 1] from two integers.
inline double hashed_unit(std::uint32_t a, std::uint32_t b) {
  std::uint32_t h = a * 0x9E3779B1u ^ (b + 0x7F4A7C15u) * 0x85EBCA77u;
  h ^= h >> 15;
  h *= 0x2C1B3C6Du;
  h ^= h >> 12;
  return 2.0 * (h & 0xFFFFFF) / double(0xFFFFFF) - 1.0;
}

// How far deformed_cube's interior nodes move, in units of h; 0 gives the plain box.
constexpr double deformed = 0.2, plain = 0.0;

// Unit cube, n nodes per direction, two blocks (y < 1/2, y > 1/2), interior nodes moved by up to
// distortion * h in each direction.
inline Mesh deformed_cube(int n, double distortion = deformed) {
  const int cells = n - 1;
  BoxSpec spec;
  spec.nx = spec.nz = cells;
  spec.blocks = {{"lower", 0.0, 0.5, cells / 2, 1.0}, {"upper", 0.5, 1.0, cells - cells / 2, 1.0}};
  Mesh mesh = make_box_mesh(spec);
  if (distortion == 0) return mesh;
  const double h = 1.0 / cells, eps = 1e-12;
  for (int i = 0; i < mesh.n_nodes(); ++i) {
    auto& x = mesh.x[i];
    bool interior = true;
    for (int d = 0; d < 3; ++d) interior = interior && x[d] > eps && x[d] < 1 - eps;
    if (!interior) continue;
    for (int d = 0; d < 3; ++d) x[d] += distortion * h * hashed_unit(i, d);
  }
  return mesh;
}

template <class F>
NodalView nodal_aux(const Mesh& mesh, int n_aux, F f) {
  NodalView aux(std::string("bench::aux"), mesh.n_nodes(), n_aux > 0 ? n_aux : 1);
  auto h = Kokkos::create_mirror_view(aux);
  for (int i = 0; i < mesh.n_nodes(); ++i)
    for (int c = 0; c < n_aux; ++c) h(i, c) = f(c, mesh.x[i]);
  Kokkos::deep_copy(aux, h);
  return aux;
}

template <class F>
Vector nodal_vector(const Mesh& mesh, int nc, F f, const char* label) {
  Vector v(std::string(label), nc * mesh.n_nodes());
  auto h = Kokkos::create_mirror_view(v);
  for (int i = 0; i < mesh.n_nodes(); ++i)
    for (int c = 0; c < nc; ++c) h(nc * i + c) = f(c, mesh.x[i]);
  Kokkos::deep_copy(v, h);
  return v;
}

// Each field's physics at a one-step-theta step (theta 0.66) of the given length.
inline TransportPhysics scalar_physics(double inv_dt = 1.0) {
  TransportPhysics p;
  p.coef.diffusivity[0] = 1e-2, p.coef.diffusivity[1] = 5e-3;
  p.coef.monod_rate[1] = 1.0, p.coef.monod_half_saturation[1] = 0.1;
  p.inv_dt = inv_dt, p.theta = 0.66, p.supg = true;
  return p;
}

inline StructurePhysics structure_physics(double dt = 0.01) {
  StructurePhysics p;
  p.materials.model[0] = SaintVenantKirchhoff, p.materials.model[1] = NeoHooke;
  p.materials.lambda[0] = 0.577, p.materials.mu[0] = 0.385;
  p.materials.lambda[1] = 1.55, p.materials.mu[1] = 0.172;
  p.materials.density[0] = 1.0, p.materials.density[1] = 1.2;
  p.dt = dt, p.theta = 0.66, p.mass_coefficient = 1.0 / (p.theta * dt * dt);
  return p;
}

inline FluidPhysics fluid_physics(double inv_dt = 20.0) {
  FluidPhysics p;
  p.density = 1.0, p.viscosity = 0.01, p.inv_dt = inv_dt, p.theta = 0.66;
  return p;
}

inline PseudoElasticPhysics mesh_motion_physics(const Mesh& mesh) {
  PseudoElasticPhysics p;
  p.lambda = 0.5, p.mu = 1.0, p.stiffening = 1.0;
  const double h = 1.0 / std::cbrt(double(mesh.n_elements()));
  p.reference_det = h * h * h / 8;
  return p;
}

inline NodalView field_aux(const Mesh& m, const TransportPhysics&) {
  return nodal_aux(m, TransportPhysics::n_aux, [](int c, const Point& x) {
    if (c == 0) return 0.5 + 0.25 * std::sin(3 * x[0]) * std::cos(2 * x[1]);
    if (c == 4) return x[1];
    if (c == 5) return 0.1 * std::sin(4 * x[0]);
    if (c == 6) return 0.2 * std::cos(3 * x[2]);
    return 0.0;
  });
}
// The structure's displacement: strains ~0.1, zero at the bottom.
inline Point structure_displacement(const Point& x) {
  return {0.05 * std::sin(3 * x[1]) * x[1], 0.04 * x[0] * x[1], 0.03 * std::cos(2 * x[2]) * x[1]};
}

inline NodalView field_aux(const Mesh& m, const StructurePhysics&) {
  return nodal_aux(m, StructurePhysics::n_aux, [](int c, const Point& x) {
    if (c < 3) return structure_displacement(x)[c];
    if (c == 3) return 0.1 * x[1];
    return 0.0;
  });
}
inline NodalView field_aux(const Mesh& m, const FluidPhysics&) {
  return nodal_aux(m, FluidPhysics::n_aux, [](int c, const Point& x) {
    if (c < 3) return 0.5 * std::sin(1.3 * x[0] + c) * std::cos(x[1] - 0.4 * x[2]);
    if (c < 6) return 0.05 * std::cos(x[0] + 2 * x[1] + c);
    return 0.0;
  });
}
inline NodalView field_aux(const Mesh& m, const PseudoElasticPhysics&) {
  return nodal_aux(m, 0, [](int, const Point&) { return 0.0; });
}

// Nodes per direction for about `dofs` unknowns of nc components.
inline int nodes_per_direction(double dofs, int nc) {
  return std::max(3, int(std::lround(std::cbrt(dofs / nc))));
}

// The state every field is linearised at unless a program gives its own: component c at x.
inline double field_state(int c, const Point& p) {
  return 0.02 * std::cos(2 * p[0] + c) * (1 + p[1]) + (c == 3 ? 0.1 * p[0] : 0.0);
}

inline std::vector<int> all_elements(const Mesh& mesh) {
  std::vector<int> all(mesh.n_elements());
  for (int e = 0; e < mesh.n_elements(); ++e) all[e] = e;
  return all;
}

// One field's operator on the cube, its state u and the matrix assembled at u (coloured scatter).
template <class Physics>
struct AssembledField {
  static constexpr int NC = Physics::n_components;
  int n_dofs = 0;
  Mesh mesh;
  DeviceMesh device;
  NodalView aux;
  std::unique_ptr<ElementOperator<Physics>> op;
  ElementGroups groups;
  CsrMatrix matrix;
  Vector u;

  AssembledField(int n, const Physics& physics, double distortion = deformed,
                 double (*state)(int, const Point&) = field_state)
      : mesh(deformed_cube(n, distortion)) {
    n_dofs = NC * mesh.n_nodes();
    device = to_device(mesh);
    aux = field_aux(mesh, physics);
    op = std::make_unique<ElementOperator<Physics>>(device.conn, device.x, device.element_block,
                                                    aux, physics);
    const std::vector<int> all = all_elements(mesh);
    groups = make_element_groups(mesh, all, Scatter::Colored);
    u = nodal_vector(mesh, NC, state, "bench::u");
    matrix = make_sparsity(mesh, all, NC);
    op->assemble(groups, u, matrix);
    Kokkos::fence();
  }
};

}  // namespace bench
}  // namespace biofsi
