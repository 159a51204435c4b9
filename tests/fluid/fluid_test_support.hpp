// Shared set-up for the fluid verification tests: pseudo-2-D box meshes (from the scalar tests'
// helpers), settings with tight tolerances, random states and small host helpers.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "fluid/fluid.hpp"
#include "scalar/scalar_test_support.hpp"

namespace biofsi {
namespace test {

// Newton to 1e-12 relative: the algebraic error stays far below what a test measures.
inline FluidSettings tight_fluid_settings(double density, double viscosity) {
  FluidSettings s;
  s.density = density;
  s.viscosity = viscosity;
  s.pseudo_2d = true;
  s.newton_options.rel_tol = 1e-12;
  s.newton_options.abs_tol = 1e-13;
  s.newton_options.max_iterations = 30;
  s.newton_options.krylov.max_iterations = 1000;
  return s;
}

inline FluidFunction constant(double v) {
  return [v](const Point&, double) { return v; };
}

// An enclosed flow on the unit square: its four walls driven with velocity (ux, uy, 0) and the
// pressure level, which only a pin can fix, set at the "pin" node set.
inline std::vector<FluidBoundaryCondition> driven_walls(const FluidFunction& ux,
                                                        const FluidFunction& uy,
                                                        const FluidFunction& pin_pressure) {
  std::vector<FluidBoundaryCondition> bcs;
  for (const char* side : {"left", "right", "bottom", "top"})
    bcs.push_back(fluid_velocity(side, ux, uy, constant(0.0)));
  bcs.push_back(fluid_pressure("pin", pin_pressure));
  return bcs;
}

inline std::vector<double> random_values(int n, double lo, double hi, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> dist(lo, hi);
  std::vector<double> v(n);
  for (double& x : v) x = dist(gen);
  return v;
}

inline Vector device_vector(const std::vector<double>& v) {
  Vector d("test::v", v.size());
  auto h = Kokkos::create_mirror_view(d);
  for (size_t i = 0; i < v.size(); ++i) h(i) = v[i];
  Kokkos::deep_copy(d, h);
  return d;
}

inline std::vector<double> host_vector(ConstVector d) {
  auto h = Kokkos::create_mirror_view(d);
  Kokkos::deep_copy(h, d);
  return std::vector<double>(h.data(), h.data() + h.extent(0));
}

// Nodes of a mesh whose (x, y) lie within 1e-12 of a point: a pseudo-2-D "point" set through the
// thickness, e.g. to pin the pressure level.
inline std::vector<int> nodes_at(const Mesh& mesh, double x, double y) {
  std::vector<int> out;
  for (int n = 0; n < mesh.n_nodes(); ++n)
    if (std::abs(mesh.x[n][0] - x) < 1e-12 && std::abs(mesh.x[n][1] - y) < 1e-12) out.push_back(n);
  return out;
}

// Relative max-norm difference of two vectors.
inline double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0, s = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    d = std::max(d, std::abs(a[i] - b[i]));
    s = std::max(s, std::abs(b[i]));
  }
  return d / std::max(s, 1e-300);
}

}  // namespace test
}  // namespace biofsi
