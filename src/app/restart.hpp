// The state a transient flow run's checkpoint holds, and its move onto another mesh of the same
// domain (a restart on a refined mesh). Used by the driver (run.cpp); depends on src/mesh.
#pragma once

#include <vector>

#include "mesh/mesh.hpp"

namespace biofsi {

// Nodal state of a flow run; a field the run does not have stays empty.
struct FlowState {
  std::vector<double> fluid;                            // (u, v, w, p) per node
  std::vector<Point> displacement, velocity;            // the structure's
  std::vector<Point> mesh_displacement, mesh_velocity;  // the fluid mesh's (FSI)
};

// The element blocks of each field, by block index (the same on both meshes: meshes of one scene
// list their blocks in one order).
struct FieldBlocks {
  std::vector<int> fluid, structure;
};

// `state` of mesh `from` interpolated at the nodes of mesh `to` in the reference configuration:
// the fluid's and the fluid mesh's fields from the fluid's elements, the structure's from its
// elements. On nodes that both fields share (the FSI interface) the fluid mesh follows the
// structure's displacement and the fluid its velocity, as on the mesh it was written on. A node
// of `to` outside `from`'s elements by more than a few per cent of an element is an error
// (std::runtime_error): the meshes do not cover the same domain. The velocity is not
// divergence-free on the new mesh; the first steps' pressure absorbs that.
FlowState transfer(const Mesh& from, const FlowState& state, const Mesh& to,
                   const FieldBlocks& blocks);

}  // namespace biofsi
