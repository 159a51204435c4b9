// src/io: scene files (YAML), expressions in x, y, z, t, and results (HDF5 + XDMF).
// What it may include: src/mesh, yaml-cpp, muparser, HDF5, and each field's section reader
// (src/<field>/parameters.hpp, which may include io/scene_reader.hpp and io/expression.hpp). The
// driver (src/app) depends on it; fields and solvers do not.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "ale/parameters.hpp"
#include "coupling/parameters.hpp"
#include "fluid/parameters.hpp"
#include "growth/parameters.hpp"
#include "io/fidelity.hpp"
#include "io/scene_reader.hpp"
#include "mesh/mesh.hpp"
#include "scalar/parameters.hpp"
#include "structure/parameters.hpp"

namespace biofsi {

enum class TimeMode { Transient, Steady };

struct TimeSpec {
  TimeMode mode = TimeMode::Transient;
  double dt = 1;  // > 0; with stages, the first stage's
  int steps = 1;  // >= 1 (transient); with stages, their sum
  // Consecutive stretches of a flow run (no scalar field), each with its own step: e.g. a coarse
  // start-up, then the periodic state with a finer step. Without the `stages` key, one: {dt,
  // steps}.
  struct Stage {
    double dt;
    int steps;
    double theta;  // the fluid's and the structure's in this stage; time.theta unless given
  };
  std::vector<Stage> stages;
  double theta = 0.66;          // in [0.5, 1]
  double steady_tolerance = 0;  // stop early when max|phi_{n+1}-phi_n| / max|phi| < tol (0: never)
};

// The solver section: Newton and Krylov limits of the scalar transport, and the scatter of every
// field's element loops. Set into the fields' settings when the scene is read.
struct SolverSpec {
  double newton_rel_tol = 1e-10, newton_abs_tol = 1e-13;
  int newton_max_iterations = 25;
  double linear_rel_tol = 1e-8;
  int linear_max_iterations = 500;
  int linear_restart = 50;
  // Every field's and the coupling's Newton keeps its assembled preconditioner while it serves
  // (NewtonOptions::reuse_preconditioner, PreconditionerReuse).
  bool reuse_preconditioner = NewtonOptions{}.reuse_preconditioner;
  Scatter scatter = Scatter::Colored;
};

// A value recorded at every step of a flow run in series.csv: the mean over the mesh nodes at
// `point` (2 coordinates: every node at that x, y, through a pseudo-2-D mesh's thickness).
struct ProbeSpec {
  enum class Quantity { Displacement, Velocity, Pressure };
  std::string name;
  std::vector<double> point;
  Quantity quantity = Quantity::Displacement;
  int line = 0;  // 1-based line in the scene file, for messages
};

struct OutputSpec {
  std::string directory = "out";
  int every = 1;                              // write every N steps (and always the last)
  std::vector<std::string> flux_boundaries;   // report the consistent flux through these sets
  std::vector<std::string> force_boundaries;  // report the fluid's force on these sets
  // Flow runs (no scalar field) write series.csv, one row per step: the time, the fluid's force
  // on each force boundary and each probe's value, when there are any.
  std::vector<ProbeSpec> probes;
};

struct Scene {
  std::string file;         // path the scene was read from
  FidelityReport fidelity;  // the `fidelity` preset, already applied to what follows
  // mesh: type "box" (the structured multi-block generator, `box`) or "gmsh" (a MSH 4.1 file,
  // `gmsh_file` resolved against the scene's folder; a 2-D file is extruded by `gmsh_thickness`).
  std::string mesh_type = "box";
  BoxSpec box;
  std::string gmsh_file;  // .msh (read) or .geo (meshed by gmsh with gmsh_parameters)
  double gmsh_thickness = 0;
  std::vector<std::pair<std::string, double>> gmsh_parameters;
  // The blocks kept from the file (empty: all): a sub-mesh of them, its sets restricted to it.
  std::vector<std::string> gmsh_keep_blocks;
  // mesh.unions: face sets made as unions of the mesh's own (add_union_set), in scene order.
  std::vector<std::pair<std::string, std::vector<std::string>>> mesh_unions;
  std::vector<std::string> block_names;  // of either kind of mesh, in block order
  Materials materials;
  // Each field's section, with its settings complete: the time and solver sections' values (theta,
  // scatter, Newton limits) are set into them when the scene is read.
  ScalarSection scalar;
  FluidSection fluid;
  StructureSection structure;
  FsiSettings fsi;  // the fluid mesh's motion: the mesh_motion section, fsi walls if given
  TimeSpec time;
  SolverSpec solver;
  OutputSpec output;
  GrowthSection growth;  // settings.mesh_motion: the mesh_motion section
};

// The scene's mesh (generated, or read from its Gmsh file and cut to mesh.keep_blocks unless
// `keep_blocks` is false, with mesh.unions added, and the growth interface cut to its faces on the
// biofilm side: orient_interface); *reoriented receives the number of mirrored elements of a Gmsh
// file that were re-oriented (read_gmsh).
Mesh make_scene_mesh(const Scene& scene, int* reoriented = nullptr, bool keep_blocks = true);

// A scene file is a few kB; anything larger than this is refused before it is parsed.
constexpr size_t kMaxSceneBytes = 16u << 20;

// Reads and validates a scene. `overrides` are "dotted.key=value" strings (e.g. "time.dt=0.5",
// "mesh.blocks.1.ny=40") applied to the YAML tree before validation. Throws SceneError before any
// solve on unknown keys, wrong types, missing required values or non-physical values, on a path
// that is not a regular file and on a file larger than kMaxSceneBytes.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

// The same from a YAML string (tests); `file` is used in messages.
Scene parse_scene(const std::string& yaml_text, const std::string& file,
                  const std::vector<std::string>& overrides = {});

}  // namespace biofsi
