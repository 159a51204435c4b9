#include "growth/growth.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace biofsi {

std::string orient_interface(Mesh& mesh, const std::string& set, int biofilm) {
  std::vector<BoundaryFace> faces = faces_of_block(mesh, set, biofilm);
  if (faces.empty())
    return "the face set has no face of a '" + mesh.block_names.at(biofilm) +
           "' element (it does not bound the biofilm block)";
  mesh.face_sets[set] = std::move(faces);
  const WeakestNormal w = weakest_nodal_normal(mesh, set);
  if (w.ratio >= kMinInterfaceNormalRatio) return "";
  const Point& p = mesh.x[w.node];
  std::ostringstream why;
  why << "the normals of its faces on the biofilm side nearly cancel at node (" << p[0] << ", "
      << p[1] << ", " << p[2] << "): |nodal normal| / |face normal| = " << w.ratio << " < "
      << kMinInterfaceNormalRatio << ", so the growth direction there is undefined";
  return why.str();
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
  for (const auto& wall : s.mesh_motion.sliding_walls) {
    if (!mesh.node_sets.count(wall)) continue;
    const auto& wall_nodes = mesh.node_sets.at(wall);
    const auto wall_normal = nodal_normals(mesh, wall);
    for (size_t i = 0; i < m.nodes.size(); ++i) {
      const int j = position_in_sorted(wall_nodes, m.nodes[i]);
      if (j >= 0) m.displacement[i][wall_axis(wall_normal[j], wall)] = 0;
    }
  }
  return m;
}

GrowthStepReport grow(Mesh& mesh, MeshMotion& motion, const GrowthSettings& s,
                      const InterfaceMotion& interface, const std::string& label) {
  MeshDisplacementBc bc =
      wall_constraints(mesh, s.mesh_motion.fixed_walls, s.mesh_motion.sliding_walls);
  for (size_t i = 0; i < interface.nodes.size(); ++i)
    bc.prescribe(interface.nodes[i], interface.displacement[i]);

  MeshMotionResult mr;
  const auto d = motion.solve(mesh, bc, label, &mr);
  Mesh moved = mesh;
  for (int n = 0; n < mesh.n_nodes(); ++n)
    for (int c = 0; c < 3; ++c) moved.x[n][c] += d[n][c];

  GrowthStepReport r;
  r.krylov_iterations = mr.krylov_iterations;
  r.preconditioner_set_up = mr.preconditioner_set_up;
  r.quality = mesh_quality_by_block(moved);
  for (size_t b = 0; b < r.quality.size(); ++b)
    if (r.quality[b].min < s.mesh_motion.min_quality) {
      std::ostringstream why;
      why << "element " << r.quality[b].worst_element << " of block '" << mesh.block_names[b]
          << "' would get scaled Jacobian " << r.quality[b].min
          << (r.quality[b].min <= 0 ? " (inverted)" : " (degenerate)") << ", below min_quality "
          << s.mesh_motion.min_quality << "; the mesh was not moved";
      throw SolveError("growth", label, why.str());
    }
  double sum = 0;
  for (const auto& v : interface.displacement) {
    r.max_interface_displacement =
        std::max(r.max_interface_displacement, std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
    sum += v[1];
  }
  r.mean_interface_displacement =
      interface.displacement.empty() ? 0 : sum / interface.displacement.size();
  mesh = std::move(moved);
  return r;
}

}  // namespace biofsi
