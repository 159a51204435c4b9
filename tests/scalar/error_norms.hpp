// Host-side reference quadrature for the scalar verification tests, independent of kernels/:
// tensor Gauss rules on hex8 elements with trilinear shape functions on the mesh's current
// coordinates, the L2 and H1-seminorm errors of a nodal (Q1) solution against an exact function
// and its gradient, and the observed order of convergence between two refinements.
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "mesh/mesh.hpp"

namespace biofsi {
namespace test {

using Gradient = std::array<double, 3>;
using ExactFunction = std::function<double(const Point& x)>;
using ExactGradient = std::function<Gradient(const Point& x)>;

// What a quadrature-point callback sees: the element, the physical point, the weight times det J,
// the 8 shape functions (VTK node order) and their physical gradients there.
struct QuadraturePoint {
  int element = 0;
  Point x{};
  double weight = 0;  // Gauss weight * det J
  double shape[8] = {};
  double shape_gradient[8][3] = {};
};

// Calls f(qp) at the n_points^3 Gauss points (n_points = 1, 2 or 3) of each listed element (all
// elements when `elements` is empty). Throws if an element is inverted at a point.
void for_each_quadrature_point(const Mesh& mesh, int n_points, const std::vector<int>& elements,
                               const std::function<void(const QuadraturePoint&)>& f);

struct ErrorNorms {
  double l2 = 0;  // ||u_h - u||_L2
  double h1 = 0;  // |u_h - u|_H1 = ||grad u_h - grad u||_L2
};

// Errors of the nodal solution u (one value per mesh node, interpolated with the trilinear shape
// functions) with a 3x3x3 Gauss rule per element, over the listed elements (all when empty).
ErrorNorms error_norms(const Mesh& mesh, const std::vector<double>& u, const ExactFunction& exact,
                       const ExactGradient& gradient, const std::vector<int>& elements = {});

// Observed order p of e ~ h^p between a coarse and a fine run whose mesh sizes differ by `ratio`.
double observed_order(double error_coarse, double error_fine, double ratio = 2.0);

}  // namespace test
}  // namespace biofsi
