// Values from environment variables, for the long runs' studies (mesh, step, end time...): a
// number that does not parse as a finite one fails the test and leaves the default in place.
// Header-only; any test may include it.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>

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

// The variable's text, or `fallback` where it is unset or empty.
inline std::string env_or(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::string(v) : fallback;
}

}  // namespace test
}  // namespace biofsi
