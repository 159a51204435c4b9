#include "scalar/error_norms.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace biofsi {
namespace test {

namespace {

// Reference coordinates of the VTK hexahedron's nodes on [-1,1]^3.
constexpr double reference_node[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                         {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

// 1-D Gauss-Legendre rules on [-1,1].
void gauss_rule(int n, double* points, double* weights) {
  if (n == 1) {
    points[0] = 0;
    weights[0] = 2;
  } else if (n == 2) {
    points[0] = -1 / std::sqrt(3.0);
    points[1] = -points[0];
    weights[0] = weights[1] = 1;
  } else if (n == 3) {
    points[0] = -std::sqrt(0.6);
    points[1] = 0;
    points[2] = std::sqrt(0.6);
    weights[0] = weights[2] = 5.0 / 9.0;
    weights[1] = 8.0 / 9.0;
  } else {
    throw std::invalid_argument("reference quadrature has 1, 2 or 3 points per direction");
  }
}

}  // namespace

void for_each_quadrature_point(const Mesh& mesh, int n_points, const std::vector<int>& elements,
                               const std::function<void(const QuadraturePoint&)>& f) {
  double points[3], weights[3];
  gauss_rule(n_points, points, weights);
  std::vector<int> all;
  if (elements.empty()) {
    all.resize(mesh.n_elements());
    for (int e = 0; e < mesh.n_elements(); ++e) all[e] = e;
  }
  const std::vector<int>& list = elements.empty() ? all : elements;
  QuadraturePoint qp;
  for (int e : list) {
    qp.element = e;
    for (int k = 0; k < n_points; ++k)
      for (int j = 0; j < n_points; ++j)
        for (int i = 0; i < n_points; ++i) {
          const double xi[3] = {points[i], points[j], points[k]};
          double dref[8][3];
          for (int a = 0; a < 8; ++a) {
            double v[3], d[3];
            for (int c = 0; c < 3; ++c) {
              v[c] = 0.5 * (1 + reference_node[a][c] * xi[c]);
              d[c] = 0.5 * reference_node[a][c];
            }
            qp.shape[a] = v[0] * v[1] * v[2];
            dref[a][0] = d[0] * v[1] * v[2];
            dref[a][1] = v[0] * d[1] * v[2];
            dref[a][2] = v[0] * v[1] * d[2];
          }
          // jac[c][d] = dx_c / dxi_d
          double jac[3][3] = {}, x[3] = {};
          for (int a = 0; a < 8; ++a) {
            const Point& p = mesh.x[mesh.conn[e][a]];
            for (int c = 0; c < 3; ++c) {
              x[c] += qp.shape[a] * p[c];
              for (int d = 0; d < 3; ++d) jac[c][d] += p[c] * dref[a][d];
            }
          }
          const double det = jac[0][0] * (jac[1][1] * jac[2][2] - jac[1][2] * jac[2][1]) -
                             jac[0][1] * (jac[1][0] * jac[2][2] - jac[1][2] * jac[2][0]) +
                             jac[0][2] * (jac[1][0] * jac[2][1] - jac[1][1] * jac[2][0]);
          if (!(det > 0))
            throw std::runtime_error("reference quadrature: element " + std::to_string(e) +
                                     " is inverted");
          // inv[d][c] = dxi_d / dx_c = cofactor(jac)[c][d] / det (cyclic index form).
          double inv[3][3];
          for (int d = 0; d < 3; ++d)
            for (int c = 0; c < 3; ++c) {
              const int r1 = (c + 1) % 3, r2 = (c + 2) % 3, s1 = (d + 1) % 3, s2 = (d + 2) % 3;
              inv[d][c] = (jac[r1][s1] * jac[r2][s2] - jac[r1][s2] * jac[r2][s1]) / det;
            }
          for (int a = 0; a < 8; ++a)
            for (int c = 0; c < 3; ++c)
              qp.shape_gradient[a][c] =
                  dref[a][0] * inv[0][c] + dref[a][1] * inv[1][c] + dref[a][2] * inv[2][c];
          qp.x = {x[0], x[1], x[2]};
          qp.weight = weights[i] * weights[j] * weights[k] * det;
          f(qp);
        }
  }
}

ErrorNorms error_norms(const Mesh& mesh, const std::vector<double>& u, const ExactFunction& exact,
                       const ExactGradient& gradient, const std::vector<int>& elements) {
  if (static_cast<int>(u.size()) != mesh.n_nodes())
    throw std::invalid_argument("error_norms: one value per mesh node expected");
  double l2 = 0, h1 = 0;
  for_each_quadrature_point(mesh, 3, elements, [&](const QuadraturePoint& qp) {
    double uh = 0, guh[3] = {0, 0, 0};
    for (int a = 0; a < 8; ++a) {
      const double ua = u[mesh.conn[qp.element][a]];
      uh += qp.shape[a] * ua;
      for (int c = 0; c < 3; ++c) guh[c] += qp.shape_gradient[a][c] * ua;
    }
    const double e = uh - exact(qp.x);
    const Gradient g = gradient(qp.x);
    double ge = 0;
    for (int c = 0; c < 3; ++c) ge += (guh[c] - g[c]) * (guh[c] - g[c]);
    l2 += qp.weight * e * e;
    h1 += qp.weight * ge;
  });
  return {std::sqrt(l2), std::sqrt(h1)};
}

double observed_order(double error_coarse, double error_fine, double ratio) {
  return std::log(error_coarse / error_fine) / std::log(ratio);
}

}  // namespace test
}  // namespace biofsi
