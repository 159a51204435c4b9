// A scalar expression in x, y, z, t (muparser), e.g. "0.5 + 0.5*cos(0.2*_pi*x)"; `pi` and `_pi`
// both mean pi. As papers write them, [] group like () and juxtaposition multiplies:
// "[0.5+0.5cos(0.2 pi x)][1+cos(0.05 pi y)]" is read as "(0.5+0.5*cos(0.2*pi*x))*(1+cos(...))".
// Host only; not thread-safe (one parser per object).
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

#include "mesh/mesh.hpp"

namespace biofsi {

class Expression {
 public:
  // Throws std::invalid_argument naming the expression and muparser's reason if it does not parse
  // or uses variables other than x, y, z, t.
  explicit Expression(const std::string& text);
  ~Expression();
  Expression(Expression&&) noexcept;
  Expression& operator=(Expression&&) noexcept;

  double operator()(double x, double y, double z, double t) const;
  const std::string& text() const;
  bool is_constant() const;  // uses none of x, y, z, t

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// An expression that is NaN or infinite where it is used: sqrt(-1), 1/0, 10^400, 1/(t-2) at t = 2.
// The message names the scene key, the expression, the point and the time.
class NonFiniteExpression : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The expression as a function of a point and time (boundary and initial data of the fields).
// Every value is checked: a NaN or infinite one throws NonFiniteExpression naming `key` (the
// scene key the expression was read from, e.g. "fields.scalar.initial"), whenever it is met.
std::function<double(const Point&, double)> space_time_function(const std::string& text,
                                                                const std::string& key);
// A vector field of 3 expressions, read from the list `key` (components named key[0..2]).
std::array<std::function<double(const Point&, double)>, 3> space_time_functions(
    const std::array<std::string, 3>& texts, const std::string& key);

}  // namespace biofsi
