// src/scalar/parameters.hpp: the fields.scalar section of a scene — its keys, their defaults
// (those of TransportSettings) and checks — and its boundary conditions, made into the field's.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "io/scene_reader.hpp"
#include "scalar/transport.hpp"

namespace biofsi {

// A scalar boundary condition on a named face/node set of the mesh.
//   dirichlet: phi = value(x, y, z, t)
//   neumann:   inward flux D grad(phi) . n_out = flux(x, y, z, t)  (positive: substrate enters)
//   robin:     inward flux D grad(phi) . n_out = coefficient * (ambient(x, y, z, t) - phi)
struct ScalarBcSpec {
  std::string boundary;
  ScalarBcKind kind = ScalarBcKind::Dirichlet;
  std::string value;       // dirichlet value, neumann flux, or robin ambient (expression)
  double coefficient = 0;  // robin only, >= 0
  int line = 0;            // 1-based line in the scene file, for messages
};

struct ScalarSection {
  bool enabled = true;
  std::string initial = "0";                              // expression
  std::array<std::string, 3> velocity = {"0", "0", "0"};  // convective velocity (expressions)
  TransportSettings settings;
  std::vector<ScalarBcSpec> boundary_conditions;
};

// Reads fields.scalar (absent: the defaults, without boundary conditions) after fields.structure:
// settings.coefficients come from `materials` in block order, with the material-motion term on
// the structure's blocks. A prescribed velocity is refused when the fluid convects the scalar.
ScalarSection read_scalar_section(const scene_input::MapView& fields,
                                  const scene_input::MeshNames& names, const Materials& materials,
                                  const std::vector<std::string>& deforming_blocks,
                                  bool fluid_enabled);

std::vector<ScalarBoundaryCondition> scalar_boundary_conditions(const ScalarSection& section);

}  // namespace biofsi
