// Model matrices for the solver tests, built on the host and copied to the execution space:
// finite-difference stencils on the interior nodes of an m x m x m grid with homogeneous Dirichlet
// boundaries (the boundary nodes are eliminated, so every matrix here is nonsingular).
#pragma once

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "solvers/solvers.hpp"

namespace biofsi::test {

struct HostCsr {
  int n_rows = 0;
  std::vector<int> row_ptr{0}, col;
  std::vector<double> val;

  void add(int c, double v) {
    col.push_back(c);
    val.push_back(v);
  }
  void end_row() {
    row_ptr.push_back(static_cast<int>(col.size()));
    ++n_rows;
  }
  std::vector<double> multiply(const std::vector<double>& x) const {
    std::vector<double> y(n_rows, 0.0);
    for (int r = 0; r < n_rows; ++r)
      for (int k = row_ptr[r]; k < row_ptr[r + 1]; ++k) y[r] += val[k] * x[col[k]];
    return y;
  }
};

// The vector copies are the library's (src/solvers/solvers.hpp); this file adds the CSR one.
using biofsi::to_device;
using biofsi::to_host;

inline CsrMatrix to_device(const HostCsr& h) {
  CsrMatrix a;
  a.n_rows = h.n_rows;
  a.row_ptr = to_device(h.row_ptr, "test::row_ptr");
  a.col = to_device(h.col, "test::col");
  a.val = to_device(h.val, "test::val");
  return a;
}

// Upwind convection-diffusion -lap u + beta . grad u on the unit cube's interior grid, scaled by
// h^2: the 7-point Laplacian (diagonal 6, neighbours -1) plus first-order upwind differences of a
// positive velocity whose cell Peclet numbers are h * beta. beta = 0 gives the SPD Laplacian.
// Columns come out sorted because the neighbours are visited in increasing index order.
inline HostCsr convection_diffusion(int m, std::array<double, 3> cell_peclet = {0, 0, 0}) {
  HostCsr a;
  const double px = cell_peclet[0], py = cell_peclet[1], pz = cell_peclet[2];
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        const int r = i + m * (j + m * k);
        if (k > 0) a.add(r - m * m, -1.0 - pz);
        if (j > 0) a.add(r - m, -1.0 - py);
        if (i > 0) a.add(r - 1, -1.0 - px);
        a.add(r, 6.0 + px + py + pz);
        if (i < m - 1) a.add(r + 1, -1.0);
        if (j < m - 1) a.add(r + m, -1.0);
        if (k < m - 1) a.add(r + m * m, -1.0);
        a.end_row();
      }
  return a;
}

inline HostCsr poisson(int m) { return convection_diffusion(m); }

// Kronecker product L (x) C of the scalar Laplacian with a small dense coupling matrix, with
// interleaved dofs (dof = node * nc + component), the layout of biofsi's vector fields.
inline HostCsr coupled_laplacian(int m, const std::vector<std::vector<double>>& c) {
  const HostCsr l = poisson(m);
  const int nc = static_cast<int>(c.size());
  HostCsr a;
  for (int node = 0; node < l.n_rows; ++node)
    for (int ci = 0; ci < nc; ++ci) {
      for (int k = l.row_ptr[node]; k < l.row_ptr[node + 1]; ++k)
        for (int cj = 0; cj < nc; ++cj)
          if (c[ci][cj] != 0) a.add(l.col[k] * nc + cj, l.val[k] * c[ci][cj]);
      a.end_row();
    }
  return a;
}

// A smooth field with an oscillating component, so that no Krylov method gets it for free.
inline std::vector<double> manufactured(int n) {
  std::vector<double> x(n);
  for (int i = 0; i < n; ++i) x[i] = std::sin(0.37 * i) + 0.5 * std::cos(0.011 * i) + 0.1;
  return x;
}

inline double norm(const std::vector<double>& x) {
  double s = 0;
  for (double v : x) s += v * v;
  return std::sqrt(s);
}

inline double distance(const std::vector<double>& x, const std::vector<double>& y) {
  double s = 0;
  for (size_t i = 0; i < x.size(); ++i) s += (x[i] - y[i]) * (x[i] - y[i]);
  return std::sqrt(s);
}

inline ApplyFn matrix_operator(const CsrMatrix& a) {
  return [a](ConstVector x, Vector y) { csr_multiply(a, x, y); };
}

}  // namespace biofsi::test
