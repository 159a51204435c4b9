// Nodal fields of one hex8 mesh interpolated onto the nodes of another mesh of the same domain: a
// transient run restarted from a checkpoint written on another mesh (a mesh study from a periodic
// state reached on a coarser mesh instead of from rest). Depends on mesh.hpp only.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace biofsi {

// Where a point lies in a set of elements of a source mesh: the element, its trilinear shape
// function values there, and how far outside the element the point is in reference coordinates
// (0 inside). Curved boundaries are chords of different lengths on two meshes, so a node of the
// target mesh on the cylinder may lie a little outside every source element; it takes the
// nearest one, with its reference coordinates clamped to the element.
struct NodalWeights {
  int element = -1;
  std::array<double, 8> n{};
  double outside = 0;
};

class NodalInterpolator {
 public:
  // `slack`: how far outside (reference coordinates, element size 2) a point may be and still take
  // the nearest element; farther is an error (the meshes do not cover the same domain).
  NodalInterpolator(const Mesh& from, std::vector<int> elements, double slack = 0.05)
      : mesh_(from), elements_(std::move(elements)), slack_(slack) {
    if (elements_.empty()) throw std::invalid_argument("mesh transfer: no source elements");
    build_buckets();
  }

  NodalWeights locate(const Point& x) const {
    NodalWeights best;
    best.outside = HUGE_VAL;
    const std::array<int, 3> c = cell_of(x);
    // The point's cell first; its neighbours too when it lies outside every element there.
    for (int reach = 0; reach <= 1 && !(best.outside <= 0); ++reach)
      for (int i = std::max(0, c[0] - reach); i <= std::min(dims_[0] - 1, c[0] + reach); ++i)
        for (int j = std::max(0, c[1] - reach); j <= std::min(dims_[1] - 1, c[1] + reach); ++j)
          for (int k = std::max(0, c[2] - reach); k <= std::min(dims_[2] - 1, c[2] + reach); ++k)
            for (int e : buckets_[index(i, j, k)]) {
              const NodalWeights w = weights_in(e, x);
              if (w.outside < best.outside) best = w;
              if (best.outside <= 0) return best;
            }
    if (!(best.outside <= slack_)) {
      std::ostringstream m;
      m << "mesh transfer: point (" << x[0] << ", " << x[1] << ", " << x[2]
        << ") is in no source element (nearest " << best.outside
        << " outside in reference coordinates, at most " << slack_ << " accepted)";
      throw std::runtime_error(m.str());
    }
    return best;
  }

  // sum_a N_a values[conn[a]] for nodal values of any type with + and scalar *.
  template <class T>
  T interpolate(const NodalWeights& w, const std::vector<T>& values) const {
    const auto& c = mesh_.conn[w.element];
    T out = scaled(values[c[0]], w.n[0]);
    for (int a = 1; a < 8; ++a) add_scaled(out, values[c[a]], w.n[a]);
    return out;
  }

 private:
  static double scaled(double v, double s) { return v * s; }
  static Point scaled(const Point& v, double s) { return {v[0] * s, v[1] * s, v[2] * s}; }
  static void add_scaled(double& out, double v, double s) { out += v * s; }
  static void add_scaled(Point& out, const Point& v, double s) {
    for (int d = 0; d < 3; ++d) out[d] += v[d] * s;
  }

  // The shape functions at the reference point clamped to the element.
  NodalWeights weights_in(int e, const Point& x) const {
    std::array<double, 3> xi = hex8_reference_coordinates(mesh_, e, x);
    NodalWeights w;
    w.element = e;
    for (int k = 0; k < 3; ++k) {
      w.outside = std::max(w.outside, std::abs(xi[k]) - 1 - 1e-10);
      xi[k] = std::max(-1.0, std::min(1.0, xi[k]));
    }
    w.outside = std::max(w.outside, 0.0);
    w.n = hex8_shape_values(xi);
    return w;
  }

  // A uniform grid of about one cell per element over the elements' bounding boxes; each cell
  // lists the elements whose box overlaps it.
  void build_buckets() {
    std::vector<std::array<Point, 2>> boxes;
    Point mean_size{0, 0, 0};
    lo_ = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
    Point hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (int e : elements_) {
      const auto [b_lo, b_hi] = element_bounds(mesh_, e);
      const std::array<Point, 2> b{b_lo, b_hi};
      for (int d = 0; d < 3; ++d) {
        mean_size[d] += (b[1][d] - b[0][d]) / elements_.size();
        lo_[d] = std::min(lo_[d], b[0][d]);
        hi[d] = std::max(hi[d], b[1][d]);
      }
      boxes.push_back(b);
    }
    for (int d = 0; d < 3; ++d) {
      const double extent = hi[d] - lo_[d];
      dims_[d] = mean_size[d] > 0 ? std::max(1, static_cast<int>(extent / mean_size[d])) : 1;
      dims_[d] = std::min(dims_[d], 4096);
      cell_[d] = extent > 0 ? extent / dims_[d] : 1.0;
    }
    buckets_.assign(static_cast<size_t>(dims_[0]) * dims_[1] * dims_[2], {});
    for (size_t i = 0; i < elements_.size(); ++i) {
      const std::array<int, 3> a = cell_of(boxes[i][0]), b = cell_of(boxes[i][1]);
      for (int p = a[0]; p <= b[0]; ++p)
        for (int q = a[1]; q <= b[1]; ++q)
          for (int r = a[2]; r <= b[2]; ++r) buckets_[index(p, q, r)].push_back(elements_[i]);
    }
  }

  std::array<int, 3> cell_of(const Point& x) const {
    std::array<int, 3> c{};
    for (int d = 0; d < 3; ++d)
      c[d] = std::max(0, std::min(dims_[d] - 1, static_cast<int>((x[d] - lo_[d]) / cell_[d])));
    return c;
  }
  size_t index(int i, int j, int k) const {
    return (static_cast<size_t>(k) * dims_[1] + j) * dims_[0] + i;
  }

  const Mesh& mesh_;
  std::vector<int> elements_;
  double slack_;
  Point lo_{}, cell_{};
  std::array<int, 3> dims_{1, 1, 1};
  std::vector<std::vector<int>> buckets_;
};

}  // namespace biofsi
