#include "growth/growth.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace biofsi {

namespace {

Point cross(const Point& a, const Point& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double dot3(const Point& a, const Point& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Index of a node in a sorted node list, -1 if absent.
int position(const std::vector<int>& sorted, int node) {
  const auto it = std::lower_bound(sorted.begin(), sorted.end(), node);
  return it != sorted.end() && *it == node ? static_cast<int>(it - sorted.begin()) : -1;
}

// The axis a wall's normal is aligned with; sliding is implemented for axis-aligned walls only.
int wall_axis(const Point& n, const std::string& set) {
  int axis = 0;
  for (int d = 1; d < 3; ++d)
    if (std::abs(n[d]) > std::abs(n[axis])) axis = d;
  if (std::abs(std::abs(n[axis]) - 1.0) > 1e-8)
    throw std::invalid_argument("growth: nodes can slide only along axis-aligned walls; set '" +
                                set + "' is not one");
  return axis;
}

}  // namespace

std::vector<Point> nodal_normals(const Mesh& mesh, const std::string& set) {
  const auto& nodes = mesh.node_sets.at(set);
  std::vector<Point> n(nodes.size(), Point{0, 0, 0});
  for (const auto& f : mesh.face_sets.at(set)) {
    int v[4];
    for (int k = 0; k < 4; ++k) v[k] = mesh.conn[f.element][hex8_face_nodes[f.local_face][k]];
    // Twice the area vector of the bilinear quad (diagonals' cross product).
    Point d1, d2, centre{0, 0, 0}, elem_centre{0, 0, 0};
    for (int c = 0; c < 3; ++c) {
      d1[c] = mesh.x[v[2]][c] - mesh.x[v[0]][c];
      d2[c] = mesh.x[v[3]][c] - mesh.x[v[1]][c];
    }
    Point a = cross(d1, d2);
    for (int k = 0; k < 4; ++k)
      for (int c = 0; c < 3; ++c) centre[c] += mesh.x[v[k]][c] / 4;
    for (int k = 0; k < 8; ++k)
      for (int c = 0; c < 3; ++c) elem_centre[c] += mesh.x[mesh.conn[f.element][k]][c] / 8;
    Point out{centre[0] - elem_centre[0], centre[1] - elem_centre[1], centre[2] - elem_centre[2]};
    const double sign = dot3(a, out) < 0 ? -0.5 : 0.5;  // orient outward; 0.5: area, not twice
    for (int k = 0; k < 4; ++k) {
      const int i = position(nodes, v[k]);
      for (int c = 0; c < 3; ++c) n[i][c] += sign * a[c] / 4;
    }
  }
  for (auto& v : n) {
    const double len = std::sqrt(dot3(v, v));
    if (len > 0)
      for (auto& c : v) c /= len;
  }
  return n;
}

InterfaceMotion interface_motion(const Mesh& mesh, const GrowthSettings& s,
                                 const std::vector<double>& flux_density,
                                 const std::vector<double>& shear_stress) {
  InterfaceMotion m;
  m.nodes = mesh.node_sets.at(s.interface_set);
  if (flux_density.size() != m.nodes.size() || shear_stress.size() != m.nodes.size())
    throw std::invalid_argument("growth: flux and shear must be given at every interface node");
  const auto normal = nodal_normals(mesh, s.interface_set);
  m.velocity.resize(m.nodes.size());
  m.displacement.resize(m.nodes.size());
  for (size_t i = 0; i < m.nodes.size(); ++i) {
    m.velocity[i] = s.k1 * flux_density[i] - s.k2 * shear_stress[i];
    for (int c = 0; c < 3; ++c) m.displacement[i][c] = s.dt_bio * m.velocity[i] * normal[i][c];
  }
  // Where the interface meets a sliding wall, remove the wall-normal component so the biofilm stays
  // attached to the wall.
  for (const auto& wall : s.sliding_walls) {
    if (!mesh.node_sets.count(wall)) continue;
    const auto& wall_nodes = mesh.node_sets.at(wall);
    const auto wall_normal = nodal_normals(mesh, wall);
    for (size_t i = 0; i < m.nodes.size(); ++i) {
      const int j = position(wall_nodes, m.nodes[i]);
      if (j >= 0) m.displacement[i][wall_axis(wall_normal[j], wall)] = 0;
    }
  }
  return m;
}

GrowthStepReport grow(Mesh& mesh, MeshMotion& motion, const GrowthSettings& s,
                      const InterfaceMotion& interface, const std::string& label) {
  MeshDisplacementBc bc;
  for (const auto& wall : s.fixed_walls)
    if (mesh.node_sets.count(wall)) bc.fix(mesh.node_sets.at(wall), {true, true, true});
  for (const auto& wall : s.sliding_walls) {
    if (!mesh.node_sets.count(wall)) continue;
    const auto& nodes = mesh.node_sets.at(wall);
    const auto normal = nodal_normals(mesh, wall);
    for (size_t j = 0; j < nodes.size(); ++j) {
      std::array<bool, 3> mask{false, false, false};
      mask[wall_axis(normal[j], wall)] = true;
      bc.fix({nodes[j]}, mask);
    }
  }
  for (size_t i = 0; i < interface.nodes.size(); ++i)
    bc.prescribe(interface.nodes[i], interface.displacement[i]);

  MeshMotionResult mr;
  const auto d = motion.solve(mesh, bc, label, &mr);
  Mesh moved = mesh;
  for (int n = 0; n < mesh.n_nodes(); ++n)
    for (int c = 0; c < 3; ++c) moved.x[n][c] += d[n][c];

  GrowthStepReport r;
  r.krylov_iterations = mr.krylov_iterations;
  r.quality = mesh_quality_by_block(moved);
  for (size_t b = 0; b < r.quality.size(); ++b)
    if (r.quality[b].min < s.min_quality) {
      std::ostringstream why;
      why << "element " << r.quality[b].worst_element << " of block '" << mesh.block_names[b]
          << "' would get scaled Jacobian " << r.quality[b].min
          << (r.quality[b].min <= 0 ? " (inverted)" : " (degenerate)") << ", below min_quality "
          << s.min_quality << "; the mesh was not moved";
      throw SolveError("growth", label, why.str());
    }
  double sum = 0;
  for (const auto& v : interface.displacement) {
    r.max_interface_displacement = std::max(r.max_interface_displacement, std::sqrt(dot3(v, v)));
    sum += v[1];
  }
  r.mean_interface_displacement =
      interface.displacement.empty() ? 0 : sum / interface.displacement.size();
  mesh = std::move(moved);
  return r;
}

}  // namespace biofsi
