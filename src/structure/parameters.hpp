// src/structure/parameters.hpp: the fields.structure section of a scene — its keys, their
// defaults (those of StructureSettings) and checks — and its boundary conditions, made into the
// field's.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "io/scene_reader.hpp"
#include "structure/structure.hpp"

namespace biofsi {

// A structure boundary condition on a named face set: fixed (every displacement component zero)
// or displacement (3 expressions in x, y, z, t; "free" leaves a component free).
struct StructureBcSpec {
  std::string boundary;
  bool fixed = true;  // false: displacement
  std::array<std::string, 3> value = {"0", "0", "0"};
  int line = 0;  // 1-based line in the scene file, for messages
};

// The biofilm as an elastic body (paper eq. 1) on settings.blocks, loaded by the flow (FSI with
// the fluid field); other blocks' nodes are not part of it. settings.quasi_static is the scene's
// mode: dynamic (one-step-theta with time.theta) or quasi_static. Without a fluid field (and
// without the scalar and growth) the structure runs alone under its body force and boundary data.
struct StructureSection {
  bool enabled = false;  // true when the scene has a fields.structure section
  StructureSettings settings;
  std::vector<StructureBcSpec> boundary_conditions;
  // Body force per reference volume (3 expressions in x, y, z, t), e.g. gravity rho g; absent:
  // none.
  std::optional<std::array<std::string, 3>> body_force;
};

// Reads fields.structure (absent: the field is off) after fields.fluid, whose blocks the
// structure may not share; settings.materials come from `materials` in block order.
StructureSection read_structure_section(const scene_input::MapView& fields,
                                        const scene_input::MeshNames& names,
                                        const Materials& materials,
                                        const std::vector<std::string>& fluid_blocks);

std::vector<StructureDirichlet> structure_boundary_conditions(const StructureSection& section);
// The section's body force as the field takes it (section.body_force must be set).
std::array<SpaceTimeFunction, 3> structure_body_force(const StructureSection& section);

}  // namespace biofsi
