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

// How long each inner loop runs.
enum class InnerLoop {
  FixedSteps,      // exactly time.steps steps (the paper's 100), no stationarity test
  UntilStationary  // up to time.steps, ending at the first change below time.steady_tolerance
};

// What becomes the biofilm's reference configuration after a growth step (section 5 of the paper:
// the film is viscoelastic, so over a biological time step its elastic stresses relax).
enum class ReferenceUpdate {
  Reset,  // the deformed, grown shape: stress-free, elastic and fluid-mesh displacement zero
  Keep    // the undeformed reference grown: the elastic displacement (and its stress) carries on
};

struct GrowthSection {
  bool enabled = false;       // true when the scene has a growth section
  std::string biofilm_block;  // the block that grows (owns the interface faces)
  int steps = 0;              // >= 1
  GrowthAveraging averaging = GrowthAveraging::Stationary;
  int window = 1;  // inner steps averaged when averaging = window
  InnerLoop inner_loop = InnerLoop::UntilStationary;
  ReferenceUpdate reference_update = ReferenceUpdate::Reset;
  int output_every = 1;    // HDF5 every K growth steps (and the last)
  bool checkpoint = true;  // checkpoint after every growth step
  // interface_set, k1, k2, dt_bio; settings.mesh_motion is the scene's mesh_motion section.
  GrowthSettings settings;
};

// `stacked_blocks`: the box mesh's blocks bottom to top (empty for a Gmsh mesh), whose
// interfaces' faces belong to the block below. `inner_steps` and `steady_tolerance`: time.steps
// (the longest inner loop, which the window must fit) and time.steady_tolerance, which decides
// inner_loop's default (until_stationary when > 0, else fixed_steps) and must agree with it when
// inner_loop is given.
GrowthSection read_growth_section(const scene_input::Checker& c, const scene_input::Node& node,
                                  const scene_input::MeshNames& names,
                                  const std::vector<std::string>& stacked_blocks,
                                  const MeshMotionSettings& mesh_motion, int inner_steps,
                                  double steady_tolerance);

}  // namespace biofsi
