// Shared set-up for the scalar transport verification tests: pseudo-2-D box meshes, the smooth
// boundary-preserving distortion, default solver settings and small host helpers.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"
#include "scalar/transport.hpp"

namespace biofsi {
namespace test {

constexpr double pi = 3.14159265358979323846;

// [0,1] x [y-blocks] x [0,thickness] with n elements along x, nz along z.
inline Mesh box_mesh(int nx, int nz, double thickness, const std::vector<BoxBlock>& blocks) {
  BoxSpec spec;
  spec.x0 = 0;
  spec.x1 = 1;
  spec.z0 = 0;
  spec.z1 = thickness;
  spec.nx = nx;
  spec.nz = nz;
  spec.blocks = blocks;
  return make_box_mesh(spec);
}

// A smooth, z-independent distortion of [0,1]^2 x [0, t] that keeps every side of the box on its
// plane and every node with y = 0.5 on the plane y = 0.5 (where the two-block meshes put their
// interface): x += 0.1 sin(pi x) sin(pi y), y += 0.05 sin(pi x) sin(2 pi y). Both maps stay
// monotone (min dx'/dx = 1 - 0.1 pi = 0.69, min dy'/dy = 1 - 0.1 pi = 0.69), so no element inverts,
// and the elements are non-affine at every refinement (the map does not flatten out as h -> 0).
inline void distort_smoothly(Mesh& mesh) {
  distort(mesh, [](const Point& p) {
    const double sx = std::sin(pi * p[0]);
    return Point{p[0] + 0.1 * sx * std::sin(pi * p[1]), p[1] + 0.05 * sx * std::sin(2 * pi * p[1]),
                 p[2]};
  });
}

// Settings with tight Newton tolerances, so that the algebraic error stays far below what a test
// measures (discretisation errors of 1e-6 and more, balances at 1e-10 relative).
inline TransportSettings tight_settings(double theta = 1.0, bool supg = true) {
  TransportSettings s;
  s.theta = theta;
  s.supg = supg;
  s.newton.rel_tol = 1e-12;
  // The library default: a floor near round-off for these problems, whose nodal residual terms are
  // 1e-4 or larger (without it, steps that start close to their solution could never meet
  // 1e-12 relative).
  s.newton.abs_tol = 1e-14;
  s.newton.max_iterations = 50;
  s.newton.krylov.max_iterations = 2000;
  return s;
}

inline ScalarBoundaryCondition dirichlet(const std::string& set, SpaceTimeFunction value) {
  ScalarBoundaryCondition bc;
  bc.set = set;
  bc.kind = ScalarBcKind::Dirichlet;
  bc.value = std::move(value);
  return bc;
}

inline std::vector<ScalarBoundaryCondition> dirichlet_on(const std::vector<std::string>& sets,
                                                         const SpaceTimeFunction& value) {
  std::vector<ScalarBoundaryCondition> out;
  for (const auto& s : sets) out.push_back(dirichlet(s, value));
  return out;
}

template <class F>
std::vector<Point> nodal_vectors(const Mesh& mesh, F f) {
  std::vector<Point> v(mesh.n_nodes());
  for (int n = 0; n < mesh.n_nodes(); ++n) v[n] = f(mesh.x[n]);
  return v;
}

inline double max_abs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

}  // namespace test
}  // namespace biofsi
