// src/fluid/parameters.hpp: the fields.fluid section of a scene — its keys, their defaults (those
// of FluidSettings) and checks — and the boundary conditions it names, made into the field's.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "fluid/fluid.hpp"
#include "io/scene_reader.hpp"

namespace biofsi {

enum class FlowMode { Steady, Transient };  // transient: every inner step
// The state a transient flow starts from: at rest, or the steady flow (with FSI: the steady
// coupled state, the structure at equilibrium) for the boundary data at the start.
enum class FlowStart { Rest, Steady };
enum class FluidBcType { Velocity, NoSlip, Slip, Pressure, DoNothing };

// A fluid boundary condition on a named face set:
//   velocity:   u = value (3 expressions in x, y, z, t); no_slip: u = 0
//   slip:       u . n = 0 on a wall whose normal is a coordinate axis
//   pressure:   p = value[0]
//   do_nothing: the natural outflow condition (nothing is imposed)
struct FluidBcSpec {
  std::string boundary;
  FluidBcType type = FluidBcType::NoSlip;
  std::array<std::string, 3> value = {"0", "0", "0"};
  int line = 0;  // 1-based line in the scene file, for messages
};

// The fluid (paper eqs. 2-5) on settings.blocks; other blocks' nodes are held at rest (a rigid
// biofilm unless fields.structure makes it elastic). Its velocity convects the scalar, and its
// wall shear stress on the growth interface is sigma in eq. 11.
struct FluidSection {
  bool enabled = false;  // true when the scene has a fields.fluid section, unless enabled: false
  FlowMode mode = FlowMode::Steady;
  FlowStart initial = FlowStart::Rest;  // transient mode only
  FluidSettings settings;
  std::vector<FluidBcSpec> boundary_conditions;
  // Body force per volume (3 expressions in x, y, z, t), e.g. a pulse that seeds vortex
  // shedding; absent: none.
  std::optional<std::array<std::string, 3>> body_force;
};

// Reads fields.fluid (absent: the field is off). Time and solver settings are the scene's
// (src/io/scene.cpp) and are set afterwards.
FluidSection read_fluid_section(const scene_input::MapView& fields,
                                const scene_input::MeshNames& names);

std::vector<FluidBoundaryCondition> fluid_boundary_conditions(const FluidSection& section);
// The face sets through which the flow enters or leaves: those with a velocity, pressure or
// do_nothing condition, except `interface` (the moving wall of an FSI or growth run). None when
// the field is off.
std::vector<std::string> inflow_outflow_boundaries(const FluidSection& section,
                                                   const std::string& interface);
// The section's body force as the field takes it, per unit mass (section.body_force must be set).
FluidVectorFunction fluid_body_force(const FluidSection& section);

}  // namespace biofsi
