// src/io: scene files (YAML), expressions in x, y, z, t, and results (HDF5 + XDMF).
// What it may include: src/mesh, yaml-cpp, muparser, HDF5. The driver (src/app) depends on it;
// fields and solvers do not.
#pragma once

#include <array>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace biofsi {

// Bad input: the message names file, line, key, the offending value and what was expected.
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Per-block material constants (units: mm, ms, concentration normalised to 1).
struct MaterialSpec {
  double diffusivity = 0;            // D > 0 [mm^2/ms]
  double monod_rate = 0;             // k >= 0 [1/ms]
  double monod_half_saturation = 0;  // K > 0 when k > 0 [-]
  // Elastic constants of a structure block (fields.structure); `elastic` says they were given.
  bool elastic = false;
  std::string model = "saint_venant_kirchhoff";  // or neo_hooke
  double youngs_modulus = 0;                     // E > 0 [mass/(mm ms^2)]
  double poisson_ratio = 0;                      // in (-1, 0.5)
  double density = 0;                            // rho >= 0 [mass/mm^3]
};

enum class BcType { Dirichlet, Neumann, Robin };

// A scalar boundary condition on a named face/node set of the mesh.
//   dirichlet: phi = value(x, y, z, t)
//   neumann:   inward flux D grad(phi) . n_out = flux(x, y, z, t)  (positive: substrate enters)
//   robin:     inward flux D grad(phi) . n_out = coefficient * (ambient(x, y, z, t) - phi)
struct ScalarBc {
  std::string boundary;
  BcType type = BcType::Dirichlet;
  std::string value;       // dirichlet value, neumann flux, or robin ambient (expression)
  double coefficient = 0;  // robin only, >= 0
  int line = 0;            // 1-based line in the scene file, for messages
};

struct ScalarFieldSpec {
  bool enabled = true;
  std::string initial = "0";                              // expression
  std::array<std::string, 3> velocity = {"0", "0", "0"};  // convective velocity (expressions)
  bool supg = true;
  std::vector<ScalarBc> boundary_conditions;
};

// A fluid boundary condition on a named face set:
//   velocity:   u = value (3 expressions in x, y, z, t); no_slip: u = 0
//   slip:       u . n = 0 on a wall whose normal is a coordinate axis
//   pressure:   p = value[0]
//   do_nothing: the natural outflow condition (nothing is imposed)
struct FluidBc {
  std::string boundary;
  std::string type;  // velocity | no_slip | slip | pressure | do_nothing
  std::array<std::string, 3> value = {"0", "0", "0"};
  int line = 0;
};

// The fluid (paper eqs. 2-5) on `blocks`; other blocks' nodes are held at rest (a rigid biofilm
// unless fields.structure makes it elastic). Its velocity convects the scalar, and its wall shear
// stress on the growth interface is sigma in eq. 11.
struct FluidFieldSpec {
  bool enabled = false;  // true when the scene has a fields.fluid section, unless enabled: false
  std::vector<std::string> blocks;
  double density = 1, viscosity = 1;      // > 0 [mass/mm^3], dynamic [mass/(mm ms)]
  std::string mode = "steady";            // steady | transient (every inner step)
  bool supg = true, grad_div = true;      // stabilisation terms besides PSPG
  bool transient_tau = true;              // tau_M with its (2/dt)^2 term
  bool pseudo_2d = false;                 // w = 0 everywhere (one element thick runs)
  bool symmetric_viscous = true;          // false: the grad u form (benchmarks' do-nothing outflow)
  std::string preconditioner = "simple";  // simple | simplec | monolithic_amg
  std::vector<FluidBc> boundary_conditions;
};

// A structure boundary condition on a named face set: fixed (every displacement component zero)
// or displacement (3 expressions in x, y, z, t; "free" leaves a component free).
struct StructureBc {
  std::string boundary;
  std::string type;  // fixed | displacement
  std::array<std::string, 3> value = {"0", "0", "0"};
  int line = 0;
};

// The biofilm as an elastic body (paper eq. 1) on `blocks`, loaded by the flow (FSI with the
// fluid field); other blocks' nodes are not part of it.
struct StructureFieldSpec {
  bool enabled = false;  // true when the scene has a fields.structure section
  std::vector<std::string> blocks;
  std::string mode = "dynamic";  // dynamic (one-step-theta with time.theta) | quasi_static
  bool plane_strain = false;     // z displacement zero everywhere (one element thick runs)
  std::vector<StructureBc> boundary_conditions;
};

// The monolithic coupling of structure, fluid and fluid mesh.
struct FsiSpec {
  std::string interface;                                // face set of Γ
  std::string shape_derivatives = "finite_difference";  // or none
  // Fluid-mesh walls; empty: those of mesh_motion.
  std::vector<std::string> fixed_walls, sliding_walls;
  bool walls_given = false;
  double rel_tol = 1e-8;
  int max_iterations = 25;
};

enum class TimeMode { Transient, Steady };

struct TimeSpec {
  TimeMode mode = TimeMode::Transient;
  double dt = 1;                // > 0
  int steps = 1;                // >= 1 (transient)
  double theta = 0.66;          // in [0.5, 1]
  double steady_tolerance = 0;  // stop early when max|phi_{n+1}-phi_n| / max|phi| < tol (0: never)
};

struct SolverSpec {
  double newton_rel_tol = 1e-10, newton_abs_tol = 1e-13;
  int newton_max_iterations = 25;
  double linear_rel_tol = 1e-8;
  int linear_max_iterations = 500;
  int linear_restart = 50;
  std::string scatter = "colored";  // colored | atomic
};

struct OutputSpec {
  std::string directory = "out";
  int every = 1;                              // write every N steps (and always the last)
  std::vector<std::string> flux_boundaries;   // report the consistent flux through these sets
  std::vector<std::string> force_boundaries;  // report the fluid's force on these sets
};

// The multi-scale growth loop (paper sections 4-5): after each inner loop (time.dt, time.steps,
// time.steady_tolerance) the interface moves by dt_bio (k1 J - k2 sigma) n.
struct GrowthSpec {
  bool enabled = false;                  // true when the scene has a growth section
  std::string interface;                 // face set of the biofilm-fluid interface
  std::string biofilm_block;             // the block that grows (owns the interface faces)
  double k1 = 0, k2 = 0;                 // >= 0
  double dt_bio = 0;                     // > 0 [ms]
  int steps = 0;                         // >= 1
  std::string averaging = "stationary";  // stationary | window
  int window = 1;                        // inner steps averaged when averaging = window
  int output_every = 1;                  // HDF5 every K growth steps (and the last)
  bool checkpoint = true;                // checkpoint after every growth step
};

// Pseudo-elastic mesh motion of the growth step.
struct MeshMotionSpec {
  double stiffening = 1.0;     // >= 0, exponent of (1/det J)
  double poisson_ratio = 0.3;  // in [0, 0.5)
  double min_quality = 0.02;   // in (0, 1): smallest scaled Jacobian accepted
  std::vector<std::string> sliding_walls = {"left", "right", "front", "back"};
  std::vector<std::string> fixed_walls = {"bottom", "top"};
};

struct Scene {
  std::string file;  // path the scene was read from
  // mesh: type "box" (the structured multi-block generator, `box`) or "gmsh" (a MSH 4.1 file,
  // `gmsh_file` resolved against the scene's folder; a 2-D file is extruded by `gmsh_thickness`).
  std::string mesh_type = "box";
  BoxSpec box;
  std::string gmsh_file;  // .msh (read) or .geo (meshed by gmsh with gmsh_parameters)
  double gmsh_thickness = 0;
  std::vector<std::pair<std::string, double>> gmsh_parameters;
  std::vector<std::string> block_names;           // of either kind of mesh, in block order
  std::map<std::string, MaterialSpec> materials;  // by block name; every block has one
  ScalarFieldSpec scalar;
  FluidFieldSpec fluid;
  StructureFieldSpec structure;
  FsiSpec fsi;
  TimeSpec time;
  SolverSpec solver;
  OutputSpec output;
  GrowthSpec growth;
  MeshMotionSpec mesh_motion;
};

// The scene's mesh (generated, or read from its Gmsh file).
Mesh make_scene_mesh(const Scene& scene);

// Reads and validates a scene. `overrides` are "dotted.key=value" strings (e.g. "time.dt=0.5",
// "mesh.blocks.1.ny=40") applied to the YAML tree before validation. Throws SceneError before any
// solve on unknown keys, wrong types, missing required values or non-physical values.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

// The same from a YAML string (tests); `file` is used in messages.
Scene parse_scene(const std::string& yaml_text, const std::string& file,
                  const std::vector<std::string>& overrides = {});

}  // namespace biofsi
