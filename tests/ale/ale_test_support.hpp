// Shared set-up for the mesh-motion verification tests (src/ale, kernels/ale): box meshes, a smooth
// fully 3-D distortion that keeps the boundary on the box, the pseudo-material that MeshMotion
// builds from its settings (host <-> device copies of flat vectors: kernels/small_mesh.hpp). Host
// code only: the device work happens inside the library (element loops, csr_multiply,
// csr_diagonal).
#pragma once

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "ale/mesh_motion.hpp"
#include "kernels/ale/pointwise.hpp"
#include "kernels/small_mesh.hpp"
#include "mesh/mesh.hpp"
#include "scalar/scalar_test_support.hpp"

namespace biofsi {
namespace test {

// box_mesh(nx, nz, thickness, blocks) is shared with the scalar tests.

// A smooth, fully 3-D map of the unit cube onto itself that keeps every side on its plane: each
// coordinate moves by amplitude * sin(pi x_i) times a function of the other two, so the normal
// displacement vanishes on every side while the tangential one does not (boundary nodes slide
// within their side). With amplitude a <= 0.06 each diagonal entry of the map's Jacobian is at
// least 1 - pi a = 0.81 and each row's off-diagonal sum at most 2 pi a = 0.38, so (Gershgorin) its
// determinant stays positive and no element inverts; the map does not flatten out as h -> 0, so
// every refinement has non-affine elements.
inline Point smooth_cube_map(const Point& p, double amplitude) {
  const double x = p[0], y = p[1], z = p[2], a = amplitude;
  return {x + a * std::sin(pi * x) * std::cos(1.3 * pi * y + 0.4) * std::cos(0.7 * pi * z),
          y + a * std::sin(pi * y) * std::cos(0.9 * pi * x + 0.3) * std::cos(1.1 * pi * z),
          z + a * std::sin(pi * z) * std::cos(1.2 * pi * x) * std::cos(0.8 * pi * y + 0.5)};
}

// The smallest det J at an element centre, where the hex8 map's columns are the mean
// half-edges along each reference direction (VTK corner order); written independently of
// src/ale's centre_jacobian.
inline double smallest_centre_det(const Mesh& mesh) {
  constexpr int edges[3][4][2] = {{{0, 1}, {3, 2}, {4, 5}, {7, 6}},
                                  {{0, 3}, {1, 2}, {4, 7}, {5, 6}},
                                  {{0, 4}, {1, 5}, {2, 6}, {3, 7}}};
  double smallest = 1e300;
  for (int e = 0; e < mesh.n_elements(); ++e) {
    double col[3][3] = {};
    for (int d = 0; d < 3; ++d)
      for (const auto& edge : edges[d])
        for (int k = 0; k < 3; ++k)
          col[d][k] += (mesh.x[mesh.conn[e][edge[1]]][k] - mesh.x[mesh.conn[e][edge[0]]][k]) / 8;
    const double det = col[0][0] * (col[1][1] * col[2][2] - col[1][2] * col[2][1]) -
                       col[0][1] * (col[1][0] * col[2][2] - col[1][2] * col[2][0]) +
                       col[0][2] * (col[1][0] * col[2][1] - col[1][1] * col[2][0]);
    smallest = std::min(smallest, det);
  }
  return smallest;
}

// The pseudo-material MeshMotion builds from its settings on `mesh` (E = 1, stiffening scaled to
// 1 on the smallest element): the Lame parameters of a Poisson ratio nu, written out here
// independently of src/ale.
inline PseudoElasticPhysics pseudo_material(double poisson_ratio, double stiffening,
                                            const Mesh& mesh) {
  const double nu = poisson_ratio;
  PseudoElasticPhysics p;
  p.lambda = nu / ((1 + nu) * (1 - 2 * nu));
  p.mu = 1 / (2 * (1 + nu));
  p.stiffening = stiffening;
  p.reference_det = smallest_centre_det(mesh);
  return p;
}

inline std::vector<int> all_elements(const Mesh& mesh) {
  std::vector<int> e(mesh.n_elements());
  for (int i = 0; i < mesh.n_elements(); ++i) e[i] = i;
  return e;
}

// Union of named node sets, sorted and unique.
inline std::vector<int> nodes_of_sets(const Mesh& mesh, const std::vector<std::string>& sets) {
  std::set<int> nodes;
  for (const auto& s : sets) nodes.insert(mesh.node_sets.at(s).begin(), mesh.node_sets.at(s).end());
  return std::vector<int>(nodes.begin(), nodes.end());
}

inline std::vector<int> boundary_nodes(const Mesh& mesh) {
  return nodes_of_sets(mesh, {"left", "right", "bottom", "top", "front", "back"});
}

// The mesh with every node moved by its displacement.
inline Mesh moved(const Mesh& mesh, const std::vector<Point>& d) {
  Mesh m = mesh;
  for (int n = 0; n < m.n_nodes(); ++n)
    for (int c = 0; c < 3; ++c) m.x[n][c] += d[n][c];
  return m;
}

}  // namespace test
}  // namespace biofsi
