#include "io/scene_reader.hpp"

#include <cctype>
#include <cmath>
#include <sstream>

#include "io/expression.hpp"

namespace biofsi {
namespace scene_input {

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

namespace {

// yaml-cpp tags plain scalars "?" and quoted ones "!": a quoted "1.0" is a string, not a number.
bool is_plain_scalar(const Node& n) { return n.IsScalar() && n.Tag() != "!"; }

// `plain` says what a plain scalar is not, e.g. "not a number".
std::string kind_of(const Node& n, const std::string& plain) {
  if (!n.IsDefined() || n.IsNull()) return "empty";
  if (n.IsMap()) return "a map";
  if (n.IsSequence()) return "a list";
  return is_plain_scalar(n) ? plain : "a quoted string";
}

}  // namespace

void Checker::fail(const Node& at, const std::string& key, const std::string& problem,
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
      << "; got " << (got ? "'" + *got + "'" : std::string("nothing")) << ", expected " << expected
      << from;
  throw SceneError(msg.str());
}

void Checker::wrong_type(const Node& n, const std::string& key, const std::string& expected,
                         const std::string& plain) const {
  fail(n, key, "wrong type (" + kind_of(n, plain) + ")", render(n), expected);
}

MapView::MapView(const Checker& c, const Node& node, std::string key,
                 const std::vector<std::string>& allowed, const std::string& what)
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

std::optional<Node> MapView::get(const std::string& name) const {
  for (const auto& [k, v] : entries_)
    if (k == name) return v;
  return std::nullopt;
}

void MapView::missing(const std::string& name, const std::string& expected,
                      const std::string& why) const {
  c_.fail(node_, key(name), "missing required key" + why, std::nullopt, expected);
}

Node MapView::require(const std::string& name, const std::string& expected) const {
  auto n = get(name);
  if (!n) missing(name, expected);
  return *n;
}

namespace {

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

}  // namespace

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

namespace {
const char* kExpressionExpected = "an expression in x, y, z, t (e.g. \"0.5 + 0.5*cos(0.2*pi*x)\")";

}  // namespace

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

std::optional<std::array<std::string, 3>> get_expression_vector(const MapView& m,
                                                                const std::string& name,
                                                                const std::string& expected) {
  auto n = m.get(name);
  if (!n) return std::nullopt;
  if (!n->IsSequence() || n->size() != 3) m.checker().wrong_type(*n, m.key(name), expected);
  std::array<std::string, 3> out;
  for (size_t d = 0; d < 3; ++d)
    out[d] = expression(m.checker(), (*n)[d], index_key(m.key(name), d));
  return out;
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

std::vector<std::string> face_set_list(const Checker& c, const Node& n, const std::string& key,
                                       const std::set<std::string>& face_sets) {
  std::vector<std::string> out;
  if (!n.IsSequence()) c.wrong_type(n, key, "a list of face set names");
  for (size_t i = 0; i < n.size(); ++i)
    out.push_back(boundary_name(c, n[i], index_key(key, i), face_sets));
  return out;
}

std::vector<std::string> block_list(const MapView& m, const std::string& name,
                                    const std::vector<std::string>& block_names,
                                    const std::string& what) {
  const Checker& c = m.checker();
  const std::string expected = "a list of " + what + ": one or more of " + join_list(block_names);
  const Node blocks = m.require(name, expected);
  if (!blocks.IsSequence() || blocks.size() == 0) c.wrong_type(blocks, m.key(name), expected);
  std::vector<std::string> out;
  for (size_t i = 0; i < blocks.size(); ++i) {
    const std::string key = index_key(m.key(name), i);
    const std::string b = string_value(c, blocks[i], key, expected);
    if (std::find(block_names.begin(), block_names.end(), b) == block_names.end())
      c.fail(blocks[i], key, "unknown block", b, expected);
    out.push_back(b);
  }
  return out;
}

int line_of(const Node& n, int fallback) {
  return n.IsDefined() && !n.Mark().is_null() ? n.Mark().line + 1 : fallback;
}

void OneConditionPerBoundary::claim(const Checker& c, const Node& at, const std::string& key,
                                    const std::string& boundary) {
  const auto [first, fresh] = first_.emplace(boundary, key);
  if (!fresh)
    c.fail(at, key,
           "a second " + field_ + " boundary condition on '" + boundary + "' (the first is " +
               first->second + ")",
           boundary, "each boundary once in a field's boundary_conditions");
}

}  // namespace scene_input
}  // namespace biofsi
