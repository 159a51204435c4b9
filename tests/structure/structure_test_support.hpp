// Shared set-up for the structure verification tests (src/structure, kernels/structure): materials,
// settings with tight solver tolerances, host <-> device copies (from the ale tests' support) and
// small host helpers. Host code only: the device work happens inside the library.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "ale/ale_test_support.hpp"
#include "structure/structure.hpp"

namespace biofsi {
namespace test {

inline StructureMaterial material(StructureModel model, double e, double nu, double rho = 0.0) {
  return StructureMaterial::from_young(model, e, nu, rho);
}

// Newton to 1e-10 relative (or round-off): the algebraic error then stays orders of magnitude
// below the discretisation errors and reference tolerances the tests measure (1e-6 and more).
inline StructureSettings tight_structure_settings(std::vector<StructureMaterial> materials,
                                                  bool quasi_static) {
  StructureSettings s;
  s.materials = std::move(materials);
  s.quasi_static = quasi_static;
  s.newton.rel_tol = 1e-10;
  s.newton.abs_tol = 1e-14;
  s.newton.max_iterations = 30;
  s.newton.krylov.max_iterations = 1000;
  s.newton.krylov.restart = 100;
  return s;
}

inline SpaceTimeFunction constant(double v) {
  return [v](const Point&, double) { return v; };
}

// Clamp (all three components zero) on a node set.
inline StructureDirichlet clamp(const std::string& set) {
  return {set, {constant(0), constant(0), constant(0)}};
}

inline double max_abs_difference(const HostVector& a, const HostVector& b) {
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

inline double norm(const HostVector& a) {
  double s = 0;
  for (double x : a) s += x * x;
  return std::sqrt(s);
}

}  // namespace test
}  // namespace biofsi
