// Numbers from environment variables, for the long runs' studies (mesh, step, end time...): a
// value that does not parse as a finite number fails the test and leaves the default in place.
// Header-only; any test may include it.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

namespace biofsi {
namespace test {

inline double env_or(const char* name, double fallback) {
  const char* v = std::getenv(name);
  if (!v || !*v) return fallback;
  char* end = nullptr;
  const double x = std::strtod(v, &end);
  if (end == v || *end != '\0' || !std::isfinite(x)) {
    ADD_FAILURE() << "environment variable " << name << " = '" << v << "': expected a number";
    return fallback;
  }
  return x;
}

}  // namespace test
}  // namespace biofsi
