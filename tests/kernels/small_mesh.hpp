// A tiny structured hex8 mesh for kernel tests, self-contained so that the kernel tests build
// without src/ (the CUDA preset compiles only kernels/ and tests/kernels/). It has what the
// element and face drivers need: coordinates and VTK-ordered connectivity as device Views (with
// host mirrors for checks), a smooth non-affine distortion, two element blocks, a CSR sparsity
// pattern, element groups for both scatter policies and boundary face lists; host <-> device
// copies of flat vectors.
#pragma once

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "kernels/core/csr.hpp"
#include "kernels/core/element_loop.hpp"
#include "kernels/core/face.hpp"

namespace biofsi {
namespace test {

using HostVector = std::vector<double>;

inline HostVector to_host(ConstVector v) {
  Kokkos::View<Real*, HostSpace> h(std::string("test::host"), v.extent(0));
  Kokkos::deep_copy(h, v);
  return HostVector(h.data(), h.data() + h.extent(0));
}

inline Vector to_device(const HostVector& v) {
  Vector d(std::string("test::device"), v.size());
  Kokkos::View<const Real*, HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> h(v.data(),
                                                                                  v.size());
  Kokkos::deep_copy(d, h);
  return d;
}

// f(out) on a device vector of n entries, returned on the host.
template <class F>
HostVector host_result(size_t n, F f) {
  Vector out(std::string("test::out"), n);
  f(out);
  return to_host(out);
}

// A CSR matrix copied to the host, for checks.
struct HostCsr {
  std::vector<int> row_ptr, col;
  HostVector val;
  int n_rows() const { return static_cast<int>(row_ptr.size()) - 1; }
  // Position of (r, c), or -1.
  int find(int r, int c) const {
    for (int k = row_ptr[r]; k < row_ptr[r + 1]; ++k)
      if (col[k] == c) return k;
    return -1;
  }
  HostVector multiply(const HostVector& x) const {
    HostVector y(n_rows(), 0.0);
    for (int r = 0; r < n_rows(); ++r)
      for (int k = row_ptr[r]; k < row_ptr[r + 1]; ++k) y[r] += val[k] * x[col[k]];
    return y;
  }
  double max_row_abs_sum() const {
    double m = 0;
    for (int r = 0; r < n_rows(); ++r) {
      double s = 0;
      for (int k = row_ptr[r]; k < row_ptr[r + 1]; ++k) s += std::abs(val[k]);
      m = std::max(m, s);
    }
    return m;
  }
};

inline HostCsr to_host(const CsrMatrix& a) {
  HostCsr h;
  auto rp = Kokkos::create_mirror_view_and_copy(HostSpace(), a.row_ptr);
  auto col = Kokkos::create_mirror_view_and_copy(HostSpace(), a.col);
  h.row_ptr.assign(rp.data(), rp.data() + rp.extent(0));
  h.col.assign(col.data(), col.data() + col.extent(0));
  h.val = to_host(a.val);
  return h;
}

struct SmallMesh {
  int nx = 1, ny = 1, nz = 1;
  double length[3] = {1, 1, 1};
  CoordView x;
  ConnView conn;
  IndexView block;
  CoordView::HostMirror x_host;
  ConnView::HostMirror conn_host;
  IndexView::HostMirror block_host;

  int n_nodes() const { return (nx + 1) * (ny + 1) * (nz + 1); }
  int n_elements() const { return nx * ny * nz; }
  int node(int i, int j, int k) const { return i + (nx + 1) * (j + (ny + 1) * k); }
  int element(int i, int j, int k) const { return i + nx * (j + ny * k); }
};

// Box [0,Lx]x[0,Ly]x[0,Lz] with n elements per direction, moved by a smooth map whose normal
// component vanishes on each side: every side stays a flat rectangle of known area (face tests)
// while interior elements become non-affine (the general case for the kernels). `amplitude` is
// relative to the box size; keep it below ~0.05 so that no element inverts. Elements whose centroid
// has y >= Ly/2 are block 1, the others block 0 (a fluid/biofilm pair with distinct coefficients).
inline SmallMesh make_small_mesh(int nx, int ny, int nz, const double length[3], double amplitude) {
  SmallMesh m;
  m.nx = nx, m.ny = ny, m.nz = nz;
  for (int d = 0; d < 3; ++d) m.length[d] = length[d];
  m.x = CoordView(std::string("test::x"), m.n_nodes());
  m.conn = ConnView(std::string("test::conn"), m.n_elements());
  m.block = IndexView(std::string("test::block"), m.n_elements());
  m.x_host = Kokkos::create_mirror_view(m.x);
  m.conn_host = Kokkos::create_mirror_view(m.conn);
  m.block_host = Kokkos::create_mirror_view(m.block);
  const double pi = std::acos(-1.0);
  const double lx = length[0], ly = length[1], lz = length[2];
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        const double s = double(i) / nx, t = double(j) / ny, r = double(k) / nz;
        const double a = amplitude;
        const int n = m.node(i, j, k);
        m.x_host(n, 0) =
            lx * (s + a * std::sin(pi * s) * std::cos(1.3 * pi * t + 0.4) * std::cos(0.7 * pi * r));
        m.x_host(n, 1) =
            ly * (t + a * std::sin(pi * t) * std::cos(0.9 * pi * s + 0.3) * std::cos(1.1 * pi * r));
        m.x_host(n, 2) =
            lz * (r + a * std::sin(pi * r) * std::cos(1.2 * pi * s) * std::cos(0.8 * pi * t + 0.5));
      }
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int e = m.element(i, j, k);
        const int v[8] = {m.node(i, j, k),
                          m.node(i + 1, j, k),
                          m.node(i + 1, j + 1, k),
                          m.node(i, j + 1, k),
                          m.node(i, j, k + 1),
                          m.node(i + 1, j, k + 1),
                          m.node(i + 1, j + 1, k + 1),
                          m.node(i, j + 1, k + 1)};
        for (int a = 0; a < 8; ++a) m.conn_host(e, a) = v[a];
        m.block_host(e) = (j + 0.5) / ny >= 0.5 ? 1 : 0;
      }
  Kokkos::deep_copy(m.x, m.x_host);
  Kokkos::deep_copy(m.conn, m.conn_host);
  Kokkos::deep_copy(m.block, m.block_host);
  return m;
}

// The 1 x 0.8 x 0.6 box in 5 x 4 x 3 elements with 4% distortion: the y-split puts whole element
// layers in each block.
inline SmallMesh box_5x4x3() {
  const double length[3] = {1.0, 0.8, 0.6};
  return make_small_mesh(5, 4, 3, length, 0.04);
}

inline IndexView to_device(const std::vector<int>& v, const std::string& label) {
  IndexView d(label, v.size());
  auto h = Kokkos::create_mirror_view(d);
  for (size_t i = 0; i < v.size(); ++i) h(i) = v[i];
  Kokkos::deep_copy(d, h);
  return d;
}

// Greedy colouring: each element takes the smallest colour not used by an element sharing a node.
inline std::vector<std::vector<int>> colour_elements(const SmallMesh& m) {
  std::vector<std::vector<int>> elements_of_node(m.n_nodes());
  std::vector<int> elements(m.n_elements());
  for (int e = 0; e < m.n_elements(); ++e) {
    elements[e] = e;
    for (int a = 0; a < 8; ++a) elements_of_node[m.conn_host(e, a)].push_back(e);
  }
  return greedy_colouring(elements, m.n_elements(), [&](int e, auto visit) {
    for (int a = 0; a < 8; ++a)
      for (int other : elements_of_node[m.conn_host(e, a)]) visit(other);
  });
}

inline ElementGroups element_groups(const SmallMesh& m, Scatter scatter) {
  ElementGroups g;
  g.scatter = scatter;
  if (scatter == Scatter::Atomic) {
    std::vector<int> all(m.n_elements());
    for (int e = 0; e < m.n_elements(); ++e) all[e] = e;
    g.groups.push_back(to_device(all, "test::elements"));
  } else {
    for (const auto& group : colour_elements(m))
      g.groups.push_back(to_device(group, "test::colour"));
  }
  return g;
}

// Scalar (one dof per node) pattern: node a couples to every node sharing an element with it.
inline CsrMatrix make_pattern(const SmallMesh& m) {
  std::vector<std::vector<int>> nb(m.n_nodes());
  for (int e = 0; e < m.n_elements(); ++e)
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) nb[m.conn_host(e, a)].push_back(m.conn_host(e, b));
  CsrMatrix a;
  a.n_rows = m.n_nodes();
  a.row_ptr = Kokkos::View<int*, MemSpace>(std::string("test::row_ptr"), a.n_rows + 1);
  auto rp = Kokkos::create_mirror_view(a.row_ptr);
  std::vector<int> cols;
  rp(0) = 0;
  for (int r = 0; r < a.n_rows; ++r) {
    std::sort(nb[r].begin(), nb[r].end());
    nb[r].erase(std::unique(nb[r].begin(), nb[r].end()), nb[r].end());
    cols.insert(cols.end(), nb[r].begin(), nb[r].end());
    rp(r + 1) = static_cast<int>(cols.size());
  }
  Kokkos::deep_copy(a.row_ptr, rp);
  a.col = to_device(cols, "test::col");
  a.val = Kokkos::View<Real*, MemSpace>(std::string("test::val"), cols.size());
  return a;
}

// Boundary faces (element, local face) on the given sides of the box, local faces numbered as in
// kernels/core/face.hpp: 0 x-, 1 x+, 2 y-, 3 y+, 4 z-, 5 z+.
inline FaceView boundary_faces(const SmallMesh& m, const std::vector<int>& sides) {
  std::vector<int> list;
  for (int k = 0; k < m.nz; ++k)
    for (int j = 0; j < m.ny; ++j)
      for (int i = 0; i < m.nx; ++i) {
        const bool on[6] = {i == 0, i == m.nx - 1, j == 0, j == m.ny - 1, k == 0, k == m.nz - 1};
        for (int f : sides)
          if (on[f]) list.insert(list.end(), {m.element(i, j, k), f});
      }
  FaceView faces(std::string("test::faces"), list.size() / 2);
  auto h = Kokkos::create_mirror_view(faces);
  for (size_t n = 0; n < list.size() / 2; ++n) h(n, 0) = list[2 * n], h(n, 1) = list[2 * n + 1];
  Kokkos::deep_copy(faces, h);
  return faces;
}

}  // namespace test
}  // namespace biofsi
