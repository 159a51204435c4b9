// src/ale/parameters.hpp: the mesh_motion section of a scene — its keys, their defaults (those of
// MeshMotionSettings) and checks. The growth step and the FSI fluid mesh both use it.
#pragma once

#include "ale/mesh_motion.hpp"
#include "io/scene_reader.hpp"

namespace biofsi {

MeshMotionSettings read_mesh_motion_section(const scene_input::Checker& c,
                                            const scene_input::Node& node,
                                            const scene_input::MeshNames& names);

// With inflow_outflow = Fixed, adds `inflow_outflow_sets` (the flow's inflow and outflow face
// sets) to the fixed walls; otherwise leaves the walls as they are.
void hold_inflow_outflow(MeshMotionSettings& settings,
                         const std::vector<std::string>& inflow_outflow_sets);

}  // namespace biofsi
