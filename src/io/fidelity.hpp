// src/io/fidelity: the scene key `fidelity: draft | standard | fine`. A preset scales the scene's
// mesh resolution (box: nx, each block's ny, nz where it is above 1; Gmsh .geo: the `refine`
// parameter) by a factor read off the measured speed-accuracy study (docs/speed-accuracy.md,
// bench/run_tradeoff), and says what error and time that study measured for the scene. It works on
// the YAML tree before the scene is read, after the --set overrides, so what it changes is checked
// like the file itself and a --set of a mesh count is scaled too. What it may include:
// src/io/scene_reader.hpp. src/io/scene.cpp calls it; src/app prints its report.
#pragma once

#include <string>
#include <vector>

#include "io/scene_reader.hpp"

namespace biofsi {

struct FidelityReport {
  std::string level;                 // draft, standard or fine; empty: the scene has no preset
  double mesh_factor = 1;            // what multiplied the mesh's division counts
  std::vector<std::string> changes;  // "mesh.nx: 40 -> 20", one per changed key
  // The measured error and time of this preset on this scene (matched by the scene's file name),
  // or a sentence saying that none is known.
  std::string expected;
};

// Reads and applies root["fidelity"] (absent: nothing changes, an empty report). A value other
// than draft, standard or fine stops with the checker's message.
FidelityReport apply_fidelity(scene_input::Node& root, const scene_input::Checker& c);

// The run's start-up lines about the preset (empty when the scene has none).
std::string describe_fidelity(const FidelityReport& report);

}  // namespace biofsi
