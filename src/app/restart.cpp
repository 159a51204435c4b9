#include "app/restart.hpp"

#include "mesh/mesh_transfer.hpp"

namespace biofsi {

namespace {

std::vector<int> elements_of_blocks(const Mesh& mesh, const std::vector<int>& blocks) {
  std::vector<int> out;
  for (int b : blocks)
    for (int e : mesh.elements_of_block(b)) out.push_back(e);
  return out;
}

std::vector<char> nodes_of_blocks(const Mesh& mesh, const std::vector<int>& blocks) {
  std::vector<char> on(mesh.n_nodes(), 0);
  for (int b : blocks)
    for (int n : mesh.nodes_of_block(b)) on[n] = 1;
  return on;
}

}  // namespace

FlowState transfer(const Mesh& from, const FlowState& state, const Mesh& to,
                   const FieldBlocks& blocks) {
  const size_t n = to.n_nodes();
  const Point zero{0, 0, 0};
  FlowState out;
  std::vector<char> fluid_node(n, 0), structure_node(n, 0);
  if (!state.fluid.empty() || !state.mesh_displacement.empty()) {
    const NodalInterpolator fluid(from, elements_of_blocks(from, blocks.fluid));
    fluid_node = nodes_of_blocks(to, blocks.fluid);
    if (!state.fluid.empty()) out.fluid.assign(4 * n, 0.0);
    if (!state.mesh_displacement.empty()) {
      out.mesh_displacement.assign(n, zero);
      out.mesh_velocity.assign(n, zero);
    }
    for (size_t a = 0; a < n; ++a) {
      if (!fluid_node[a]) continue;
      const NodalWeights w = fluid.locate(to.x[a]);
      if (!state.fluid.empty()) {
        const auto& c = from.conn[w.element];
        for (int k = 0; k < 4; ++k) {
          double value = 0;
          for (int b = 0; b < 8; ++b) value += w.n[b] * state.fluid[4 * c[b] + k];
          out.fluid[4 * a + k] = value;
        }
      }
      if (!state.mesh_displacement.empty()) {
        out.mesh_displacement[a] = fluid.interpolate(w, state.mesh_displacement);
        out.mesh_velocity[a] = fluid.interpolate(w, state.mesh_velocity);
      }
    }
  }
  if (!state.displacement.empty()) {
    const NodalInterpolator structure(from, elements_of_blocks(from, blocks.structure));
    structure_node = nodes_of_blocks(to, blocks.structure);
    out.displacement.assign(n, zero);
    out.velocity.assign(n, zero);
    for (size_t a = 0; a < n; ++a) {
      if (!structure_node[a]) continue;
      const NodalWeights w = structure.locate(to.x[a]);
      out.displacement[a] = structure.interpolate(w, state.displacement);
      out.velocity[a] = structure.interpolate(w, state.velocity);
    }
  }
  // The interface: the fluid mesh moves with the structure and the fluid sticks to it (the fluid
  // mesh's velocity is the time scheme's difference quotient, not the structure's velocity).
  for (size_t a = 0; a < n; ++a) {
    if (!fluid_node[a] || !structure_node[a]) continue;
    if (!out.mesh_displacement.empty()) out.mesh_displacement[a] = out.displacement[a];
    if (!out.fluid.empty())
      for (int k = 0; k < 3; ++k) out.fluid[4 * a + k] = out.velocity[a][k];
  }
  return out;
}

}  // namespace biofsi
