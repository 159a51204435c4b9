// Time-stepping helpers every field and the FSI share: step cutting and pseudo-transient
// continuation of a steady solve.
#include "solvers/solvers.hpp"

namespace biofsi {

NewtonResult retry_in_sub_steps(
    const SolveError& first, const std::string& field, const std::string& label, double dt,
    int max_cuts, const std::function<NewtonResult(double, const std::string&)>& sub_step,
    const std::function<void()>& restore, int& cut_steps) {
  for (int level = 1; level <= max_cuts; ++level) {
    const int n = 1 << level;
    try {
      NewtonResult r;
      for (int i = 0; i < n; ++i)
        r = sub_step(dt / n,
                     label + " (sub-step " + std::to_string(i + 1) + "/" + std::to_string(n) + ")");
      ++cut_steps;
      return r;
    } catch (const SolveError&) {
      restore();
    }
  }
  throw SolveError(field, label,
                   first.why() + "; cutting the step into up to " + std::to_string(1 << max_cuts) +
                       " sub-steps did not help");
}

NewtonResult solve_steady_with_continuation(
    const std::string& field, const std::string& label, Vector state, double& time, int max_steps,
    double dt0, const std::function<NewtonResult(const std::string&)>& steady,
    const std::function<void(double, const std::string&)>& pseudo_step,
    const std::function<void()>& restored, int& pseudo_steps) {
  const int n = static_cast<int>(state.extent(0));
  Vector start(Kokkos::view_alloc(Kokkos::WithoutInitializing, "biofsi::steady_start"), n);
  copy(state, start);
  const double t = time;
  try {
    return steady(label);
  } catch (const SolveError& first) {
    if (max_steps == 0) throw;
    auto restore_start = [&] {
      copy(start, state);
      time = t;
      if (restored) restored();
    };
    restore_start();
    double dt = dt0;
    Vector before(Kokkos::view_alloc(Kokkos::WithoutInitializing, "biofsi::pseudo_before"), n);
    for (int i = 1; i <= max_steps; ++i) {
      copy(state, before);
      try {
        pseudo_step(dt, label + " (pseudo-time step " + std::to_string(i) + ")");
        time = t;
      } catch (const SolveError&) {
        copy(before, state);
        time = t;
        dt /= 4;
        continue;
      }
      ++pseudo_steps;
      dt *= 2;
      axpby(1.0, state, -1.0, before);  // before := state - before
      if (norm2(before) > 1e-3 * norm2(state)) continue;
      copy(state, before);
      try {
        return steady(label + " (after pseudo-time continuation)");
      } catch (const SolveError&) {
        copy(before, state);
      }
    }
    restore_start();
    throw SolveError(field, label,
                     first.why() + "; pseudo-transient continuation (" + std::to_string(max_steps) +
                         " pseudo-time steps) did not reach the steady state either");
  }
}

}  // namespace biofsi
