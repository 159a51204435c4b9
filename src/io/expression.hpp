// A scalar expression in x, y, z, t (muparser), e.g. "0.5 + 0.5*cos(0.2*_pi*x)"; `pi` and `_pi`
// both mean pi. As papers write them, [] group like () and juxtaposition multiplies:
// "[0.5+0.5cos(0.2 pi x)][1+cos(0.05 pi y)]" is read as "(0.5+0.5*cos(0.2*pi*x))*(1+cos(...))".
// Host only; not thread-safe (one parser per object).
#pragma once

#include <functional>
#include <memory>
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

// The expression as a function of a point and time (boundary and initial data of the fields).
std::function<double(const Point&, double)> space_time_function(const std::string& text);

}  // namespace biofsi
