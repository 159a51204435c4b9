// src/coupling/parameters.hpp: the fsi section of a scene — the monolithic coupling of
// fields.structure and fields.fluid, only with both. Its keys, their defaults (those of
// FsiSettings) and checks.
#pragma once

#include <string>

#include "coupling/fsi.hpp"
#include "fluid/parameters.hpp"
#include "io/scene_reader.hpp"

namespace biofsi {

// `coupled`: both the structure and the fluid are on (otherwise an fsi section is an error).
// The interface defaults to the growth interface (`growth_interface`, empty without growth); the
// fluid mesh's walls default to those of `mesh_motion`.
FsiSettings read_fsi_section(const scene_input::Checker& c, const scene_input::Node& node,
                             const scene_input::MeshNames& names, bool coupled,
                             const FluidSection& fluid, const std::string& growth_interface,
                             const MeshMotionSettings& mesh_motion);

}  // namespace biofsi
