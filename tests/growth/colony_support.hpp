// A circular colony in a circular fluid domain, for the colony tests: the mesh (an O-grid of a disc
// of radius 1, block "biofilm", in an annulus out to radius r_outer, block "fluid", extruded into
// one hex layer) with its interface listed once per side as a Gmsh mesh lists it, and the steady
// radially symmetric Monod solution, in 2-D and 3-D, that the transport on it (and on the 3-D
// hemisphere of test_colony3d.cpp) approximates.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "growth/growth.hpp"
#include "mesh/mesh.hpp"
#include "scalar/transport.hpp"

namespace colony {

using biofsi::Mesh;
using biofsi::Point;

// The colony tests' substrate: Monod consumption in the biofilm (block 0), diffusion in the fluid
// (block 1), Newton to near round-off so that the flux is the discretisation's.
constexpr double kBiofilmDiffusivity = 0.5, kMonodRate = 0.1, kHalfSaturation = 0.1;
constexpr double kFluidDiffusivity = 1.0;

inline biofsi::TransportSettings monod_settings() {
  biofsi::TransportSettings ts;
  ts.coefficients.diffusivity[0] = kBiofilmDiffusivity;
  ts.coefficients.monod_rate[0] = kMonodRate;
  ts.coefficients.monod_half_saturation[0] = kHalfSaturation;
  ts.coefficients.diffusivity[1] = kFluidDiffusivity;
  ts.newton.rel_tol = 1e-12;
  ts.newton.abs_tol = 1e-14;
  return ts;
}

// The flux into the colony of the steady substrate with phi = 1 on the face set `outer`.
inline biofsi::BoundaryFlux steady_flux_into_colony(const Mesh& mesh) {
  biofsi::TransportField field(
      mesh, monod_settings(),
      {{"outer", biofsi::ScalarBcKind::Dirichlet, [](const Point&, double) { return 1.0; }}});
  field.solve_steady("steady");
  return field.boundary_flux("biofilm_fluid", mesh.block_index("biofilm"));
}

struct DiscSpec {
  int n = 8;             // elements along a quarter of the circle (and a side of the core)
  int n_ring = 4;        // radial, core square to circle
  int n_fluid = 8;       // radial, circle to r_outer
  double core = 0.45;    // half-width of the colony's core square
  double r_outer = 2.0;  // outer radius of the fluid annulus
  double thickness = 0.2;
  // Only y >= 0 (n even): half a colony sitting on the substratum y = 0 (face set "bottom"), the
  // interface meeting it at a right angle.
  bool on_substratum = false;
};

namespace detail {

// A 2-D node list that gives a point met twice (a patch edge shared by two patches) one index.
class Nodes2d {
 public:
  int at(double x, double y) {
    const std::pair<long long, long long> key{std::llround(x * 1e9), std::llround(y * 1e9)};
    const auto it = index_.find(key);
    if (it != index_.end()) return it->second;
    points_.push_back({x, y});
    return index_[key] = static_cast<int>(points_.size()) - 1;
  }
  const std::vector<std::array<double, 2>>& points() const { return points_; }

 private:
  std::map<std::pair<long long, long long>, int> index_;
  std::vector<std::array<double, 2>> points_;
};

struct Quad {
  std::array<int, 4> node;  // counter-clockwise seen from +z
  int block;
};

// The (n_t + 1) x (n_r + 1) nodes of a patch between an inner and an outer curve, both
// parametrised by s in [0, 1] counter-clockwise; quads counter-clockwise.
template <class Inner, class Outer>
void add_patch(Nodes2d& nodes, std::vector<Quad>& quads, int n_t, int n_r, int block,
               const Inner& inner, const Outer& outer) {
  std::vector<std::vector<int>> id(n_t + 1, std::vector<int>(n_r + 1));
  for (int i = 0; i <= n_t; ++i)
    for (int j = 0; j <= n_r; ++j) {
      const double s = static_cast<double>(i) / n_t, t = static_cast<double>(j) / n_r;
      const auto a = inner(s), b = outer(s);
      id[i][j] = nodes.at((1 - t) * a[0] + t * b[0], (1 - t) * a[1] + t * b[1]);
    }
  for (int i = 0; i < n_t; ++i)
    for (int j = 0; j < n_r; ++j)
      quads.push_back({{id[i][j], id[i][j + 1], id[i + 1][j + 1], id[i + 1][j]}, block});
}

// The quads with their centre above y = 0, on nodes renumbered to those they use.
inline void keep_upper_half(Nodes2d& nodes, std::vector<Quad>& quads) {
  Nodes2d kept_nodes;
  std::vector<Quad> kept;
  for (const auto& q : quads) {
    double y = 0;
    for (int v : q.node) y += nodes.points()[v][1] / 4;
    if (y < 0) continue;
    Quad k = q;
    for (int& v : k.node) v = kept_nodes.at(nodes.points()[v][0], nodes.points()[v][1]);
    kept.push_back(k);
  }
  nodes = std::move(kept_nodes);
  quads = std::move(kept);
}

inline std::array<double, 2> rotated(std::array<double, 2> p, int quarter) {
  for (int q = 0; q < quarter; ++q) p = {-p[1], p[0]};
  return p;
}

}  // namespace detail

// Face sets: biofilm_fluid (the circle, its faces once from each side), outer (r = r_outer),
// front (z = 0), back (z = thickness), with on_substratum bottom (y = 0); node sets of the same
// names.
inline Mesh disc_in_annulus(const DiscSpec& spec) {
  using detail::rotated;
  const double pi = std::acos(-1.0), a = spec.core;
  detail::Nodes2d nodes;
  std::vector<detail::Quad> quads;
  for (int i = 0; i < spec.n; ++i)
    for (int j = 0; j < spec.n; ++j) {
      auto p = [&](int di, int dj) {
        return nodes.at(a * (-1 + 2.0 * (i + di) / spec.n), a * (-1 + 2.0 * (j + dj) / spec.n));
      };
      quads.push_back({{p(0, 0), p(1, 0), p(1, 1), p(0, 1)}, 0});
    }
  for (int q = 0; q < 4; ++q) {
    auto on_core = [&](double s) { return rotated({a, a * (2 * s - 1)}, q); };
    auto on_circle = [&](double r) {
      return [=](double s) {
        const double angle = (s - 0.5) * pi / 2;
        return rotated({r * std::cos(angle), r * std::sin(angle)}, q);
      };
    };
    detail::add_patch(nodes, quads, spec.n, spec.n_ring, 0, on_core, on_circle(1.0));
    detail::add_patch(nodes, quads, spec.n, spec.n_fluid, 1, on_circle(1.0),
                      on_circle(spec.r_outer));
  }
  if (spec.on_substratum) detail::keep_upper_half(nodes, quads);
  Mesh m;
  const auto& p2 = nodes.points();
  const int n2 = static_cast<int>(p2.size());
  for (int layer = 0; layer < 2; ++layer)
    for (const auto& p : p2) m.x.push_back({p[0], p[1], layer * spec.thickness});
  m.block_names = {"biofilm", "fluid"};
  auto on_circle_of = [&](int node, double r) {
    return std::abs(std::hypot(p2[node][0], p2[node][1]) - r) < 1e-9;
  };
  // The hex8 face (VTK local index) over each edge of the bottom quad.
  constexpr int face_over_edge[4] = {2, 1, 3, 0};
  for (const auto& q : quads) {
    const int e = m.n_elements();
    const auto& v = q.node;
    m.conn.push_back({v[0], v[1], v[2], v[3], v[0] + n2, v[1] + n2, v[2] + n2, v[3] + n2});
    m.element_block.push_back(q.block);
    for (int k = 0; k < 4; ++k) {
      const int u = v[k], w = v[(k + 1) % 4];
      if (on_circle_of(u, 1.0) && on_circle_of(w, 1.0))
        m.face_sets["biofilm_fluid"].push_back({e, face_over_edge[k]});
      if (on_circle_of(u, spec.r_outer) && on_circle_of(w, spec.r_outer))
        m.face_sets["outer"].push_back({e, face_over_edge[k]});
      if (spec.on_substratum && std::abs(p2[u][1]) < 1e-12 && std::abs(p2[w][1]) < 1e-12)
        m.face_sets["bottom"].push_back({e, face_over_edge[k]});
    }
    m.face_sets["front"].push_back({e, 4});
    m.face_sets["back"].push_back({e, 5});
  }
  for (const auto& [name, faces] : m.face_sets) {
    std::set<int> in_set;
    for (const auto& f : faces)
      for (int k = 0; k < 4; ++k)
        in_set.insert(m.conn[f.element][biofsi::hex8_face_nodes[f.local_face][k]]);
    m.node_sets[name] = std::vector<int>(in_set.begin(), in_set.end());
  }
  for (int n = 0; n < m.n_nodes(); ++n) m.global_node_id.push_back(n);
  m.n_owned_nodes = m.n_nodes();
  for (int e = 0; e < m.n_elements(); ++e)
    if (biofsi::check_element(m, m.conn[e]).shape != biofsi::ElementShape::Valid)
      throw std::logic_error("disc_in_annulus: element " + std::to_string(e) + " is not valid");
  return m;
}

// `steps` growth steps of `gs`, each on the steady substrate of the moved mesh.
inline void grow_on_steady_substrate(Mesh& mesh, biofsi::MeshMotion& motion,
                                     const biofsi::GrowthSettings& gs, int steps) {
  const std::vector<int> nodes = mesh.node_sets.at("biofilm_fluid");
  for (int step = 1; step <= steps; ++step) {
    const biofsi::BoundaryFlux flux = steady_flux_into_colony(mesh);
    const biofsi::InterfaceMotion im =
        biofsi::interface_motion(mesh, gs, flux.density, std::vector<double>(nodes.size(), 0.0));
    biofsi::grow(mesh, motion, gs, im, "growth step " + std::to_string(step));
  }
}

// The interface nodes' distances `radius(x)` from the colony's centre: their mean and their
// spread (largest minus smallest) relative to the mean.
struct Roundness {
  double mean = 0, spread = 0;
};
template <class Radius>
Roundness roundness(const Mesh& mesh, Radius radius) {
  const std::vector<int>& nodes = mesh.node_sets.at("biofilm_fluid");
  double lo = 1e300, hi = 0, sum = 0;
  for (int n : nodes) {
    const double r = radius(mesh.x[n]);
    lo = std::min(lo, r);
    hi = std::max(hi, r);
    sum += r;
  }
  const double mean = sum / nodes.size();
  return {mean, (hi - lo) / mean};
}

// The steady radially symmetric problem in `dimension` 2 (a disc colony) or 3 (a ball, or the
// hemisphere on a symmetry plane): D_b (phi'' + (d - 1) phi'/r) = k phi / (K + phi) in the colony
// r < 1, D_f (phi'' + (d - 1) phi'/r) = 0 in the shell 1 < r < r_outer, phi(r_outer) = 1, phi and
// D phi' continuous at r = 1.
struct RadialMonod {
  double d_biofilm, k, half_saturation, d_fluid, r_outer;
  int dimension = 2;

  // The flux density into the colony at r = 1, D_b phi'(1): shooting on phi(0), bisected until
  // phi(r_outer) = 1 to round-off; each shot is RK4 in (phi, r^(d-1) phi') over `steps` steps from
  // a series start at r0 (its error O(r0^4) = 1e-16).
  double interface_flux_density(int steps = 20000) const {
    double lo = 0, hi = 1;
    for (int it = 0; it < 100; ++it) {
      const double mid = 0.5 * (lo + hi);
      (outer_value(mid, steps) < 1 ? lo : hi) = mid;
    }
    return shoot(0.5 * (lo + hi), steps).second * d_biofilm;
  }

 private:
  double reaction(double phi) const { return k * phi / (half_saturation + phi); }
  double area_factor(double r) const { return std::pow(r, dimension - 1); }  // r^(d-1)

  // (phi(1), phi'(1)) from phi(0) = centre.
  std::pair<double, double> shoot(double centre, int steps) const {
    const double r0 = 1e-4;
    const double c2 = reaction(centre) / (dimension * d_biofilm);  // phi = centre + c2 r^2 / 2
    double r = r0, phi = centre + c2 * r0 * r0 / 2,
           w = c2 * r0 * area_factor(r0);  // w = r^(d-1) phi'
    const double h = (1 - r0) / steps;
    auto rhs = [&](double rr, double p, double ww) {
      return std::pair<double, double>{ww / area_factor(rr),
                                       area_factor(rr) * reaction(p) / d_biofilm};
    };
    for (int s = 0; s < steps; ++s) {
      const auto k1 = rhs(r, phi, w);
      const auto k2 = rhs(r + h / 2, phi + h / 2 * k1.first, w + h / 2 * k1.second);
      const auto k3 = rhs(r + h / 2, phi + h / 2 * k2.first, w + h / 2 * k2.second);
      const auto k4 = rhs(r + h, phi + h * k3.first, w + h * k3.second);
      phi += h / 6 * (k1.first + 2 * k2.first + 2 * k3.first + k4.first);
      w += h / 6 * (k1.second + 2 * k2.second + 2 * k3.second + k4.second);
      r += h;
    }
    return {phi, w};  // at r = 1, r^(d-1) phi' = phi'
  }

  // phi(r_outer): the shell carries the flux D_b phi'(1) as phi = phi(1) + s ln r (d = 2) or
  // phi(1) + s (1 - 1/r) (d = 3), s = D_b phi'(1) / D_f.
  double outer_value(double centre, int steps) const {
    const auto [phi1, slope1] = shoot(centre, steps);
    const double s = d_biofilm * slope1 / d_fluid;
    return phi1 + s * (dimension == 2 ? std::log(r_outer) : 1 - 1 / r_outer);
  }
};

}  // namespace colony
