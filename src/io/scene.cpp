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
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include "io/expression.hpp"
#include "mesh/gmsh.hpp"

namespace biofsi {

namespace {

using YAML::Node;

std::string join_list(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

std::string child_key(const std::string& parent, const std::string& name) {
  return parent.empty() ? name : parent + "." + name;
}

std::string index_key(const std::string& parent, size_t i) {
  return parent + "[" + std::to_string(i) + "]";
}

bool is_prefix_key(const std::string& prefix, const std::string& key) {
  if (key.compare(0, prefix.size(), prefix) != 0) return false;
  return key.size() == prefix.size() || key[prefix.size()] == '.' || key[prefix.size()] == '[';
}

// A scalar's text, or a node in one-line flow style, short enough for a message.
std::string render(const Node& n) {
  if (!n.IsDefined() || n.IsNull()) return "";
  if (n.IsScalar()) return n.Scalar();
  YAML::Emitter e;
  e.SetMapFormat(YAML::Flow);
  e.SetSeqFormat(YAML::Flow);
  e << n;
  std::string s = e.c_str();
  std::replace(s.begin(), s.end(), '\n', ' ');
  if (s.size() > 80) s = s.substr(0, 77) + "...";
  return s;
}

// yaml-cpp tags plain scalars "?" and quoted ones "!": a quoted "1.0" is a string, not a number.
bool is_plain_scalar(const Node& n) { return n.IsScalar() && n.Tag() != "!"; }

// `plain` says what a plain scalar is not, e.g. "not a number".
std::string kind_of(const Node& n, const std::string& plain) {
  if (!n.IsDefined() || n.IsNull()) return "empty";
  if (n.IsMap()) return "a map";
  if (n.IsSequence()) return "a list";
  return is_plain_scalar(n) ? plain : "a quoted string";
}

// Where an override put a value: errors about that value (or anything below it) point at the
// line it replaced in the file and name the override.
struct OverrideOrigin {
  std::string key;
  std::string text;
  int line;
};

class Checker {
 public:
  Checker(std::string file, std::vector<OverrideOrigin> origins)
      : file_(std::move(file)), origins_(std::move(origins)) {}

  const std::string& file() const { return file_; }

  // got == nullopt: the value is missing.
  [[noreturn]] void fail(const Node& at, const std::string& key, const std::string& problem,
                         const std::optional<std::string>& got, const std::string& expected) const {
    int line = 1;
    if (at.IsDefined() && !at.Mark().is_null()) line = at.Mark().line + 1;
    std::string from;
    const OverrideOrigin* best = nullptr;
    for (const auto& o : origins_)
      if (is_prefix_key(o.key, key) && (!best || o.key.size() >= best->key.size())) best = &o;
    if (best) {
      line = best->line;
      from = " (set by --set " + best->text + ")";
    }
    std::ostringstream msg;
    msg << file_ << ":" << line << ": " << (key.empty() ? "(top level)" : key) << ": " << problem
        << "; got " << (got ? "'" + *got + "'" : std::string("nothing")) << ", expected "
        << expected << from;
    throw SceneError(msg.str());
  }

  [[noreturn]] void wrong_type(const Node& n, const std::string& key, const std::string& expected,
                               const std::string& plain = "a scalar") const {
    fail(n, key, "wrong type (" + kind_of(n, plain) + ")", render(n), expected);
  }

 private:
  std::string file_;
  std::vector<OverrideOrigin> origins_;
};

// A YAML map whose keys have been checked against the allowed ones.
class MapView {
 public:
  // An absent or empty (null) optional map reads as a map without keys.
  MapView(const Checker& c, const Node& node, std::string key,
          const std::vector<std::string>& allowed, const std::string& what = "a map")
      : c_(c), node_(node), key_(std::move(key)) {
    if (!node_.IsDefined() || node_.IsNull()) return;
    if (!node_.IsMap()) c_.wrong_type(node_, key_, what);
    std::set<std::string> seen;
    for (auto it = node_.begin(); it != node_.end(); ++it) {
      const Node k = it->first;
      if (!k.IsScalar())
        c_.fail(k, key_, "a key must be a plain name", render(k), "one of " + join_list(allowed));
      const std::string name = k.Scalar();
      if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
        c_.fail(k, child_key(key_, name), "unknown key", name, "one of " + join_list(allowed));
      if (!seen.insert(name).second)
        c_.fail(k, child_key(key_, name), "duplicate key", name, "each key once");
      entries_.emplace_back(name, it->second);
    }
  }

  const Checker& checker() const { return c_; }
  const Node& node() const { return node_; }
  const std::string& key() const { return key_; }
  std::string key(const std::string& name) const { return child_key(key_, name); }

  std::optional<Node> get(const std::string& name) const {
    for (const auto& [k, v] : entries_)
      if (k == name) return v;
    return std::nullopt;
  }

  [[noreturn]] void missing(const std::string& name, const std::string& expected,
                            const std::string& why = "") const {
    c_.fail(node_, key(name), "missing required key" + why, std::nullopt, expected);
  }

  Node require(const std::string& name, const std::string& expected) const {
    auto n = get(name);
    if (!n) missing(name, expected);
    return *n;
  }

 private:
  const Checker& c_;
  Node node_;
  std::string key_;
  std::vector<std::pair<std::string, Node>> entries_;
};

std::optional<double> parse_double(const Node& n) {
  if (!is_plain_scalar(n)) return std::nullopt;
  double v;
  if (!YAML::convert<double>::decode(n, v)) return std::nullopt;
  return v;
}

std::optional<long long> parse_integer(const Node& n) {
  if (!is_plain_scalar(n)) return std::nullopt;
  const std::string& s = n.Scalar();
  size_t i = (!s.empty() && (s[0] == '+' || s[0] == '-')) ? 1 : 0;
  if (i == s.size() || s.size() > 18) return std::nullopt;
  for (size_t j = i; j < s.size(); ++j)
    if (!std::isdigit(static_cast<unsigned char>(s[j]))) return std::nullopt;
  return std::stoll(s);
}

double number(const Checker& c, const Node& n, const std::string& key,
              const std::function<bool(double)>& ok, const std::string& expected) {
  auto v = parse_double(n);
  if (!v) c.wrong_type(n, key, expected, "not a number");
  if (!std::isfinite(*v) || !ok(*v)) c.fail(n, key, "out of range", n.Scalar(), expected);
  return *v;
}

double get_number(const MapView& m, const std::string& name, const std::function<bool(double)>& ok,
                  const std::string& expected, std::optional<double> fallback) {
  auto n = m.get(name);
  if (!n) {
    if (!fallback) m.missing(name, expected);
    return *fallback;
  }
  return number(m.checker(), *n, m.key(name), ok, expected);
}

int get_int(const MapView& m, const std::string& name, int min, std::optional<int> fallback) {
  const std::string expected = "an integer >= " + std::to_string(min);
  auto n = m.get(name);
  if (!n) {
    if (!fallback) m.missing(name, expected);
    return *fallback;
  }
  auto v = parse_integer(*n);
  if (!v)
    m.checker().wrong_type(*n, m.key(name), expected,
                           parse_double(*n) ? "not an integer" : "not a number");
  if (*v < min || *v > 2147483647LL)
    m.checker().fail(*n, m.key(name), "out of range", n->Scalar(), expected);
  return static_cast<int>(*v);
}

bool get_bool(const MapView& m, const std::string& name, bool fallback) {
  auto n = m.get(name);
  if (!n) return fallback;
  bool v;
  if (!is_plain_scalar(*n) || !YAML::convert<bool>::decode(*n, v))
    m.checker().wrong_type(*n, m.key(name), "true or false", "not true or false");
  return v;
}

std::string string_value(const Checker& c, const Node& n, const std::string& key,
                         const std::string& expected) {
  if (!n.IsScalar()) c.wrong_type(n, key, expected);
  return n.Scalar();
}

std::string get_choice(const MapView& m, const std::string& name,
                       const std::vector<std::string>& choices,
                       std::optional<std::string> fallback) {
  const std::string expected = "one of " + join_list(choices);
  auto n = m.get(name);
  if (!n) {
    if (!fallback) m.missing(name, expected);
    return *fallback;
  }
  const std::string v = string_value(m.checker(), *n, m.key(name), expected);
  if (std::find(choices.begin(), choices.end(), v) == choices.end())
    m.checker().fail(*n, m.key(name), "unknown value", v, expected);
  return v;
}

const char* kExpressionExpected = "an expression in x, y, z, t (e.g. \"0.5 + 0.5*cos(0.2*pi*x)\")";

std::string expression(const Checker& c, const Node& n, const std::string& key) {
  const std::string text = string_value(c, n, key, kExpressionExpected);
  try {
    Expression e(text);
  } catch (const std::invalid_argument& err) {
    // The message repeats the text, which "got" already shows.
    std::string reason = err.what();
    const std::string quoted = "invalid expression '" + text + "'";
    if (reason.rfind(quoted, 0) == 0) reason = "invalid expression" + reason.substr(quoted.size());
    c.fail(n, key, reason, text, kExpressionExpected);
  }
  return text;
}

std::string get_expression(const MapView& m, const std::string& name,
                           std::optional<std::string> fallback) {
  auto n = m.get(name);
  if (!n) {
    if (!fallback) m.missing(name, kExpressionExpected);
    return *fallback;
  }
  return expression(m.checker(), *n, m.key(name));
}

// [a, b] with b > a.
std::pair<double, double> get_interval(const MapView& m, const std::string& name) {
  const std::string expected = "[" + name + "0, " + name + "1] with " + name + "1 > " + name + "0";
  const Node n = m.require(name, expected);
  const std::string key = m.key(name);
  if (!n.IsSequence() || n.size() != 2) m.checker().wrong_type(n, key, expected);
  const double a = number(
      m.checker(), n[0], index_key(key, 0), [](double) { return true; }, "a number");
  const double b = number(
      m.checker(), n[1], index_key(key, 1), [](double) { return true; }, "a number");
  if (!(b > a)) m.checker().fail(n, key, "empty interval", render(n), expected);
  return {a, b};
}

std::string boundary_name(const Checker& c, const Node& n, const std::string& key,
                          const std::set<std::string>& face_sets) {
  std::vector<std::string> names(face_sets.begin(), face_sets.end());
  const std::string expected = "a face set of the mesh: " + join_list(names);
  const std::string v = string_value(c, n, key, expected);
  if (!face_sets.count(v)) c.fail(n, key, "unknown boundary", v, expected);
  return v;
}

bool valid_block_name(const std::string& s) {
  if (s.empty()) return false;
  for (char ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_') return false;
  return true;
}

// mesh: {type: gmsh, file: <path relative to the scene>, thickness: <for a 2-D file>}. The file is
// read here, so that a bad mesh and unknown set names are reported before anything runs.
std::set<std::string> read_gmsh_mesh(const Checker& c, const MapView& m, Scene& scene) {
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
  Mesh mesh;
  try {
    mesh = make_scene_mesh(scene);
  } catch (const MeshFileError& e) {
    c.fail(file, m.key("file"), std::string("cannot use the mesh (") + e.what() + ")", name,
           expected +
               " (.msh, or .geo meshed by gmsh) with hexahedra, or quadrilaterals and "
               "mesh.thickness");
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

// Returns the names of the mesh's face sets.
std::set<std::string> read_mesh(const Checker& c, const Node& node, Scene& scene) {
  MapView m(c, node, "mesh",
            {"type", "x", "z", "nx", "nz", "blocks", "file", "thickness", "parameters"});
  scene.mesh_type = get_choice(m, "type", {"box", "gmsh"}, std::nullopt);
  const std::vector<std::string> box_keys = {"x", "z", "nx", "nz", "blocks"},
                                 gmsh_keys = {"file", "thickness", "parameters"};
  for (const auto& key : scene.mesh_type == "box" ? gmsh_keys : box_keys)
    if (auto n = m.get(key))
      c.fail(*n, m.key(key), "not a key of a " + scene.mesh_type + " mesh", key,
             "the keys " + join_list(scene.mesh_type == "box" ? box_keys : gmsh_keys));
  if (scene.mesh_type == "gmsh") return read_gmsh_mesh(c, m, scene);
  read_box_mesh(c, m, scene);
  for (const auto& b : scene.box.blocks) scene.block_names.push_back(b.name);
  // Face-set names depend only on the block names, not on the resolution: a one-element-thick
  // copy names every set at negligible cost whatever the scene's size.
  BoxSpec coarse = scene.box;
  coarse.nx = coarse.nz = 1;
  for (auto& b : coarse.blocks) b.ny = 1;
  std::set<std::string> face_sets;
  try {
    for (const auto& [name, faces] : make_box_mesh(coarse).face_sets) face_sets.insert(name);
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
      mat.model = get_choice(m, "model", {"saint_venant_kirchhoff", "neo_hooke"}, mat.model);
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

// The boundary_conditions list of a field section (required, non-empty, maps with the keys
// boundary, type and value): calls read(item, line, boundary) for each, the boundary checked to
// be a face set of the mesh.
template <class Read>
void for_each_boundary_condition(const Checker& c, const MapView& m, const std::string& field,
                                 const std::set<std::string>& face_sets, Read read) {
  const std::string key = m.key("boundary_conditions");
  const std::string list_expected =
      "a list of " + field + " boundary conditions {boundary, type, ...}";
  const Node bcs = m.require("boundary_conditions", list_expected);
  if (!bcs.IsSequence() || bcs.size() == 0) c.wrong_type(bcs, key, list_expected);
  std::vector<std::string> names(face_sets.begin(), face_sets.end());
  for (size_t i = 0; i < bcs.size(); ++i) {
    const Node item = bcs[i];
    const std::string ikey = index_key(key, i);
    if (!item.IsMap()) c.wrong_type(item, ikey, "a map {boundary, type, ...}");
    const MapView typed(c, item, ikey, {"boundary", "type", "value"});
    const Node b = typed.require("boundary", "a face set of the mesh: " + join_list(names));
    const int line = item.Mark().is_null() ? 0 : item.Mark().line + 1;
    read(typed, line, boundary_name(c, b, typed.key("boundary"), face_sets));
  }
}

void read_fluid_field(const Checker& c, const MapView& f, const std::set<std::string>& face_sets,
                      Scene& scene) {
  auto node = f.get("fluid");
  if (!node) return;
  MapView m(
      c, *node, f.key("fluid"),
      {"enabled", "blocks", "density", "viscosity", "mode", "supg", "grad_div", "transient_tau",
       "pseudo_2d", "viscous_form", "preconditioner", "boundary_conditions"});
  FluidFieldSpec& spec = scene.fluid;
  spec.enabled = get_bool(m, "enabled", true);
  const std::string blocks_expected =
      "a list of the blocks that hold fluid: one or more of " + join_list(scene.block_names);
  const Node blocks = m.require("blocks", blocks_expected);
  if (!blocks.IsSequence() || blocks.size() == 0)
    c.wrong_type(blocks, m.key("blocks"), blocks_expected);
  for (size_t i = 0; i < blocks.size(); ++i) {
    const std::string b =
        string_value(c, blocks[i], index_key(m.key("blocks"), i), blocks_expected);
    if (std::find(scene.block_names.begin(), scene.block_names.end(), b) == scene.block_names.end())
      c.fail(blocks[i], index_key(m.key("blocks"), i), "unknown block", b, blocks_expected);
    spec.blocks.push_back(b);
  }
  auto positive = [](double v) { return v > 0; };
  spec.density = get_number(m, "density", positive, "a number > 0 [mass/mm^3]", std::nullopt);
  spec.viscosity =
      get_number(m, "viscosity", positive, "a number > 0 (dynamic) [mass/(mm ms)]", std::nullopt);
  spec.mode = get_choice(m, "mode", {"steady", "transient"}, spec.mode);
  spec.supg = get_bool(m, "supg", spec.supg);
  spec.grad_div = get_bool(m, "grad_div", spec.grad_div);
  spec.transient_tau = get_bool(m, "transient_tau", spec.transient_tau);
  spec.pseudo_2d = get_bool(m, "pseudo_2d", spec.pseudo_2d);
  spec.symmetric_viscous =
      get_choice(m, "viscous_form", {"symmetric", "gradient"}, "symmetric") == "symmetric";
  spec.preconditioner =
      get_choice(m, "preconditioner", {"simple", "simplec", "monolithic_amg"}, spec.preconditioner);
  for_each_boundary_condition(
      c, m, "fluid", face_sets, [&](const MapView& typed, int line, const std::string& boundary) {
        FluidBc bc;
        bc.line = line;
        bc.boundary = boundary;
        bc.type = get_choice(
            typed, "type", {"velocity", "no_slip", "slip", "pressure", "do_nothing"}, std::nullopt);
        const bool has_value = bc.type == "velocity" || bc.type == "pressure";
        if (auto v = typed.get("value")) {
          if (!has_value)
            c.fail(*v, typed.key("value"), "a " + bc.type + " condition takes no value", render(*v),
                   "no value key");
          if (bc.type == "velocity") {
            const std::string expected = "a list of 3 expressions (velocity components)";
            if (!v->IsSequence() || v->size() != 3) c.wrong_type(*v, typed.key("value"), expected);
            for (size_t d = 0; d < 3; ++d)
              bc.value[d] = expression(c, (*v)[d], index_key(typed.key("value"), d));
          } else {
            bc.value[0] = expression(c, *v, typed.key("value"));
          }
        } else if (has_value) {
          typed.missing("value",
                        bc.type == "velocity" ? "a list of 3 expressions" : "an expression", "");
        }
        spec.boundary_conditions.push_back(bc);
      });
}

void read_structure_field(const Checker& c, const MapView& f,
                          const std::set<std::string>& face_sets, Scene& scene) {
  auto node = f.get("structure");
  if (!node) return;
  MapView m(c, *node, f.key("structure"),
            {"enabled", "blocks", "mode", "plane_strain", "boundary_conditions"});
  StructureFieldSpec& spec = scene.structure;
  spec.enabled = get_bool(m, "enabled", true);
  const std::string blocks_expected =
      "a list of the elastic blocks: one or more of " + join_list(scene.block_names);
  const Node blocks = m.require("blocks", blocks_expected);
  if (!blocks.IsSequence() || blocks.size() == 0)
    c.wrong_type(blocks, m.key("blocks"), blocks_expected);
  for (size_t i = 0; i < blocks.size(); ++i) {
    const std::string key = index_key(m.key("blocks"), i);
    const std::string b = string_value(c, blocks[i], key, blocks_expected);
    if (std::find(scene.block_names.begin(), scene.block_names.end(), b) == scene.block_names.end())
      c.fail(blocks[i], key, "unknown block", b, blocks_expected);
    if (std::find(scene.fluid.blocks.begin(), scene.fluid.blocks.end(), b) !=
        scene.fluid.blocks.end())
      c.fail(blocks[i], key, "block '" + b + "' already holds the fluid", b,
             "blocks that are not fields.fluid.blocks");
    if (spec.enabled && !scene.materials.at(b).elastic)
      c.fail(blocks[i], key, "block '" + b + "' has no elastic constants", b,
             "materials." + b + " with youngs_modulus, poisson_ratio and density");
    spec.blocks.push_back(b);
  }
  spec.mode = get_choice(m, "mode", {"dynamic", "quasi_static"}, spec.mode);
  spec.plane_strain = get_bool(m, "plane_strain", spec.plane_strain);
  for_each_boundary_condition(
      c, m, "structure", face_sets,
      [&](const MapView& typed, int line, const std::string& boundary) {
        StructureBc bc;
        bc.line = line;
        bc.boundary = boundary;
        bc.type = get_choice(typed, "type", {"fixed", "displacement"}, std::nullopt);
        const std::string expected =
            "a list of 3 expressions (displacement components; \"free\" leaves one free)";
        if (auto v = typed.get("value")) {
          if (bc.type == "fixed")
            c.fail(*v, typed.key("value"), "a fixed condition takes no value", render(*v),
                   "no value key");
          if (!v->IsSequence() || v->size() != 3) c.wrong_type(*v, typed.key("value"), expected);
          for (size_t d = 0; d < 3; ++d) {
            const Node comp = (*v)[d];
            bc.value[d] = comp.IsScalar() && comp.Scalar() == "free"
                              ? "free"
                              : expression(c, comp, index_key(typed.key("value"), d));
          }
        } else if (bc.type == "displacement") {
          typed.missing("value", expected);
        }
        spec.boundary_conditions.push_back(bc);
      });
  if (spec.enabled && !scene.fluid.enabled)
    c.fail(*node, f.key("structure"), "a structure without a fluid field", std::nullopt,
           "a fields.fluid section as well: scenes load the structure by the flow (FSI)");
  if (spec.enabled && scene.fluid.mode == "steady" && spec.mode != "quasi_static")
    c.fail(m.get("mode").value_or(*node), m.key("mode"), "a dynamic structure in a steady flow",
           spec.mode, "quasi_static (the steady coupled problem), or fields.fluid.mode: transient");
}

void read_fields(const Checker& c, const Node& node, const std::set<std::string>& face_sets,
                 Scene& scene) {
  MapView f(c, node, "fields", {"scalar", "fluid", "structure"});
  read_fluid_field(c, f, face_sets, scene);
  read_structure_field(c, f, face_sets, scene);
  auto scalar_node = f.get("scalar");
  if (!scalar_node) return;
  MapView s(c, *scalar_node, f.key("scalar"),
            {"enabled", "initial", "velocity", "supg", "boundary_conditions"});
  ScalarFieldSpec& spec = scene.scalar;
  spec.enabled = get_bool(s, "enabled", spec.enabled);
  spec.initial = get_expression(s, "initial", spec.initial);
  if (auto v = s.get("velocity")) {
    if (scene.fluid.enabled)
      c.fail(*v, s.key("velocity"), "a prescribed velocity while the fluid field is on", render(*v),
             "no velocity key: the scalar is convected by the fluid's velocity");
    const std::string expected = "a list of 3 expressions (velocity components)";
    if (!v->IsSequence() || v->size() != 3) c.wrong_type(*v, s.key("velocity"), expected);
    for (size_t i = 0; i < 3; ++i)
      spec.velocity[i] = expression(c, (*v)[i], index_key(s.key("velocity"), i));
  }
  spec.supg = get_bool(s, "supg", spec.supg);
  auto bcs = s.get("boundary_conditions");
  if (!bcs || bcs->IsNull()) return;
  const std::string key = s.key("boundary_conditions");
  if (!bcs->IsSequence()) c.wrong_type(*bcs, key, "a list of boundary conditions");
  for (size_t i = 0; i < bcs->size(); ++i) {
    const Node item = (*bcs)[i];
    const std::string ikey = index_key(key, i);
    const std::string map_expected = "a map {boundary, type, ...}";
    if (!item.IsMap()) c.wrong_type(item, ikey, map_expected);
    // The type decides which other keys are allowed, so read it before checking the keys.
    MapView typed(c, item, ikey, {"boundary", "type", "value", "flux", "coefficient", "ambient"});
    ScalarBc bc;
    bc.line = item.Mark().is_null() ? 0 : item.Mark().line + 1;
    const std::string type =
        get_choice(typed, "type", {"dirichlet", "neumann", "robin"}, std::nullopt);
    if (type == "dirichlet") {
      MapView m(c, item, ikey, {"boundary", "type", "value"});
      bc.type = BcType::Dirichlet;
      bc.value = get_expression(m, "value", std::nullopt);
    } else if (type == "neumann") {
      MapView m(c, item, ikey, {"boundary", "type", "flux"});
      bc.type = BcType::Neumann;
      bc.value = get_expression(m, "flux", std::nullopt);
    } else {
      MapView m(c, item, ikey, {"boundary", "type", "coefficient", "ambient"});
      bc.type = BcType::Robin;
      bc.coefficient = get_number(
          m, "coefficient", [](double v) { return v >= 0; }, "a number >= 0 [mm/ms]", std::nullopt);
      bc.value = get_expression(m, "ambient", std::nullopt);
    }
    std::vector<std::string> names(face_sets.begin(), face_sets.end());
    const Node b = typed.require("boundary", "a face set of the mesh: " + join_list(names));
    bc.boundary = boundary_name(c, b, typed.key("boundary"), face_sets);
    spec.boundary_conditions.push_back(bc);
  }
}

void read_time(const Checker& c, const Node& node, Scene& scene) {
  MapView m(c, node, "time", {"mode", "dt", "steps", "theta", "steady_tolerance"});
  TimeSpec& t = scene.time;
  const bool transient = get_choice(m, "mode", {"transient", "steady"}, "transient") == "transient";
  t.mode = transient ? TimeMode::Transient : TimeMode::Steady;
  t.dt = get_number(
      m, "dt", [](double v) { return v > 0; }, "a finite number > 0 [ms]",
      transient ? std::nullopt : std::optional<double>(t.dt));
  t.steps = get_int(m, "steps", 1, transient ? std::nullopt : std::optional<int>(t.steps));
  t.theta = get_number(
      m, "theta", [](double v) { return v >= 0.5 && v <= 1; }, "a number in [0.5, 1]", t.theta);
  t.steady_tolerance = get_number(
      m, "steady_tolerance", [](double v) { return v >= 0; }, "a number >= 0", t.steady_tolerance);
}

void read_solver(const Checker& c, const Node& node, Scene& scene) {
  MapView m(c, node, "solver", {"newton", "linear", "scatter"});
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
  s.scatter = get_choice(m, "scatter", {"colored", "atomic"}, s.scatter);
}

void read_output(const Checker& c, const Node& node, const std::set<std::string>& face_sets,
                 Scene& scene) {
  MapView m(c, node, "output", {"directory", "every", "flux_boundaries", "force_boundaries"});
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
      list.push_back(boundary_name(c, (*fb)[i], index_key(m.key(key), i), face_sets));
  }
  if (!o.force_boundaries.empty() && !scene.fluid.enabled)
    c.fail(*m.get("force_boundaries"), m.key("force_boundaries"),
           "fluid forces asked for without a fluid field", render(*m.get("force_boundaries")),
           "a fields.fluid section, or no force_boundaries");
}

std::vector<std::string> face_set_list(const Checker& c, const Node& n, const std::string& key,
                                       const std::set<std::string>& face_sets) {
  std::vector<std::string> out;
  if (!n.IsSequence()) c.wrong_type(n, key, "a list of face set names");
  for (size_t i = 0; i < n.size(); ++i)
    out.push_back(boundary_name(c, n[i], index_key(key, i), face_sets));
  return out;
}

void read_growth(const Checker& c, const Node& node, const std::set<std::string>& face_sets,
                 Scene& scene) {
  if (!node.IsDefined() || node.IsNull()) return;
  MapView m(c, node, "growth",
            {"enabled", "interface", "biofilm_block", "k1", "k2", "dt_bio", "steps", "averaging",
             "window", "output_every", "checkpoint"});
  GrowthSpec& g = scene.growth;
  g.enabled = get_bool(m, "enabled", true);
  g.interface =
      boundary_name(c, m.require("interface", "the face set of the biofilm-fluid interface"),
                    m.key("interface"), face_sets);
  g.biofilm_block = get_choice(m, "biofilm_block", scene.block_names, std::nullopt);
  // The interface's faces belong to the block below it; that block is the one that grows.
  const auto& bs = scene.box.blocks;
  for (size_t i = 0; i + 1 < bs.size(); ++i)
    if (g.interface == bs[i].name + "_" + bs[i + 1].name && g.biofilm_block != bs[i].name)
      c.fail(*m.get("biofilm_block"), m.key("biofilm_block"),
             "the interface's faces belong to block '" + bs[i].name + "'", g.biofilm_block,
             "'" + bs[i].name + "'");
  auto nonnegative = [](double v) { return v >= 0; };
  g.k1 = get_number(m, "k1", nonnegative,
                    "a number >= 0 [mm per ms per unit flux density] (growth by substrate flux)",
                    std::nullopt);
  g.k2 = get_number(m, "k2", nonnegative, "a number >= 0 (erosion by shear stress)", 0.0);
  g.dt_bio = get_number(
      m, "dt_bio", [](double v) { return v > 0; }, "a finite number > 0 [ms]", std::nullopt);
  g.steps = get_int(m, "steps", 1, std::nullopt);
  g.averaging = get_choice(m, "averaging", {"stationary", "window"}, g.averaging);
  g.window = get_int(m, "window", 1, g.window);
  g.output_every = get_int(m, "output_every", 1, g.output_every);
  g.checkpoint = get_bool(m, "checkpoint", g.checkpoint);
}

// fsi: the coupling of fields.structure and fields.fluid; only with both.
void read_fsi(const Checker& c, const Node& node, const std::set<std::string>& face_sets,
              Scene& scene) {
  const bool coupled = scene.structure.enabled && scene.fluid.enabled;
  if (!coupled) {
    if (node.IsDefined() && !node.IsNull())
      c.fail(node, "fsi", "a coupling section without a structure and a fluid", render(node),
             "fields.structure and fields.fluid, or no fsi section");
    return;
  }
  MapView m(c, node, "fsi",
            {"interface", "shape_derivatives", "fixed_walls", "sliding_walls", "rel_tol",
             "max_iterations"});
  FsiSpec& f = scene.fsi;
  if (auto n = m.get("interface"))
    f.interface = boundary_name(c, *n, m.key("interface"), face_sets);
  else if (scene.growth.enabled)
    f.interface = scene.growth.interface;
  else
    m.missing("interface", "the face set of the fluid-structure interface");
  f.shape_derivatives =
      get_choice(m, "shape_derivatives", {"finite_difference", "none"}, f.shape_derivatives);
  if (auto n = m.get("fixed_walls")) {
    f.fixed_walls = face_set_list(c, *n, m.key("fixed_walls"), face_sets);
    f.walls_given = true;
  }
  if (auto n = m.get("sliding_walls")) {
    f.sliding_walls = face_set_list(c, *n, m.key("sliding_walls"), face_sets);
    f.walls_given = true;
  }
  f.rel_tol = get_number(
      m, "rel_tol", [](double v) { return v > 0 && v < 1; }, "a number in (0, 1)", f.rel_tol);
  f.max_iterations = get_int(m, "max_iterations", 1, f.max_iterations);
  // The fluid's velocity on Γ is the structure's: the fluid must hold it (no_slip or velocity).
  bool held = false;
  for (const auto& bc : scene.fluid.boundary_conditions)
    held = held || (bc.boundary == f.interface && (bc.type == "no_slip" || bc.type == "velocity"));
  if (!held)
    c.fail(m.get("interface").value_or(node), m.key("interface"),
           "the fluid has no no_slip condition on the interface", f.interface,
           "a fields.fluid boundary condition {boundary: " + f.interface +
               ", type: no_slip} (its velocity is then the structure's)");
}

void read_mesh_motion(const Checker& c, const Node& node, const std::set<std::string>& face_sets,
                      Scene& scene) {
  MapView m(c, node, "mesh_motion",
            {"stiffening", "poisson_ratio", "min_quality", "sliding_walls", "fixed_walls"});
  MeshMotionSpec& mm = scene.mesh_motion;
  mm.stiffening = get_number(
      m, "stiffening", [](double v) { return v >= 0; }, "a number >= 0", mm.stiffening);
  mm.poisson_ratio = get_number(
      m, "poisson_ratio", [](double v) { return v >= 0 && v < 0.5; }, "a number in [0, 0.5)",
      mm.poisson_ratio);
  mm.min_quality = get_number(
      m, "min_quality", [](double v) { return v > 0 && v < 1; },
      "a number in (0, 1) (smallest scaled Jacobian)", mm.min_quality);
  if (auto n = m.get("sliding_walls"))
    mm.sliding_walls = face_set_list(c, *n, m.key("sliding_walls"), face_sets);
  if (auto n = m.get("fixed_walls"))
    mm.fixed_walls = face_set_list(c, *n, m.key("fixed_walls"), face_sets);
}

Scene read_scene(const Node& root, const Checker& c) {
  const std::vector<std::string> top = {"mesh",   "materials", "fields", "time",       "solver",
                                        "output", "growth",    "fsi",    "mesh_motion"};
  if (!root.IsDefined() || root.IsNull())
    c.fail(root, "", "the scene is empty", std::nullopt, "a map with keys " + join_list(top));
  MapView m(c, root, "", top, "a map with keys " + join_list(top));
  Scene scene;
  scene.file = c.file();
  const std::set<std::string> face_sets =
      read_mesh(c, m.require("mesh", "a map describing the mesh (type: box or gmsh, ...)"), scene);
  read_materials(c, m.require("materials", "a map with one material per block"), scene);
  read_fields(c, m.get("fields").value_or(Node()), face_sets, scene);
  read_time(c, m.require("time", "a map with dt [ms] and steps"), scene);
  read_solver(c, m.get("solver").value_or(Node()), scene);
  read_output(c, m.get("output").value_or(Node()), face_sets, scene);
  read_growth(c, m.get("growth").value_or(Node()), face_sets, scene);
  read_mesh_motion(c, m.get("mesh_motion").value_or(Node()), face_sets, scene);
  read_fsi(c, m.get("fsi").value_or(Node()), face_sets, scene);
  if (scene.structure.enabled && !scene.fsi.walls_given) {
    scene.fsi.fixed_walls = scene.mesh_motion.fixed_walls;
    scene.fsi.sliding_walls = scene.mesh_motion.sliding_walls;
  }
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

int line_of(const Node& n, int fallback) {
  return n.IsDefined() && !n.Mark().is_null() ? n.Mark().line + 1 : fallback;
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
      const unsigned long idx = std::stoul(part.name);
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
    return read_scene(root, checker);
  } catch (const YAML::Exception& e) {
    // Every access above is checked; this is a safety net so no raw yaml-cpp error escapes.
    throw SceneError(file + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw SceneError(path + ": cannot read the scene file: it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot read the scene file: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw SceneError(path + ": cannot read the scene file: " + std::strerror(errno));
  return parse_scene(text.str(), path, overrides);
}

Mesh make_scene_mesh(const Scene& scene) {
  if (scene.mesh_type != "gmsh") return make_box_mesh(scene.box);
  if (std::filesystem::path(scene.gmsh_file).extension() == ".geo")
    return mesh_geo_with_gmsh(scene.gmsh_file, scene.gmsh_parameters, scene.gmsh_thickness);
  return read_gmsh(scene.gmsh_file, scene.gmsh_thickness);
}

}  // namespace biofsi
