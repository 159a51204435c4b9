#include "io/scene.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include "io/expression.hpp"
#include "mesh/gmsh.hpp"

namespace biofsi {

using namespace scene_input;

namespace {

bool valid_block_name(const std::string& s) {
  if (s.empty()) return false;
  for (char ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_') return false;
  return true;
}

// mesh: {type: gmsh, file: <path relative to the scene>, thickness: <for a 2-D file>}. The file is
// read here, so that a bad mesh and unknown set names are reported before anything runs.
std::set<std::string> read_gmsh_mesh(const Checker& c, const MapView& m, Scene& scene, Mesh& mesh) {
  const std::string expected = "the path of a MSH 4.1 ASCII file, relative to the scene file";
  const Node file = m.require("file", expected);
  const std::string name = string_value(c, file, m.key("file"), expected);
  std::filesystem::path path(name);
  if (path.is_relative()) path = std::filesystem::path(c.file()).parent_path() / path;
  scene.gmsh_file = path.lexically_normal().string();
  scene.gmsh_thickness = get_number(
      m, "thickness", [](double v) { return v > 0; },
      "a number > 0 [mm] (the hex layer a 2-D mesh is extruded into)", 0.0);
  const bool geo = path.extension() == ".geo";
  if (auto p = m.get("parameters")) {
    const std::string p_expected = "a map of gmsh -setnumber parameters, e.g. {refine: 2}";
    if (!geo)
      c.fail(*p, m.key("parameters"), "parameters are for a .geo file", render(*p),
             "a .geo mesh file, or no parameters");
    if (!p->IsMap()) c.wrong_type(*p, m.key("parameters"), p_expected);
    for (auto it = p->begin(); it != p->end(); ++it) {
      const std::string pname = it->first.as<std::string>();
      scene.gmsh_parameters.emplace_back(
          pname, number(
                     c, it->second, child_key(m.key("parameters"), pname),
                     [](double v) { return std::isfinite(v); }, p_expected));
    }
  }
  try {
    mesh = make_scene_mesh(scene, nullptr, false);
  } catch (const MeshFileError& e) {
    c.fail(file, m.key("file"), std::string("cannot use the mesh (") + e.what() + ")", name,
           expected +
               " (.msh, or .geo meshed by gmsh) with hexahedra, or quadrilaterals and "
               "mesh.thickness");
  }
  if (m.get("keep_blocks")) {
    scene.gmsh_keep_blocks = block_list(m, "keep_blocks", mesh.block_names, "the blocks kept");
    mesh = submesh(mesh, scene.gmsh_keep_blocks);
  }
  for (const auto& b : mesh.block_names)
    if (!valid_block_name(b))
      c.fail(file, m.key("file"), "a physical group has an invalid block name", b,
             "names of letters, digits and underscores");
  scene.block_names = mesh.block_names;
  std::set<std::string> sets;
  for (const auto& [set, faces] : mesh.face_sets) sets.insert(set);
  return sets;
}

void read_box_mesh(const Checker& c, const MapView& m, Scene& scene);
std::set<std::string> read_box_face_sets(const Checker& c, const MapView& m, Scene& scene,
                                         Mesh& mesh);
void read_unions(const Checker& c, const MapView& m, Scene& scene,
                 std::set<std::string>& face_sets);

// Returns the names of the mesh's face sets; `mesh` receives the mesh they were read from (for a
// box, a copy one element thick), with the unions added.
std::set<std::string> read_mesh(const Checker& c, const Node& node, Scene& scene, Mesh& mesh) {
  MapView m(c, node, "mesh",
            {"type", "x", "z", "nx", "nz", "blocks", "file", "thickness", "parameters",
             "keep_blocks", "unions"});
  scene.mesh_type = get_choice(m, "type", {"box", "gmsh"}, std::nullopt);
  const std::vector<std::string> box_keys = {"x", "z", "nx", "nz", "blocks"},
                                 gmsh_keys = {"file", "thickness", "parameters", "keep_blocks"};
  for (const auto& key : scene.mesh_type == "box" ? gmsh_keys : box_keys)
    if (auto n = m.get(key))
      c.fail(*n, m.key(key), "not a key of a " + scene.mesh_type + " mesh", key,
             "the keys " + join_list(scene.mesh_type == "box" ? box_keys : gmsh_keys));
  std::set<std::string> face_sets = scene.mesh_type == "gmsh"
                                        ? read_gmsh_mesh(c, m, scene, mesh)
                                        : read_box_face_sets(c, m, scene, mesh);
  read_unions(c, m, scene, face_sets);
  for (const auto& [name, sets] : scene.mesh_unions) add_union_set(mesh, sets, name);
  return face_sets;
}

// mesh.unions: {name: [face set, ...]}, derived sets (e.g. a body made of two walls, whose force
// then counts the nodes they share once).
void read_unions(const Checker& c, const MapView& m, Scene& scene,
                 std::set<std::string>& face_sets) {
  auto unions = m.get("unions");
  if (!unions) return;
  const std::string expected = "a map {name: [face set, ...]} of unions of the mesh's face sets";
  if (!unions->IsMap()) c.wrong_type(*unions, m.key("unions"), expected);
  for (auto it = unions->begin(); it != unions->end(); ++it) {
    const std::string name = it->first.as<std::string>();
    const std::string key = child_key(m.key("unions"), name);
    if (!valid_block_name(name) || face_sets.count(name))
      c.fail(it->second, key, "not a new set name", name,
             "a name of letters, digits and underscores that the mesh does not have");
    scene.mesh_unions.emplace_back(name, face_set_list(c, it->second, key, face_sets));
  }
  for (const auto& u : scene.mesh_unions) face_sets.insert(u.first);
}

// The face-set names of a box mesh.
std::set<std::string> read_box_face_sets(const Checker& c, const MapView& m, Scene& scene,
                                         Mesh& mesh) {
  const Node& node = m.node();
  read_box_mesh(c, m, scene);
  for (const auto& b : scene.box.blocks) scene.block_names.push_back(b.name);
  // Face-set names depend only on the block names, not on the resolution: a one-element-thick
  // copy names every set at negligible cost whatever the scene's size.
  BoxSpec coarse = scene.box;
  coarse.nx = coarse.nz = 1;
  for (auto& b : coarse.blocks) b.ny = 1;
  std::set<std::string> face_sets;
  try {
    mesh = make_box_mesh(coarse);
    for (const auto& [name, faces] : mesh.face_sets) face_sets.insert(name);
  } catch (const std::invalid_argument& e) {
    c.fail(node, "mesh", e.what(), std::nullopt, "a valid box mesh");
  }
  return face_sets;
}

void read_box_mesh(const Checker& c, const MapView& m, Scene& scene) {
  const Node& node = m.node();
  BoxSpec& box = scene.box;
  std::tie(box.x0, box.x1) = get_interval(m, "x");
  std::tie(box.z0, box.z1) = get_interval(m, "z");
  box.nx = get_int(m, "nx", 1, std::nullopt);
  box.nz = get_int(m, "nz", 1, std::nullopt);

  const std::string list_expected = "a list of 1 to 8 blocks stacked along y, bottom to top";
  const Node blocks = m.require("blocks", list_expected);
  if (!blocks.IsSequence()) c.wrong_type(blocks, m.key("blocks"), list_expected);
  if (blocks.size() < 1 || blocks.size() > 8)
    c.fail(blocks, m.key("blocks"),
           "wrong number of blocks (" + std::to_string(blocks.size()) + ")", render(blocks),
           list_expected);
  std::set<std::string> names;
  for (size_t i = 0; i < blocks.size(); ++i) {
    MapView b(c, blocks[i], index_key(m.key("blocks"), i), {"name", "y", "ny", "grading"});
    BoxBlock blk;
    const std::string name_expected = "a unique name of letters, digits and underscores";
    const Node name = b.require("name", name_expected);
    blk.name = string_value(c, name, b.key("name"), name_expected);
    if (!valid_block_name(blk.name))
      c.fail(name, b.key("name"), "invalid name", blk.name, name_expected);
    if (!names.insert(blk.name).second)
      c.fail(name, b.key("name"), "duplicate block name", blk.name, name_expected);
    std::tie(blk.y0, blk.y1) = get_interval(b, "y");
    blk.ny = get_int(b, "ny", 1, std::nullopt);
    blk.grading = get_number(
        b, "grading", [](double v) { return v > 0; },
        "a number > 0 (last over first element height)", 1.0);
    if (i > 0) {
      const BoxBlock& prev = box.blocks.back();
      // The same tolerance as make_box_mesh, which would otherwise reject the spec later.
      if (std::abs(blk.y0 - prev.y1) > 1e-12 * (1 + std::abs(blk.y0))) {
        char y1[32];
        *std::to_chars(y1, y1 + sizeof y1 - 1, prev.y1).ptr = '\0';
        c.fail(*b.get("y"), b.key("y"), "blocks are not contiguous", render(*b.get("y")),
               std::string("y0 = ") + y1 + " (where block '" + prev.name + "' ends)");
      }
    }
    box.blocks.push_back(blk);
  }

  // Node ids are ints throughout; a larger mesh would overflow them silently.
  long long ny_total = 0;
  for (const auto& b : box.blocks) ny_total += b.ny;
  const long long n_nodes = (box.nx + 1LL) * (ny_total + 1) * (box.nz + 1LL);
  if (n_nodes > 2147483647LL)
    c.fail(node, "mesh", "too many nodes", std::to_string(n_nodes) + " nodes",
           "at most 2147483647 nodes (nx, nz and the blocks' ny)");
  // Refused here, not when the mesh is built: a box larger than memory would otherwise be
  // allocated until the system runs out.
  const std::string memory = memory_shortfall(n_nodes);
  if (!memory.empty())
    c.fail(node, "mesh", "the mesh does not fit in memory: " + memory,
           std::to_string(n_nodes) + " nodes", "a mesh that fits (nx, nz and the blocks' ny)");

  // Face-set names are built from block names; two sources of one name would merge two
  // boundaries silently (e.g. blocks "a" and "left": "a_left" is both a's side and the interface).
  std::map<std::string, std::string> source;
  auto claim = [&](const std::string& set, const std::string& from, size_t block) {
    auto [it, fresh] = source.emplace(set, from);
    if (!fresh) {
      const std::string key = index_key(m.key("blocks"), block) + ".name";
      c.fail(blocks[block]["name"], key,
             "block names give two face sets named '" + set + "' (" + it->second + " and " + from +
                 ")",
             box.blocks[block].name, "names whose face sets do not collide");
    }
  };
  for (const char* s : {"left", "right", "bottom", "top", "front", "back"})
    source.emplace(s, std::string("the box's ") + s);
  for (size_t i = 0; i < box.blocks.size(); ++i) {
    const std::string& bn = box.blocks[i].name;
    for (const char* s : {"left", "right", "front", "back"})
      claim(bn + "_" + s, "block '" + bn + "' " + s, i);
    if (i + 1 < box.blocks.size())
      claim(bn + "_" + box.blocks[i + 1].name, "the interface above block '" + bn + "'", i);
  }
}

void read_materials(const Checker& c, const Node& node, Scene& scene) {
  const std::vector<std::string>& blocks = scene.block_names;
  const std::string expected = "a map with one material per block (" + join_list(blocks) + ")";
  if (!node.IsMap()) c.wrong_type(node, "materials", expected);
  std::set<std::string> seen;
  for (auto it = node.begin(); it != node.end(); ++it) {
    const Node k = it->first;
    const std::string name = k.IsScalar() ? k.Scalar() : render(k);
    const std::string key = child_key("materials", name);
    if (std::find(blocks.begin(), blocks.end(), name) == blocks.end())
      c.fail(k, key, "material for an unknown block", name,
             "one of the blocks " + join_list(blocks));
    if (!seen.insert(name).second) c.fail(k, key, "duplicate key", name, "each block once");
    MapView m(c, it->second, key,
              {"diffusivity", "monod_rate", "monod_half_saturation", "model", "youngs_modulus",
               "poisson_ratio", "density"},
              "a map with diffusivity [mm^2/ms], optional Monod and elastic constants");
    MaterialSpec mat;
    mat.diffusivity = get_number(
        m, "diffusivity", [](double v) { return v > 0; }, "a number > 0 [mm^2/ms]", std::nullopt);
    mat.monod_rate = get_number(
        m, "monod_rate", [](double v) { return v >= 0; }, "a number >= 0 [1/ms]", 0.0);
    const std::string k_expected = "a number > 0 (Monod half-saturation concentration)";
    if (m.get("monod_half_saturation"))
      mat.monod_half_saturation = get_number(
          m, "monod_half_saturation", [](double v) { return v > 0; }, k_expected, std::nullopt);
    else if (mat.monod_rate > 0)
      m.missing("monod_half_saturation", k_expected, " (monod_rate > 0 needs it)");
    // Elastic constants, for a block of fields.structure: all of E, nu and rho, or none.
    const bool any_elastic =
        m.get("youngs_modulus") || m.get("poisson_ratio") || m.get("density") || m.get("model");
    if (any_elastic) {
      mat.elastic = true;
      mat.neo_hooke = get_enum(m, "model", {{"saint_venant_kirchhoff", false}, {"neo_hooke", true}},
                               std::optional<bool>(false));
      mat.youngs_modulus = get_number(
          m, "youngs_modulus", [](double v) { return v > 0; },
          "a number > 0 [mass/(mm ms^2)] (elastic constants need E, nu and rho)", std::nullopt);
      mat.poisson_ratio = get_number(
          m, "poisson_ratio", [](double v) { return v > -1 && v < 0.5; },
          "a number in (-1, 0.5) (elastic constants need E, nu and rho)", std::nullopt);
      mat.density = get_number(
          m, "density", [](double v) { return v >= 0; },
          "a number >= 0 [mass/mm^3] (elastic constants need E, nu and rho)", std::nullopt);
    }
    scene.materials[name] = mat;
  }
  for (const auto& b : blocks)
    if (!seen.count(b))
      c.fail(node, child_key("materials", b),
             "missing required key (block '" + b + "' has no material)", std::nullopt,
             "a map with diffusivity [mm^2/ms] and optional Monod constants");
}

// fields: fluid first, then the structure (which may not share its blocks), then the scalar (whose
// material-motion term lives on the structure's blocks).
void read_fields(const Checker& c, const Node& node, const MeshNames& names, Scene& scene) {
  MapView f(c, node, "fields", {"scalar", "fluid", "structure"});
  scene.fluid = read_fluid_section(f, names);
  scene.structure = read_structure_section(f, names, scene.materials, scene.fluid.settings.blocks);
  if (scene.structure.enabled) {
    const Node node = *f.get("structure");
    if (scene.fluid.enabled && scene.fluid.mode == FlowMode::Steady &&
        !scene.structure.settings.quasi_static) {
      const MapView m(
          c, node, f.key("structure"),
          {"enabled", "blocks", "mode", "plane_strain", "body_force", "boundary_conditions"});
      c.fail(m.get("mode").value_or(node), m.key("mode"), "a dynamic structure in a steady flow",
             "dynamic",
             "quasi_static (the steady coupled problem), or fields.fluid.mode: transient");
    }
  }
  scene.scalar = read_scalar_section(
      f, names, scene.materials,
      scene.structure.enabled ? scene.structure.settings.blocks : std::vector<std::string>{},
      scene.fluid.enabled);
}

bool valid_theta(double v) { return v >= 0.5 && v <= 1; }

// time.stages, after time.theta (each stage's default).
std::vector<TimeSpec::Stage> read_stages(const Checker& c, const Node& node, const MapView& time,
                                         const Scene& scene) {
  const std::string key = time.key("stages");
  const std::string expected = "a list of stages {dt, steps, theta (optional)}";
  for (const char* other : {"dt", "steps"})
    if (auto n = time.get(other); n && !n->IsNull())
      c.fail(*n, time.key(other), "dt and steps beside stages", render(*n),
             "either dt and steps, or stages");
  if (!node.IsSequence() || node.size() == 0) c.wrong_type(node, key, expected);
  if (node.size() > 1 && (scene.scalar.enabled || scene.growth.enabled))
    c.fail(node, key, "stages in a scene with the scalar field", render(node),
           "one dt for the inner loop (time.dt and time.steps): stages are for flow runs");
  std::vector<TimeSpec::Stage> stages;
  for (size_t i = 0; i < node.size(); ++i) {
    MapView s(c, node[i], index_key(key, i), {"dt", "steps", "theta"},
              "a map {dt, steps, theta (optional)}");
    stages.push_back(
        {get_number(
             s, "dt", [](double v) { return v > 0; }, "a finite number > 0", std::nullopt),
         get_int(s, "steps", 1, std::nullopt),
         get_number(s, "theta", valid_theta, "a number in [0.5, 1]", scene.time.theta)});
  }
  return stages;
}

void read_time(const Checker& c, const Node& node, Scene& scene) {
  MapView m(c, node, "time", {"mode", "dt", "steps", "stages", "theta", "steady_tolerance"});
  TimeSpec& t = scene.time;
  const bool transient = get_choice(m, "mode", {"transient", "steady"}, "transient") == "transient";
  t.mode = transient ? TimeMode::Transient : TimeMode::Steady;
  t.theta = get_number(m, "theta", valid_theta, "a number in [0.5, 1]", t.theta);
  if (auto stages = m.get("stages")) {
    t.stages = read_stages(c, *stages, m, scene);
    t.dt = t.stages.front().dt;
    // Each stage's steps fit an int; their sum need not (it once overflowed).
    long long steps = 0;
    for (const auto& s : t.stages) steps += s.steps;
    if (steps > std::numeric_limits<int>::max())
      c.fail(*stages, m.key("stages"), "too many steps in all", std::to_string(steps) + " steps",
             "at most " + std::to_string(std::numeric_limits<int>::max()) +
                 " steps in all stages together");
    t.steps = static_cast<int>(steps);
  } else {
    t.dt = get_number(
        m, "dt", [](double v) { return v > 0; }, "a finite number > 0 [ms]",
        transient ? std::nullopt : std::optional<double>(t.dt));
    t.steps = get_int(m, "steps", 1, transient ? std::nullopt : std::optional<int>(t.steps));
    t.stages = {{t.dt, t.steps, t.theta}};
  }
  t.steady_tolerance = get_number(
      m, "steady_tolerance", [](double v) { return v >= 0; }, "a number >= 0", t.steady_tolerance);
}

void read_solver(const Checker& c, const Node& node, Scene& scene) {
  MapView m(c, node, "solver", {"newton", "linear", "scatter", "reuse_preconditioner"});
  SolverSpec& s = scene.solver;
  auto positive = [](double v) { return v > 0; };
  const std::string tol = "a number > 0";
  MapView newton(c, m.get("newton").value_or(Node()), m.key("newton"),
                 {"rel_tol", "abs_tol", "max_iterations"});
  s.newton_rel_tol = get_number(newton, "rel_tol", positive, tol, s.newton_rel_tol);
  s.newton_abs_tol = get_number(newton, "abs_tol", positive, tol, s.newton_abs_tol);
  s.newton_max_iterations = get_int(newton, "max_iterations", 1, s.newton_max_iterations);
  MapView linear(c, m.get("linear").value_or(Node()), m.key("linear"),
                 {"rel_tol", "max_iterations", "restart"});
  s.linear_rel_tol = get_number(linear, "rel_tol", positive, tol, s.linear_rel_tol);
  s.linear_max_iterations = get_int(linear, "max_iterations", 1, s.linear_max_iterations);
  s.linear_restart = get_int(linear, "restart", 1, s.linear_restart);
  s.reuse_preconditioner = get_bool(m, "reuse_preconditioner", s.reuse_preconditioner);
  s.scatter = get_enum(m, "scatter", {{"colored", Scatter::Colored}, {"atomic", Scatter::Atomic}},
                       std::optional<Scatter>(s.scatter));
}

std::vector<ProbeSpec> read_probes(const Checker& c, const Node& node, const std::string& key,
                                   const Scene& scene) {
  const std::string list_expected = "a list of probes {name, point, quantity}";
  if (!node.IsSequence()) c.wrong_type(node, key, list_expected);
  std::vector<ProbeSpec> probes;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string ikey = index_key(key, i);
    MapView m(c, node[i], ikey, {"name", "point", "quantity"}, "a map {name, point, quantity}");
    ProbeSpec p;
    p.line = line_of(node[i], 0);
    const std::string name_expected = "a name of letters, digits and underscores (a CSV column)";
    const Node name = m.require("name", name_expected);
    p.name = string_value(c, name, m.key("name"), name_expected);
    if (!valid_block_name(p.name))
      c.fail(name, m.key("name"), "invalid name", p.name, name_expected);
    for (const auto& q : probes)
      if (q.name == p.name)
        c.fail(name, m.key("name"), "duplicate probe name", p.name, name_expected);
    const std::string point_expected =
        "[x, y] (every node there through the thickness) or [x, y, z]";
    const Node point = m.require("point", point_expected);
    if (!point.IsSequence() || point.size() < 2 || point.size() > 3)
      c.wrong_type(point, m.key("point"), point_expected);
    for (size_t d = 0; d < point.size(); ++d)
      p.point.push_back(number(
          c, point[d], index_key(m.key("point"), d), [](double) { return true; }, "a number"));
    p.quantity = get_enum(m, "quantity",
                          {{"displacement", ProbeSpec::Quantity::Displacement},
                           {"velocity", ProbeSpec::Quantity::Velocity},
                           {"pressure", ProbeSpec::Quantity::Pressure}},
                          std::optional<ProbeSpec::Quantity>());
    const bool structural = p.quantity == ProbeSpec::Quantity::Displacement;
    if (structural ? !scene.structure.enabled : !scene.fluid.enabled)
      c.fail(*m.get("quantity"), m.key("quantity"),
             structural ? "a displacement without a structure field"
                        : "a flow value without a fluid field",
             structural ? "displacement"
                        : (p.quantity == ProbeSpec::Quantity::Velocity ? "velocity" : "pressure"),
             structural ? "a fields.structure section" : "a fields.fluid section");
    probes.push_back(p);
  }
  return probes;
}

void read_output(const Checker& c, const Node& node, const MeshNames& names, Scene& scene) {
  MapView m(c, node, "output",
            {"directory", "every", "flux_boundaries", "force_boundaries", "probes"});
  OutputSpec& o = scene.output;
  if (auto d = m.get("directory")) {
    o.directory = string_value(c, *d, m.key("directory"), "a directory name");
    if (o.directory.empty()) c.fail(*d, m.key("directory"), "empty", "", "a directory name");
  }
  o.every = get_int(m, "every", 1, o.every);
  for (const char* key : {"flux_boundaries", "force_boundaries"}) {
    auto fb = m.get(key);
    if (!fb || fb->IsNull()) continue;
    if (!fb->IsSequence()) c.wrong_type(*fb, m.key(key), "a list of face set names");
    auto& list = std::string(key) == "flux_boundaries" ? o.flux_boundaries : o.force_boundaries;
    for (size_t i = 0; i < fb->size(); ++i)
      list.push_back(boundary_name(c, (*fb)[i], index_key(m.key(key), i), names.face_sets));
  }
  if (!o.force_boundaries.empty() && !scene.fluid.enabled)
    c.fail(*m.get("force_boundaries"), m.key("force_boundaries"),
           "fluid forces asked for without a fluid field", render(*m.get("force_boundaries")),
           "a fields.fluid section, or no force_boundaries");
  if (auto probes = m.get("probes")) o.probes = read_probes(c, *probes, m.key("probes"), scene);
}

// The time and solver sections' values in every field that uses them, so that each field's
// settings are complete in the scene. The fluid keeps its own Newton tolerances (tighter than the
// scalar's defaults; tests/fluid) and takes at least the scene's iteration limit.
void set_time_and_solver(Scene& scene) {
  const TimeSpec& t = scene.time;
  const SolverSpec& solver = scene.solver;
  TransportSettings& scalar = scene.scalar.settings;
  scalar.theta = t.mode == TimeMode::Steady ? 1.0 : t.theta;
  scalar.scatter = solver.scatter;
  scalar.newton.rel_tol = solver.newton_rel_tol;
  scalar.newton.abs_tol = solver.newton_abs_tol;
  scalar.newton.max_iterations = solver.newton_max_iterations;
  scalar.newton.krylov.max_iterations = solver.linear_max_iterations;
  scalar.newton.krylov.restart = solver.linear_restart;
  scalar.newton.eta_max = std::max(solver.linear_rel_tol, scalar.newton.eta_min);
  scalar.newton.reuse_preconditioner = solver.reuse_preconditioner;
  FluidSettings& fluid = scene.fluid.settings;
  fluid.theta = t.theta;
  fluid.scatter = solver.scatter;
  fluid.newton_options.max_iterations =
      std::max(fluid.newton_options.max_iterations, solver.newton_max_iterations);
  fluid.newton_options.reuse_preconditioner = solver.reuse_preconditioner;
  StructureSettings& structure = scene.structure.settings;
  structure.theta = t.theta;
  structure.scatter = solver.scatter;
  structure.newton.reuse_preconditioner = solver.reuse_preconditioner;
  scene.fsi.reuse_preconditioner = solver.reuse_preconditioner;
  scene.fsi.mesh_motion.scatter = solver.scatter;
  scene.growth.settings.mesh_motion.scatter = solver.scatter;
}

std::string growth_interface_expected(const std::string& biofilm) {
  return "a face set that bounds block '" + biofilm +
         "', whose faces on that side have normals that agree at every node";
}

// The growth interface seen from the biofilm block (orient_interface) must exist and have
// normals; checked on the mesh the names were read from, so that the message points at the line.
void check_growth_interface(const Checker& c, const Node& growth, Mesh mesh, const Scene& scene) {
  if (!scene.growth.enabled) return;
  const std::string& set = scene.growth.settings.interface_set;
  const std::string& biofilm = scene.growth.biofilm_block;
  const std::string why = orient_interface(mesh, set, mesh.block_index(biofilm));
  if (!why.empty())
    c.fail(growth["interface"], "growth.interface", why, set, growth_interface_expected(biofilm));
}

Scene read_scene(const Node& root, const Checker& c) {
  const std::vector<std::string> top = {"mesh",   "materials", "fields", "time",        "solver",
                                        "output", "growth",    "fsi",    "mesh_motion", "fidelity"};
  if (!root.IsDefined() || root.IsNull())
    c.fail(root, "", "the scene is empty", std::nullopt, "a map with keys " + join_list(top));
  MapView m(c, root, "", top, "a map with keys " + join_list(top));
  Scene scene;
  scene.file = c.file();
  MeshNames names;
  Mesh mesh;
  names.face_sets = read_mesh(
      c, m.require("mesh", "a map describing the mesh (type: box or gmsh, ...)"), scene, mesh);
  names.blocks = scene.block_names;
  read_materials(c, m.require("materials", "a map with one material per block"), scene);
  read_fields(c, m.get("fields").value_or(Node()), names, scene);
  read_time(c, m.require("time", "a map with dt [ms] and steps"), scene);
  read_solver(c, m.get("solver").value_or(Node()), scene);
  read_output(c, m.get("output").value_or(Node()), names, scene);
  std::vector<std::string> stacked_blocks;
  for (const auto& b : scene.box.blocks) stacked_blocks.push_back(b.name);
  const MeshMotionSettings mesh_motion =
      read_mesh_motion_section(c, m.get("mesh_motion").value_or(Node()), names);
  scene.growth = read_growth_section(c, m.get("growth").value_or(Node()), names, stacked_blocks,
                                     mesh_motion, scene.time.steps, scene.time.steady_tolerance);
  check_growth_interface(c, m.get("growth").value_or(Node()), std::move(mesh), scene);
  const bool coupled = scene.structure.enabled && scene.fluid.enabled;
  if (scene.structure.enabled && !scene.fluid.enabled &&
      (scene.scalar.enabled || scene.growth.enabled))
    c.fail((*m.get("fields"))["structure"], "fields.structure",
           "a structure without a fluid field beside the scalar or growth", std::nullopt,
           "a fields.fluid section as well (the flow loads the biofilm), or the structure alone "
           "(fields.scalar.enabled: false, no growth section)");
  scene.fsi = read_fsi_section(c, m.get("fsi").value_or(Node()), names, coupled, scene.fluid,
                               scene.growth.enabled ? scene.growth.settings.interface_set : "",
                               mesh_motion);
  // The fluid mesh of the coupled solve (the inner loop's ALE map) keeps the flow's inflow and
  // outflow Eulerian; a growth step's mesh motion does not: the interface's end nodes on those
  // boundaries rise with the film, and nodes held above them would be overtaken (an inverted
  // element within one fluid element's height of growth).
  hold_inflow_outflow(scene.fsi.mesh_motion,
                      inflow_outflow_boundaries(scene.fluid, scene.fsi.interface));
  set_time_and_solver(scene);
  return scene;
}

// One step of an override path: a name, or "[i]" (which only indexes a list).
struct PathPart {
  std::string name;
  bool bracket = false;
  bool numeric() const {
    return !name.empty() && std::all_of(name.begin(), name.end(), [](char ch) {
      return std::isdigit(static_cast<unsigned char>(ch));
    });
  }
};

[[noreturn]] void bad_override(const std::string& text, const std::string& why) {
  throw SceneError("--set " + text + ": " + why);
}

std::vector<PathPart> split_override_key(const std::string& text, const std::string& path) {
  std::vector<PathPart> parts;
  for (size_t pos = 0; pos <= path.size();) {
    size_t end = path.find('.', pos);
    if (end == std::string::npos) end = path.size();
    const std::string seg = path.substr(pos, end - pos);
    const size_t open = seg.find('[');
    if (seg.empty() || open == 0) bad_override(text, "empty part in key '" + path + "'");
    parts.push_back({seg.substr(0, open), false});
    for (size_t p = open; p != std::string::npos && p < seg.size();) {
      const size_t close = seg.find(']', p);
      if (seg[p] != '[' || close == std::string::npos)
        bad_override(text, "malformed index in '" + seg + "'");
      PathPart idx{seg.substr(p + 1, close - p - 1), true};
      if (!idx.numeric())
        bad_override(text, "index '" + idx.name + "' in '" + seg + "' is not a number");
      parts.push_back(idx);
      p = close + 1;
    }
    pos = end + 1;
  }
  return parts;
}

void apply_override(Node& root, const std::string& text, std::vector<OverrideOrigin>& origins) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos)
    bad_override(text, "missing '='; expected key=value, e.g. time.dt=0.5");
  std::string path = text.substr(0, eq);
  path.erase(0, path.find_first_not_of(" \t"));
  path.erase(path.find_last_not_of(" \t") + 1);
  if (path.empty()) bad_override(text, "empty key; expected key=value, e.g. time.dt=0.5");
  const std::vector<PathPart> parts = split_override_key(text, path);

  Node value;
  try {
    value = YAML::Load(text.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    bad_override(text, "the value is not valid YAML: " + e.msg);
  }

  // An empty document has no node to write into; give it one.
  if (root.IsNull()) root = Node(YAML::NodeType::Map);
  // Walk with reset(): assigning one yaml-cpp handle to another would overwrite the tree.
  Node cur;
  cur.reset(root);
  std::string key;
  int line = line_of(root, 1);  // of the replaced node, else of its deepest existing ancestor
  std::string created;          // the first node this override creates; all below is its value
  for (size_t i = 0; i < parts.size(); ++i) {
    const PathPart& part = parts[i];
    const bool last = i + 1 == parts.size();
    const std::string here = key.empty() ? "(top level)" : key;
    Node next;
    if (cur.IsSequence()) {
      if (!part.numeric())
        bad_override(text, "'" + here + "' is a list; '" + part.name + "' is not an index");
      // An index of any length: one beyond size_t is out of range too (std::stoul threw).
      size_t idx = 0;
      const char* end = part.name.data() + part.name.size();
      if (std::from_chars(part.name.data(), end, idx).ec != std::errc()) idx = cur.size();
      if (idx >= cur.size())
        bad_override(text, "index " + part.name + " out of range: '" + here + "' has " +
                               std::to_string(cur.size()) + " entries");
      key = index_key(key, idx);
      line = line_of(cur[idx], line);
      if (last) cur[idx] = value;
      next.reset(cur[idx]);
    } else if (cur.IsMap() || cur.IsNull()) {
      if (part.bracket)
        bad_override(text,
                     "'" + here + "' is not a list; cannot index it with [" + part.name + "]");
      key = child_key(key, part.name);
      const Node existing = static_cast<const Node&>(cur)[part.name];
      if (existing.IsDefined()) {
        line = line_of(existing, line);
      } else if (created.empty()) {
        created = key;
      }
      if (last)
        cur[part.name] = value;
      else if (!existing.IsDefined())
        cur[part.name] = Node(YAML::NodeType::Map);
      next.reset(cur[part.name]);
    } else {
      bad_override(text, "'" + here + "' is a value ('" + render(cur) +
                             "'), not a map or list; cannot index it with '" + part.name + "'");
    }
    cur.reset(next);
  }
  origins.push_back({created.empty() ? key : created, text, line});
}

}  // namespace

Scene parse_scene(const std::string& yaml_text, const std::string& file,
                  const std::vector<std::string>& overrides) {
  Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw SceneError(file + ":" + std::to_string(e.mark.line + 1) +
                     ": YAML syntax error: " + e.msg);
  }
  std::vector<OverrideOrigin> origins;
  for (const auto& o : overrides) apply_override(root, o, origins);
  const Checker checker(file, origins);
  try {
    const FidelityReport fidelity = apply_fidelity(root, checker);
    Scene scene = read_scene(root, checker);
    scene.fidelity = fidelity;
    return scene;
  } catch (const YAML::Exception& e) {
    // Every access above is checked; this is a safety net so no raw yaml-cpp error escapes.
    throw SceneError(file + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (fs::is_directory(status))
    throw SceneError(path + ": cannot read the scene file: it is a directory");
  // A device or pipe (/dev/zero, /dev/stdin) may never end.
  if (fs::exists(status) && !fs::is_regular_file(status))
    throw SceneError(path + ": cannot read the scene file: not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot read the scene file: " + std::strerror(errno));
  // Read in chunks up to the limit, whatever the file's size claims.
  std::string text;
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    text.append(chunk, static_cast<size_t>(in.gcount()));
    if (text.size() > kMaxSceneBytes)
      throw SceneError(path + ": the scene file is larger than " + std::to_string(kMaxSceneBytes) +
                       " bytes (" + std::to_string(fs::file_size(path, ec)) +
                       "); expected a scene of a few kB");
  }
  if (in.bad()) throw SceneError(path + ": cannot read the scene file: " + std::strerror(errno));
  return parse_scene(text, path, overrides);
}

Mesh make_scene_mesh(const Scene& scene, int* reoriented, bool keep_blocks) {
  if (reoriented) *reoriented = 0;
  Mesh mesh;
  if (scene.mesh_type != "gmsh")
    mesh = make_box_mesh(scene.box);
  else if (std::filesystem::path(scene.gmsh_file).extension() == ".geo")
    mesh = mesh_geo_with_gmsh(scene.gmsh_file, scene.gmsh_parameters, scene.gmsh_thickness,
                              reoriented);
  else
    mesh = read_gmsh(scene.gmsh_file, scene.gmsh_thickness, reoriented);
  if (keep_blocks && !scene.gmsh_keep_blocks.empty()) mesh = submesh(mesh, scene.gmsh_keep_blocks);
  for (const auto& [name, sets] : scene.mesh_unions) add_union_set(mesh, sets, name);
  // Growth, its flux and the shear on the interface are taken from the biofilm's side (checked
  // when the scene was read: check_growth_interface).
  const int biofilm = mesh.block_index(scene.growth.biofilm_block);
  if (scene.growth.enabled && biofilm >= 0) {
    const std::string why = orient_interface(mesh, scene.growth.settings.interface_set, biofilm);
    if (!why.empty())
      throw SceneError(scene.file + ": growth.interface: " + why + "; got '" +
                       scene.growth.settings.interface_set + "', expected " +
                       growth_interface_expected(scene.growth.biofilm_block));
  }
  return mesh;
}

}  // namespace biofsi
