// src/growth/parameters.hpp: the growth section of a scene — the multi-scale loop (paper sections
// 4-5): after each inner loop (time.dt, time.steps, time.steady_tolerance) the interface moves by
// dt_bio (k1 J - k2 sigma) n. Its keys, their defaults and checks.
#pragma once

#include <string>

#include "growth/growth.hpp"
#include "io/scene_reader.hpp"

namespace biofsi {

// How the flux and shear that drive a growth step are taken from the inner loop.
enum class GrowthAveraging {
  Stationary,  // the inner loop's last state
  Window       // the mean over its last `window` steps
};

struct GrowthSection {
  bool enabled = false;       // true when the scene has a growth section
  std::string biofilm_block;  // the block that grows (owns the interface faces)
  int steps = 0;              // >= 1
  GrowthAveraging averaging = GrowthAveraging::Stationary;
  int window = 1;          // inner steps averaged when averaging = window
  int output_every = 1;    // HDF5 every K growth steps (and the last)
  bool checkpoint = true;  // checkpoint after every growth step
  // interface_set, k1, k2, dt_bio; settings.mesh_motion is the scene's mesh_motion section.
  GrowthSettings settings;
};

// `stacked_blocks`: the box mesh's blocks bottom to top (empty for a Gmsh mesh), whose
// interfaces' faces belong to the block below.
GrowthSection read_growth_section(const scene_input::Checker& c, const scene_input::Node& node,
                                  const scene_input::MeshNames& names,
                                  const std::vector<std::string>& stacked_blocks,
                                  const MeshMotionSettings& mesh_motion);

}  // namespace biofsi
