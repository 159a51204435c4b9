#include "io/expression.hpp"

#include <muParser.h>

#include <cctype>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

namespace biofsi {

namespace {

const std::set<std::string> kVariables = {"x", "y", "z", "t"};
// Names that stand for a value; a name outside this set directly before '(' is a function call.
const std::set<std::string> kValueNames = {"x", "y", "z", "t", "pi", "_pi", "_e"};

enum class Tok { Number, Name, Open, Close, Other, Space };

// Papers write "[0.5+0.5cos(0.2 pi x)][1+cos(0.05 pi y)]": brackets as parentheses and products
// by juxtaposition. muparser accepts neither, so rewrite to "(0.5+0.5*cos(0.2*pi*x))*(...)".
// A '*' goes between an operand's end (number, value name, ')') and an operand's start (number,
// name, '('), except between a function name and its '('.
std::string with_explicit_products(const std::string& s) {
  std::string out;
  Tok prev = Tok::Other;
  std::string prev_name;
  size_t i = 0;
  while (i < s.size()) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    Tok kind;
    std::string tok;
    if (std::isspace(c)) {
      tok = s[i++];
      out += tok;
      continue;
    } else if (std::isdigit(c) || (c == '.' && i + 1 < s.size() && std::isdigit(s[i + 1]))) {
      size_t j = i;
      while (j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) || s[j] == '.')) ++j;
      if (j < s.size() && (s[j] == 'e' || s[j] == 'E')) {
        size_t k = j + 1;
        if (k < s.size() && (s[k] == '+' || s[k] == '-')) ++k;
        if (k < s.size() && std::isdigit(static_cast<unsigned char>(s[k]))) {
          j = k;
          while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
        }
      }
      kind = Tok::Number;
      tok = s.substr(i, j - i);
      i = j;
    } else if (std::isalpha(c) || c == '_') {
      size_t j = i;
      while (j < s.size() && (std::isalnum(static_cast<unsigned char>(s[j])) || s[j] == '_')) ++j;
      kind = Tok::Name;
      tok = s.substr(i, j - i);
      i = j;
    } else if (c == '(' || c == '[') {
      kind = Tok::Open;
      tok = "(";
      ++i;
    } else if (c == ')' || c == ']') {
      kind = Tok::Close;
      tok = ")";
      ++i;
    } else {
      kind = Tok::Other;
      tok = s[i++];
    }
    const bool prev_ends = prev == Tok::Number || prev == Tok::Close || prev == Tok::Name;
    const bool starts = kind == Tok::Number || kind == Tok::Name || kind == Tok::Open;
    const bool call = prev == Tok::Name && kind == Tok::Open && !kValueNames.count(prev_name);
    if (prev_ends && starts && !call) out += '*';
    out += tok;
    prev = kind;
    prev_name = kind == Tok::Name ? tok : std::string();
  }
  return out;
}

[[noreturn]] void reject(const std::string& text, const std::string& parsed,
                         const std::string& reason) {
  std::string msg = "invalid expression '" + text + "'";
  if (parsed != text) msg += " (read as '" + parsed + "')";
  throw std::invalid_argument(msg + ": " + reason);
}

}  // namespace

struct Expression::Impl {
  std::string text;
  // The parser holds the addresses of these; they live on the heap with it so moves keep them.
  double x = 0, y = 0, z = 0, t = 0;
  bool constant = true;
  mu::Parser parser;
};

Expression::Expression(const std::string& text) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.text = text;
  const std::string parsed = with_explicit_products(text);
  try {
    m.parser.DefineVar("x", &m.x);
    m.parser.DefineVar("y", &m.y);
    m.parser.DefineVar("z", &m.z);
    m.parser.DefineVar("t", &m.t);
    // muparser 2.3.3 defines _pi as 3.141592653589 (12 digits): 8e-13 off, visible against
    // analytic solutions. Both spellings get the full double.
    constexpr double kPi = 3.14159265358979323846;
    m.parser.DefineConst("pi", kPi);
    m.parser.DefineConst("_pi", kPi);
    m.parser.SetExpr(parsed);
    // GetUsedVar parses with a permissive variable factory, so it reports unknown names by name
    // instead of muparser's less helpful "unexpected token".
    for (const auto& [name, address] : m.parser.GetUsedVar()) {
      (void)address;
      if (!kVariables.count(name))
        reject(text, parsed,
               "unknown variable '" + name +
                   "' (the variables are x, y, z, t; constants pi, _pi, _e)");
      m.constant = false;
    }
    m.parser.Eval();
    // "0,5" (a decimal comma) would otherwise silently evaluate to 5.
    if (m.parser.GetNumResults() != 1)
      reject(text, parsed,
             "it gives " + std::to_string(m.parser.GetNumResults()) +
                 " comma-separated values, expected one");
  } catch (const mu::Parser::exception_type& e) {
    reject(text, parsed, e.GetMsg());
  }
}

Expression::~Expression() = default;
Expression::Expression(Expression&&) noexcept = default;
Expression& Expression::operator=(Expression&&) noexcept = default;

double Expression::operator()(double x, double y, double z, double t) const {
  Impl& m = *impl_;
  m.x = x;
  m.y = y;
  m.z = z;
  m.t = t;
  try {
    return m.parser.Eval();
  } catch (const mu::Parser::exception_type& e) {
    throw std::runtime_error("evaluating '" + m.text + "': " + e.GetMsg());
  }
}

const std::string& Expression::text() const { return impl_->text; }

bool Expression::is_constant() const { return impl_->constant; }

}  // namespace biofsi

namespace biofsi {

namespace {

[[noreturn]] void non_finite(const std::string& key, const std::string& text, double value,
                             const Point& x, double t) {
  std::ostringstream msg;
  msg.precision(17);
  msg << key << ": '" << text << "' is " << (std::isnan(value) ? "NaN" : "infinite")
      << " at (x, y, z) = (" << x[0] << ", " << x[1] << ", " << x[2] << "), t = " << t
      << "; expected an expression that is finite wherever it applies";
  throw NonFiniteExpression(msg.str());
}

}  // namespace

std::function<double(const Point&, double)> space_time_function(const std::string& text,
                                                                const std::string& key) {
  auto e = std::make_shared<Expression>(text);
  return [e, key](const Point& x, double t) {
    const double v = (*e)(x[0], x[1], x[2], t);
    if (!std::isfinite(v)) non_finite(key, e->text(), v, x, t);
    return v;
  };
}

std::array<std::function<double(const Point&, double)>, 3> space_time_functions(
    const std::array<std::string, 3>& texts, const std::string& key) {
  std::array<std::function<double(const Point&, double)>, 3> out;
  for (int d = 0; d < 3; ++d)
    out[d] = space_time_function(texts[d], key + "[" + std::to_string(d) + "]");
  return out;
}

}  // namespace biofsi
