// src/io/scene_reader.hpp: the checked YAML access every scene section reader uses. Each field
// reads its own section (src/<field>/parameters.cpp) with these helpers, so a key's default lives
// beside the field's settings and every bad value is reported the same way: file, line, key, the
// value and what was expected. What it may include: yaml-cpp, src/io/expression.
#pragma once

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace biofsi {

// Bad input: the message names file, line, key, the offending value and what was expected.
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Per-block material constants of the materials section, read by the scalar (diffusivity, Monod)
// and structure (elastic constants) sections (units: mm, ms, concentration normalised to 1).
struct MaterialSpec {
  double diffusivity = 0;            // D > 0 [mm^2/ms]
  double monod_rate = 0;             // k >= 0 [1/ms]
  double monod_half_saturation = 0;  // K > 0 when k > 0 [-]
  // Elastic constants of a structure block (fields.structure); `elastic` says they were given.
  bool elastic = false;
  bool neo_hooke = false;     // the model; false: Saint Venant-Kirchhoff
  double youngs_modulus = 0;  // E > 0 [mass/(mm ms^2)]
  double poisson_ratio = 0;   // in (-1, 0.5)
  double density = 0;         // rho >= 0 [mass/mm^3]
};
using Materials = std::map<std::string, MaterialSpec>;  // by block name; every block has one

namespace scene_input {

using YAML::Node;

// What a section reader checks names against: the mesh's blocks (in block order) and face sets.
struct MeshNames {
  std::vector<std::string> blocks;
  std::set<std::string> face_sets;
};

std::string join_list(const std::vector<std::string>& items);
std::string child_key(const std::string& parent, const std::string& name);
std::string index_key(const std::string& parent, size_t i);
bool is_prefix_key(const std::string& prefix, const std::string& key);
// A scalar's text, or a node in one-line flow style, short enough for a message.
std::string render(const Node& n);

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
                         const std::optional<std::string>& got, const std::string& expected) const;

  [[noreturn]] void wrong_type(const Node& n, const std::string& key, const std::string& expected,
                               const std::string& plain = "a scalar") const;

 private:
  std::string file_;
  std::vector<OverrideOrigin> origins_;
};

// A YAML map whose keys have been checked against the allowed ones.
class MapView {
 public:
  // An absent or empty (null) optional map reads as a map without keys.
  MapView(const Checker& c, const Node& node, std::string key,
          const std::vector<std::string>& allowed, const std::string& what = "a map");

  const Checker& checker() const { return c_; }
  const Node& node() const { return node_; }
  const std::string& key() const { return key_; }
  std::string key(const std::string& name) const { return child_key(key_, name); }

  std::optional<Node> get(const std::string& name) const;

  [[noreturn]] void missing(const std::string& name, const std::string& expected,
                            const std::string& why = "") const;

  Node require(const std::string& name, const std::string& expected) const;

 private:
  const Checker& c_;
  Node node_;
  std::string key_;
  std::vector<std::pair<std::string, Node>> entries_;
};

// A missing key with a fallback reads as the fallback; without one it is an error.
double number(const Checker& c, const Node& n, const std::string& key,
              const std::function<bool(double)>& ok, const std::string& expected);
double get_number(const MapView& m, const std::string& name, const std::function<bool(double)>& ok,
                  const std::string& expected, std::optional<double> fallback);
int get_int(const MapView& m, const std::string& name, int min, std::optional<int> fallback);
bool get_bool(const MapView& m, const std::string& name, bool fallback);
std::string string_value(const Checker& c, const Node& n, const std::string& key,
                         const std::string& expected);
std::string get_choice(const MapView& m, const std::string& name,
                       const std::vector<std::string>& choices,
                       std::optional<std::string> fallback);

// A choice read into an enum: `names` pairs each accepted spelling with its value.
template <class Enum>
Enum get_enum(const MapView& m, const std::string& name,
              const std::vector<std::pair<std::string, Enum>>& names,
              std::optional<Enum> fallback) {
  std::vector<std::string> choices;
  std::optional<std::string> fallback_name;
  for (const auto& [text, value] : names) {
    choices.push_back(text);
    if (fallback && value == *fallback) fallback_name = text;
  }
  const std::string text = get_choice(m, name, choices, fallback_name);
  return std::find_if(names.begin(), names.end(), [&](const auto& p) { return p.first == text; })
      ->second;
}

// A text that parses as an expression in x, y, z, t.
std::string expression(const Checker& c, const Node& n, const std::string& key);
std::string get_expression(const MapView& m, const std::string& name,
                           std::optional<std::string> fallback);
// An optional list of 3 expressions (a vector field, e.g. a body force); absent: nullopt.
std::optional<std::array<std::string, 3>> get_expression_vector(const MapView& m,
                                                                const std::string& name,
                                                                const std::string& expected);
// [a, b] with b > a.
std::pair<double, double> get_interval(const MapView& m, const std::string& name);
std::string boundary_name(const Checker& c, const Node& n, const std::string& key,
                          const std::set<std::string>& face_sets);
std::vector<std::string> face_set_list(const Checker& c, const Node& n, const std::string& key,
                                       const std::set<std::string>& face_sets);
// A required, non-empty list of block names of the mesh; `what` says what the blocks hold.
std::vector<std::string> block_list(const MapView& m, const std::string& name,
                                    const std::vector<std::string>& block_names,
                                    const std::string& what);
int line_of(const Node& n, int fallback);

// A field takes one boundary condition per boundary: with two, which one holds is not what the
// scene says. claim() refuses the second, naming the first.
class OneConditionPerBoundary {
 public:
  explicit OneConditionPerBoundary(std::string field) : field_(std::move(field)) {}
  void claim(const Checker& c, const Node& at, const std::string& key, const std::string& boundary);

 private:
  std::string field_;
  std::map<std::string, std::string> first_;  // boundary -> the key of its condition
};

// The boundary_conditions list of a field section (required, non-empty, maps with the keys
// boundary, type and value): read(item, line, boundary) of each, the boundary checked to be a
// face set of the mesh that no earlier item of the list names.
template <class Read>
auto read_boundary_conditions(const MapView& m, const std::string& field,
                              const std::set<std::string>& face_sets, Read read) {
  std::vector<decltype(read(m, 0, std::string()))> out;
  const Checker& c = m.checker();
  const std::string key = m.key("boundary_conditions");
  const std::string list_expected =
      "a list of " + field + " boundary conditions {boundary, type, ...}";
  const Node bcs = m.require("boundary_conditions", list_expected);
  if (!bcs.IsSequence() || bcs.size() == 0) c.wrong_type(bcs, key, list_expected);
  std::vector<std::string> names(face_sets.begin(), face_sets.end());
  OneConditionPerBoundary once(field);
  for (size_t i = 0; i < bcs.size(); ++i) {
    const Node item = bcs[i];
    const std::string ikey = index_key(key, i);
    if (!item.IsMap()) c.wrong_type(item, ikey, "a map {boundary, type, ...}");
    const MapView typed(c, item, ikey, {"boundary", "type", "value"});
    const Node b = typed.require("boundary", "a face set of the mesh: " + join_list(names));
    const std::string boundary = boundary_name(c, b, typed.key("boundary"), face_sets);
    once.claim(c, b, typed.key("boundary"), boundary);
    out.push_back(read(typed, line_of(item, 0), boundary));
  }
  return out;
}

}  // namespace scene_input
}  // namespace biofsi
