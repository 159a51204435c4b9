// Mean, amplitude and frequency of a sampled periodic signal, as the Turek & Hron (2006) benchmark
// reports them: over the last full period, mean = (max + min) / 2, amplitude = (max - min) / 2,
// frequency = 1 / period. Extremum times and values are refined by a parabola through each
// discrete extremum and its two neighbours, since the runs resolve a period with only ~20-50 steps.
// Header-only so that the default suite tests it (test_oscillation.cpp) and the long runs use it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <utility>
#include <vector>

namespace biofsi {
namespace test {

// A published row: mean +- amplitude [frequency].
struct Reference {
  double mean, amplitude, frequency;
};

struct Oscillation {
  double mean = 0, amplitude = 0, frequency = 0;
  int periods = 0;  // full periods found in the analysed window
  // Amplitude of the last period relative to the one before, minus 1: ~0 in a periodic state,
  // > 0 while the oscillation still grows (0 when fewer than two periods were found).
  double amplitude_change = 0;
};

// The vertex of the parabola through (t[i-1], y[i-1]), (t[i], y[i]), (t[i+1], y[i+1]) on a uniform
// step: the refined extremum time and value.
inline std::pair<double, double> parabolic_extremum(const std::vector<double>& t,
                                                    const std::vector<double>& y, size_t i) {
  const double a = y[i - 1], b = y[i], c = y[i + 1];
  const double denominator = a - 2 * b + c;
  if (denominator == 0) return {t[i], b};
  const double offset = 0.5 * (a - c) / denominator;  // in steps, within (-1, 1) at an extremum
  const double h = t[i + 1] - t[i];
  return {t[i] + offset * h, b - 0.25 * (a - c) * offset};
}

// The (min, max) of y over the samples [begin, end), each refined by the parabola.
inline std::pair<double, double> refined_extremes(const std::vector<double>& t,
                                                  const std::vector<double>& y, size_t begin,
                                                  size_t end) {
  size_t i_max = begin, i_min = begin;
  for (size_t i = begin; i < end; ++i) {
    if (y[i] > y[i_max]) i_max = i;
    if (y[i] < y[i_min]) i_min = i;
  }
  auto refined = [&](size_t i) {
    return (i > 0 && i + 1 < y.size()) ? parabolic_extremum(t, y, i).second : y[i];
  };
  return {refined(i_min), refined(i_max)};
}

// Periods are delimited by upward crossings of the window's mean, each counted only after the
// signal has been 0.7 RMS deviations (half the amplitude of a sine) below it: step-to-step jitter
// (Crank-Nicolson's undamped pressure mode shows in the forces) cannot then create extra
// periods, as it could extra local maxima near a flat peak. Mean and RMS rather than the
// window's extremes, because a one-step kink (where a run changes its step) would set those
// and hide a small oscillation behind it. Frequency from the last `periods` periods; mean and
// amplitude from the extremes of the last one, each refined by the parabola; amplitude_change
// compares the last period's amplitude with the one before it.
inline Oscillation analyse(const std::vector<double>& t, const std::vector<double>& y,
                           double t_from, int periods) {
  Oscillation o;
  size_t first = 0;
  while (first < t.size() && t[first] < t_from) ++first;
  if (first + 3 > y.size()) return o;
  const double count = static_cast<double>(y.size() - first);
  const double mid = std::accumulate(y.begin() + first, y.end(), 0.0) / count;
  double square_sum = 0;
  for (size_t i = first; i < y.size(); ++i) square_sum += (y[i] - mid) * (y[i] - mid);
  const double arming_depth = 0.7 * std::sqrt(square_sum / count);
  if (!(arming_depth > 0)) return o;
  std::vector<double> crossing_time;
  std::vector<size_t> crossing_index;
  bool armed = false;
  for (size_t i = first + 1; i < y.size(); ++i) {
    if (y[i] < mid - arming_depth) armed = true;
    if (armed && y[i - 1] < mid && y[i] >= mid) {
      const double s = (mid - y[i - 1]) / (y[i] - y[i - 1]);
      crossing_time.push_back(t[i - 1] + s * (t[i] - t[i - 1]));
      crossing_index.push_back(i);
      armed = false;
    }
  }
  if (crossing_time.size() < 2) return o;
  o.periods = static_cast<int>(crossing_time.size()) - 1;
  const int n = std::min(periods, o.periods);
  o.frequency = n / (crossing_time.back() - crossing_time[crossing_time.size() - 1 - n]);
  const size_t k = crossing_index.size();
  const auto last = refined_extremes(t, y, crossing_index[k - 2], crossing_index[k - 1]);
  o.mean = 0.5 * (last.second + last.first);
  o.amplitude = 0.5 * (last.second - last.first);
  if (o.periods >= 2) {
    const auto before = refined_extremes(t, y, crossing_index[k - 3], crossing_index[k - 2]);
    o.amplitude_change = o.amplitude / (0.5 * (before.second - before.first)) - 1;
  }
  return o;
}

// 100 (value / reference - 1); 0 where the reference is 0 (a mean the benchmark does not give).
inline double percent_off(double value, double reference) {
  return reference == 0 ? 0.0 : 100 * (value / reference - 1);
}

// One "[ measured ]" line: the measured row, the published one and the deviations.
inline void report_against(const char* name, const Oscillation& o, const Reference& r) {
  std::printf(
      "[ measured ] %s: %.4e +- %.4e [%.4f Hz] (reference %.4e +- %.4e [%.4g]); mean %+.2f%%, "
      "amplitude %+.2f%%, frequency %+.2f%%; %d periods, amplitude change over the last %+.2f%%\n",
      name, o.mean, o.amplitude, o.frequency, r.mean, r.amplitude, r.frequency,
      percent_off(o.mean, r.mean), percent_off(o.amplitude, r.amplitude),
      percent_off(o.frequency, r.frequency), o.periods, 100 * o.amplitude_change);
}

// The same line for a signal the benchmark does not publish (a part of a force).
inline void report(const char* name, const Oscillation& o) {
  std::printf(
      "[ measured ] %s: %.4e +- %.4e [%.4f Hz]; %d periods, amplitude change over the "
      "last %+.2f%%\n",
      name, o.mean, o.amplitude, o.frequency, o.periods, 100 * o.amplitude_change);
}

}  // namespace test
}  // namespace biofsi
