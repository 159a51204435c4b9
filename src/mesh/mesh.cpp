#include "mesh/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <numeric>
#include <set>
#include <sstream>
#include <stdexcept>

#include "kernels/core/hex8.hpp"

namespace biofsi {

int Mesh::block_index(const std::string& name) const {
  for (size_t b = 0; b < block_names.size(); ++b)
    if (block_names[b] == name) return static_cast<int>(b);
  return -1;
}

std::vector<int> Mesh::elements_of_block(int block) const {
  std::vector<int> out;
  for (int e = 0; e < n_elements(); ++e)
    if (element_block[e] == block) out.push_back(e);
  return out;
}

std::vector<int> Mesh::nodes_of_block(int block) const {
  std::vector<char> seen(x.size(), 0);
  for (int e = 0; e < n_elements(); ++e)
    if (element_block[e] == block)
      for (int n : conn[e]) seen[n] = 1;
  std::vector<int> out;
  for (int n = 0; n < n_nodes(); ++n)
    if (seen[n]) out.push_back(n);
  return out;
}

namespace {

// Node coordinates of a graded 1-D division: element sizes grow geometrically so that the last
// over the first equals `grading`.
std::vector<double> graded_division(double a, double b, int n, double grading) {
  std::vector<double> t(n + 1, 0.0);
  if (n < 1) throw std::invalid_argument("a box block needs at least one element per direction");
  const double r = n > 1 ? std::pow(grading, 1.0 / (n - 1)) : 1.0;
  double h = 1.0, total = 0.0;
  std::vector<double> sizes(n);
  for (int i = 0; i < n; ++i, h *= r) total += (sizes[i] = h);
  for (int i = 0; i < n; ++i) t[i + 1] = t[i] + sizes[i] / total;
  std::vector<double> out(n + 1);
  for (int i = 0; i <= n; ++i) out[i] = a + (b - a) * t[i];
  out[n] = b;
  return out;
}

void add_face(Mesh& m, const std::string& name, int e, int f) {
  m.face_sets[name].push_back({e, f});
}

void finish_node_sets_from_faces(Mesh& m) {
  for (const auto& [name, faces] : m.face_sets) {
    std::set<int> nodes;
    for (const auto& bf : faces)
      for (int k = 0; k < 4; ++k)
        nodes.insert(m.conn[bf.element][hex8_face_nodes[bf.local_face][k]]);
    m.node_sets[name] = std::vector<int>(nodes.begin(), nodes.end());
  }
}

}  // namespace

Mesh make_box_mesh(const BoxSpec& spec) {
  if (spec.blocks.empty()) throw std::invalid_argument("a box mesh needs at least one block");
  Mesh m;
  const auto xs = graded_division(spec.x0, spec.x1, spec.nx, 1.0);
  const auto zs = graded_division(spec.z0, spec.z1, spec.nz, 1.0);
  std::vector<double> ys{spec.blocks[0].y0};
  std::vector<int> block_of_layer;
  for (size_t b = 0; b < spec.blocks.size(); ++b) {
    const auto& blk = spec.blocks[b];
    if (b > 0 && std::abs(blk.y0 - spec.blocks[b - 1].y1) > 1e-12 * (1 + std::abs(blk.y0)))
      throw std::invalid_argument("box block '" + blk.name + "' must start where '" +
                                  spec.blocks[b - 1].name + "' ends");
    if (!(blk.y1 > blk.y0))
      throw std::invalid_argument("box block '" + blk.name + "' has y1 <= y0");
    const auto yb = graded_division(blk.y0, blk.y1, blk.ny, blk.grading);
    ys.insert(ys.end(), yb.begin() + 1, yb.end());
    block_of_layer.insert(block_of_layer.end(), blk.ny, static_cast<int>(b));
    m.block_names.push_back(blk.name);
  }
  const int nx = spec.nx, ny = static_cast<int>(ys.size()) - 1, nz = spec.nz;
  auto node = [&](int i, int j, int k) { return i + (nx + 1) * (j + (ny + 1) * k); };
  m.x.resize(static_cast<size_t>(nx + 1) * (ny + 1) * (nz + 1));
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.x[node(i, j, k)] = {xs[i], ys[j], zs[k]};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int e = m.n_elements();
        m.conn.push_back({node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k),
                          node(i, j + 1, k), node(i, j, k + 1), node(i + 1, j, k + 1),
                          node(i + 1, j + 1, k + 1), node(i, j + 1, k + 1)});
        const int b = block_of_layer[j];
        m.element_block.push_back(b);
        const std::string& bn = spec.blocks[b].name;
        if (i == 0) add_face(m, "left", e, 0), add_face(m, bn + "_left", e, 0);
        if (i == nx - 1) add_face(m, "right", e, 1), add_face(m, bn + "_right", e, 1);
        if (j == 0) add_face(m, "bottom", e, 2);
        if (j == ny - 1) add_face(m, "top", e, 3);
        if (k == 0) add_face(m, "front", e, 4), add_face(m, bn + "_front", e, 4);
        if (k == nz - 1) add_face(m, "back", e, 5), add_face(m, bn + "_back", e, 5);
        if (j + 1 < ny && block_of_layer[j + 1] != b)
          add_face(m, bn + "_" + spec.blocks[block_of_layer[j + 1]].name, e, 3);
      }
  finish_node_sets_from_faces(m);
  m.global_node_id.resize(m.x.size());
  std::iota(m.global_node_id.begin(), m.global_node_id.end(), 0LL);
  m.n_owned_nodes = m.n_nodes();
  return m;
}

std::vector<std::vector<int>> colour_elements(const Mesh& mesh, const std::vector<int>& elements) {
  std::vector<std::vector<int>> elements_of_node(mesh.x.size());
  for (int e : elements)
    for (int n : mesh.conn[e]) elements_of_node[n].push_back(e);
  return greedy_colouring(elements, mesh.n_elements(), [&](int e, auto visit) {
    for (int n : mesh.conn[e])
      for (int other : elements_of_node[n]) visit(other);
  });
}

namespace {
ConstIndexView to_device_indices(const std::vector<int>& v, const char* label) {
  IndexView d(std::string(label), v.size());
  auto h = Kokkos::create_mirror_view(d);
  for (size_t i = 0; i < v.size(); ++i) h(i) = v[i];
  Kokkos::deep_copy(d, h);
  return d;
}
}  // namespace

ElementGroups make_element_groups(const Mesh& mesh, const std::vector<int>& elements,
                                  Scatter scatter) {
  ElementGroups g;
  g.scatter = scatter;
  if (scatter == Scatter::Atomic) {
    g.groups.push_back(to_device_indices(elements, "biofsi::elements"));
  } else {
    for (const auto& group : colour_elements(mesh, elements))
      g.groups.push_back(to_device_indices(group, "biofsi::colour"));
  }
  return g;
}

CsrMatrix make_sparsity(const Mesh& mesh, const std::vector<int>& elements, int nc) {
  const int nn = mesh.n_nodes();
  std::vector<std::vector<int>> neighbours(nn);
  for (int e : elements)
    for (int a : mesh.conn[e])
      for (int b : mesh.conn[e]) neighbours[a].push_back(b);
  CsrMatrix m;
  m.n_rows = nn * nc;
  Kokkos::View<int*, MemSpace> rp("biofsi::row_ptr", m.n_rows + 1);
  auto rph = Kokkos::create_mirror_view(rp);
  std::vector<int> cols;
  rph(0) = 0;
  for (int a = 0; a < nn; ++a) {
    auto& nb = neighbours[a];
    std::sort(nb.begin(), nb.end());
    nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
    if (nb.empty()) nb.push_back(a);  // isolated node: keep a diagonal entry
    for (int ca = 0; ca < nc; ++ca) {
      for (int b : nb)
        for (int cb = 0; cb < nc; ++cb) cols.push_back(b * nc + cb);
      rph(a * nc + ca + 1) = static_cast<int>(cols.size());
    }
  }
  m.row_ptr = rp;
  Kokkos::deep_copy(rp, rph);
  m.col = Kokkos::View<int*, MemSpace>("biofsi::col", cols.size());
  auto ch = Kokkos::create_mirror_view(m.col);
  for (size_t k = 0; k < cols.size(); ++k) ch(k) = cols[k];
  Kokkos::deep_copy(m.col, ch);
  m.val = Kokkos::View<Real*, MemSpace>("biofsi::val", cols.size());
  return m;
}

void copy_coordinates_to_device(const Mesh& mesh, CoordView x) {
  auto xh = Kokkos::create_mirror_view(x);
  for (int n = 0; n < mesh.n_nodes(); ++n)
    for (int d = 0; d < 3; ++d) xh(n, d) = mesh.x[n][d];
  Kokkos::deep_copy(x, xh);
}

DeviceMesh to_device(const Mesh& mesh) {
  DeviceMesh d;
  d.x = CoordView("biofsi::x", mesh.n_nodes());
  copy_coordinates_to_device(mesh, d.x);
  d.conn = ConnView("biofsi::conn", mesh.n_elements());
  auto ch = Kokkos::create_mirror_view(d.conn);
  for (int e = 0; e < mesh.n_elements(); ++e)
    for (int a = 0; a < 8; ++a) ch(e, a) = mesh.conn[e][a];
  Kokkos::deep_copy(d.conn, ch);
  d.element_block = IndexView("biofsi::element_block", mesh.n_elements());
  auto bh = Kokkos::create_mirror_view(d.element_block);
  for (int e = 0; e < mesh.n_elements(); ++e) bh(e) = mesh.element_block[e];
  Kokkos::deep_copy(d.element_block, bh);
  return d;
}

FaceView to_device(const std::vector<BoundaryFace>& faces) {
  FaceView d("biofsi::faces", faces.size());
  auto h = Kokkos::create_mirror_view(d);
  for (size_t i = 0; i < faces.size(); ++i) {
    h(i, 0) = faces[i].element;
    h(i, 1) = faces[i].local_face;
  }
  Kokkos::deep_copy(d, h);
  return d;
}

void add_union_set(Mesh& mesh, const std::vector<std::string>& sets, const std::string& name) {
  std::vector<int> nodes;
  std::vector<BoundaryFace> faces;
  for (const auto& s : sets) {
    nodes.insert(nodes.end(), mesh.node_sets.at(s).begin(), mesh.node_sets.at(s).end());
    faces.insert(faces.end(), mesh.face_sets.at(s).begin(), mesh.face_sets.at(s).end());
  }
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  mesh.node_sets[name] = nodes;
  mesh.face_sets[name] = faces;
}

std::array<double, 8> corner_scaled_jacobians(const Mesh& mesh, const std::array<int, 8>& corners) {
  // Corner c of a VTK hex and its three edge neighbours, ordered so that a right-handed cube has
  // positive determinant at every corner.
  constexpr int corner_edges[8][3] = {{1, 3, 4}, {2, 0, 5}, {3, 1, 6}, {0, 2, 7},
                                      {7, 5, 0}, {4, 6, 1}, {5, 7, 2}, {6, 4, 3}};
  std::array<double, 8> out;
  for (int c = 0; c < 8; ++c) {
    const Point& p = mesh.x[corners[c]];
    double v[3][3], len[3];
    for (int k = 0; k < 3; ++k) {
      const Point& q = mesh.x[corners[corner_edges[c][k]]];
      for (int d = 0; d < 3; ++d) v[k][d] = q[d] - p[d];
      len[k] = std::sqrt(v[k][0] * v[k][0] + v[k][1] * v[k][1] + v[k][2] * v[k][2]);
    }
    const double det = v[0][0] * (v[1][1] * v[2][2] - v[1][2] * v[2][1]) -
                       v[0][1] * (v[1][0] * v[2][2] - v[1][2] * v[2][0]) +
                       v[0][2] * (v[1][0] * v[2][1] - v[1][1] * v[2][0]);
    const double denom = len[0] * len[1] * len[2];
    out[c] = denom > 0 ? det / denom : 0.0;  // a zero-length edge: no volume at this corner
  }
  return out;
}

std::vector<double> scaled_jacobians(const Mesh& mesh) {
  std::vector<double> out(mesh.conn.size());
  for (int e = 0; e < mesh.n_elements(); ++e) {
    const auto q = corner_scaled_jacobians(mesh, mesh.conn[e]);
    out[e] = std::min(1.0, *std::min_element(q.begin(), q.end()));
  }
  return out;
}

namespace {

Point minus(const Point& a, const Point& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Point cross(const Point& a, const Point& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot3(const Point& a, const Point& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// A quadrilateral whose edges cross (a bow-tie): two neighbouring corners turn one way and the
// other two the other way. A concave (dart) quadrilateral has one corner against three instead.
bool is_bow_tie(const Mesh& mesh, const std::array<int, 8>& corners, int face) {
  Point p[4];
  for (int k = 0; k < 4; ++k) p[k] = mesh.x[corners[hex8_face_nodes[face][k]]];
  Point turn[4];
  for (int k = 0; k < 4; ++k)
    turn[k] = cross(minus(p[(k + 1) % 4], p[k]), minus(p[(k + 3) % 4], p[k]));
  int against = 0;
  for (int k = 1; k < 4; ++k) against += dot3(turn[k], turn[0]) < 0 ? 1 : 0;
  return against == 2;
}

}  // namespace

ElementCheck check_element(const Mesh& mesh, const std::array<int, 8>& corners) {
  const auto q = corner_scaled_jacobians(mesh, corners);
  ElementCheck r;
  r.corner = static_cast<int>(std::min_element(q.begin(), q.end()) - q.begin());
  r.value = q[r.corner];
  int positive = 0, negative = 0;
  for (int c = 0; c < 8; ++c) {
    // Written so that a NaN corner counts as degenerate.
    if (!(std::abs(q[c]) > kDegenerateJacobian)) {
      r.shape = ElementShape::Degenerate;
      r.corner = c;
      r.value = q[c];
      return r;
    }
    (q[c] > 0 ? positive : negative) += 1;
  }
  if (positive == 8) return r;
  if (negative == 8) {
    r.shape = ElementShape::Mirrored;
    return r;
  }
  r.shape = ElementShape::Inverted;
  for (int f = 0; f < 6; ++f)
    if (is_bow_tie(mesh, corners, f)) r.shape = ElementShape::Folded;
  return r;
}

const char* shape_name(ElementShape shape) {
  switch (shape) {
    case ElementShape::Valid:
      return "valid";
    case ElementShape::Mirrored:
      return "mirrored";
    case ElementShape::Degenerate:
      return "degenerate";
    case ElementShape::Folded:
      return "folded";
    case ElementShape::Inverted:
      return "inverted";
  }
  return "?";
}

std::array<int, 8> reorient(std::array<int, 8> corners) {
  std::swap(corners[1], corners[3]);
  std::swap(corners[5], corners[7]);
  return corners;
}

unsigned long long available_memory() {
  unsigned long long available = 0;
  std::ifstream meminfo("/proc/meminfo");
  for (std::string key; meminfo >> key;) {
    unsigned long long kib = 0;
    meminfo >> kib;
    if (key == "MemAvailable:") {
      available = kib * 1024;
      break;
    }
    meminfo.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  // A container's limit (cgroup v2) can be far below the machine's memory.
  unsigned long long limit = 0, used = 0;
  std::ifstream max_in("/sys/fs/cgroup/memory.max"), current_in("/sys/fs/cgroup/memory.current");
  if (max_in >> limit && current_in >> used) {
    const unsigned long long room = limit > used ? limit - used : 0;
    available = available ? std::min(available, room) : room;
  }
  return available;
}

std::string memory_shortfall(long long nodes) {
  const unsigned long long available = available_memory();
  const double needed = kRunBytesPerNode * static_cast<double>(nodes);
  if (available == 0 || needed <= static_cast<double>(available)) return "";
  std::ostringstream s;
  s << std::fixed << std::setprecision(1) << nodes << " nodes need at least " << needed / 1e9
    << " GB (" << std::setprecision(0) << kRunBytesPerNode << " bytes per node), more than the "
    << std::setprecision(1) << available / 1e9 << " GB of memory available";
  return s.str();
}

DofMap make_dof_map(const Mesh& mesh, int n_components) {
  DofMap d;
  d.n_components = n_components;
  d.n_nodes = mesh.n_nodes();
  d.n_owned_nodes = mesh.n_owned_nodes;
  return d;
}

Kokkos::View<char*, MemSpace> Constraints::mask(int n_dofs) const {
  Kokkos::View<char*, MemSpace> m("biofsi::constraint_mask", n_dofs);
  auto h = Kokkos::create_mirror_view(m);
  for (const auto& [dof, v] : value) h(dof) = 1;
  Kokkos::deep_copy(m, h);
  return m;
}

namespace {
// One column of the constraint map (its dofs or its values), on the device.
template <class View, class Pick>
View constraint_column(const std::map<int, double>& value, const char* label, Pick pick) {
  View d(std::string(label), value.size());
  auto h = Kokkos::create_mirror_view(d);
  size_t i = 0;
  for (const auto& kv : value) h(i++) = pick(kv);
  Kokkos::deep_copy(d, h);
  return d;
}
}  // namespace

IndexView Constraints::dofs() const {
  return constraint_column<IndexView>(value, "biofsi::constrained_dofs",
                                      [](const auto& kv) { return kv.first; });
}

Vector Constraints::values() const {
  return constraint_column<Vector>(value, "biofsi::constrained_values",
                                   [](const auto& kv) { return kv.second; });
}

int position_in_sorted(const std::vector<int>& sorted, int node) {
  const auto it = std::lower_bound(sorted.begin(), sorted.end(), node);
  return it != sorted.end() && *it == node ? static_cast<int>(it - sorted.begin()) : -1;
}

int wall_axis(const Point& n, const std::string& set) {
  int axis = 0;
  for (int d = 1; d < 3; ++d)
    if (std::abs(n[d]) > std::abs(n[axis])) axis = d;
  if (std::abs(std::abs(n[axis]) - 1.0) > 1e-8)
    throw std::invalid_argument(
        "mesh motion: nodes can slide only along axis-aligned walls; set '" + set + "' is not one");
  return axis;
}

Point face_area_vector(const Mesh& mesh, const BoundaryFace& f) {
  const auto& c = mesh.conn[f.element];
  Point x[4];
  for (int k = 0; k < 4; ++k) x[k] = mesh.x[c[hex8_face_nodes[f.local_face][k]]];
  Point d1, d2, centre{0, 0, 0}, fc{0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    d1[i] = x[2][i] - x[0][i];
    d2[i] = x[3][i] - x[1][i];
    for (int k = 0; k < 4; ++k) fc[i] += 0.25 * x[k][i];
    for (int a = 0; a < 8; ++a) centre[i] += 0.125 * mesh.x[c[a]][i];
  }
  Point n{0.5 * (d1[1] * d2[2] - d1[2] * d2[1]), 0.5 * (d1[2] * d2[0] - d1[0] * d2[2]),
          0.5 * (d1[0] * d2[1] - d1[1] * d2[0])};
  double s = 0;
  for (int i = 0; i < 3; ++i) s += n[i] * (fc[i] - centre[i]);
  if (s < 0)
    for (double& v : n) v = -v;
  return n;
}

std::vector<BoundaryFace> faces_of_block(const Mesh& mesh, const std::string& set, int block) {
  std::vector<BoundaryFace> out;
  for (const auto& f : mesh.face_sets.at(set))
    if (mesh.element_block[f.element] == block) out.push_back(f);
  return out;
}

bool lists_both_sides(const Mesh& mesh, const std::string& set) {
  std::set<std::array<int, 4>> seen;
  for (const auto& f : mesh.face_sets.at(set)) {
    std::array<int, 4> key;
    for (int k = 0; k < 4; ++k) key[k] = mesh.conn[f.element][hex8_face_nodes[f.local_face][k]];
    std::sort(key.begin(), key.end());
    if (!seen.insert(key).second) return true;
  }
  return false;
}

WeakestNormal weakest_nodal_normal(const Mesh& mesh, const std::string& set) {
  const auto& nodes = mesh.node_sets.at(set);
  std::vector<Point> sum(nodes.size(), Point{0, 0, 0});
  std::vector<double> area(nodes.size(), 0.0);
  for (const auto& f : mesh.face_sets.at(set)) {
    const Point a = face_area_vector(mesh, f);
    for (int k = 0; k < 4; ++k) {
      const int i =
          position_in_sorted(nodes, mesh.conn[f.element][hex8_face_nodes[f.local_face][k]]);
      for (int c = 0; c < 3; ++c) sum[i][c] += a[c];
      area[i] += std::sqrt(dot3(a, a));
    }
  }
  WeakestNormal w;
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (!(area[i] > 0)) continue;
    const double ratio = std::sqrt(dot3(sum[i], sum[i])) / area[i];
    if (ratio < w.ratio || w.node < 0) w = {ratio, nodes[i]};
  }
  return w;
}

std::vector<Point> nodal_normals(const Mesh& mesh, const std::string& set) {
  const auto& nodes = mesh.node_sets.at(set);
  std::vector<Point> n(nodes.size(), Point{0, 0, 0});
  for (const auto& f : mesh.face_sets.at(set)) {
    const Point a = face_area_vector(mesh, f);
    for (int k = 0; k < 4; ++k) {
      const int i =
          position_in_sorted(nodes, mesh.conn[f.element][hex8_face_nodes[f.local_face][k]]);
      for (int c = 0; c < 3; ++c) n[i][c] += a[c] / 4;
    }
  }
  for (auto& v : n) {
    const double len = std::sqrt(dot3(v, v));
    if (len > 0)
      for (auto& c : v) c /= len;
  }
  return n;
}

namespace {
// VTK corner signs of the reference cell.
constexpr double corner_x[8] = {-1, 1, 1, -1, -1, 1, 1, -1};
constexpr double corner_y[8] = {-1, -1, 1, 1, -1, -1, 1, 1};
constexpr double corner_z[8] = {-1, -1, -1, -1, 1, 1, 1, 1};
}  // namespace

std::array<double, 8> hex8_shape_values(const std::array<double, 3>& xi) {
  std::array<double, 8> n{};
  for (int a = 0; a < 8; ++a)
    n[a] =
        0.125 * (1 + corner_x[a] * xi[0]) * (1 + corner_y[a] * xi[1]) * (1 + corner_z[a] * xi[2]);
  return n;
}

void hex8_jacobian(const Mesh& mesh, const std::array<int, 8>& corners,
                   const std::array<double, 3>& xi, double jac[3][3]) {
  for (int d = 0; d < 3; ++d)
    for (int k = 0; k < 3; ++k) jac[d][k] = 0;
  for (int a = 0; a < 8; ++a) {
    const double bx = 0.5 * (1 + corner_x[a] * xi[0]), by = 0.5 * (1 + corner_y[a] * xi[1]),
                 bz = 0.5 * (1 + corner_z[a] * xi[2]);
    const double g[3] = {0.5 * corner_x[a] * by * bz, bx * 0.5 * corner_y[a] * bz,
                         bx * by * 0.5 * corner_z[a]};
    for (int d = 0; d < 3; ++d)
      for (int k = 0; k < 3; ++k) jac[d][k] += g[k] * mesh.x[corners[a]][d];
  }
}

std::pair<Point, Point> element_bounds(const Mesh& mesh, int e) {
  const auto& c = mesh.conn[e];
  Point lo = mesh.x[c[0]], hi = lo;
  for (int a = 1; a < 8; ++a)
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], mesh.x[c[a]][d]);
      hi[d] = std::max(hi[d], mesh.x[c[a]][d]);
    }
  return {lo, hi};
}

std::array<double, 3> hex8_reference_coordinates(const Mesh& mesh, int e, const Point& x) {
  const auto& c = mesh.conn[e];
  std::array<double, 3> xi{0, 0, 0};
  for (int it = 0; it < 30; ++it) {
    const std::array<double, 8> n = hex8_shape_values(xi);
    double f[3] = {-x[0], -x[1], -x[2]}, jac[3][3], inv[3][3];
    for (int a = 0; a < 8; ++a)
      for (int d = 0; d < 3; ++d) f[d] += n[a] * mesh.x[c[a]][d];
    hex8_jacobian(mesh, c, xi, jac);
    invert_jacobian(jac, inv);
    double step = 0;
    for (int k = 0; k < 3; ++k) {
      const double dk = inv[k][0] * f[0] + inv[k][1] * f[1] + inv[k][2] * f[2];
      xi[k] = std::max(-3.0, std::min(3.0, xi[k] - dk));
      step = std::max(step, std::abs(dk));
    }
    if (step < 1e-14) break;
  }
  return xi;
}

}  // namespace biofsi
