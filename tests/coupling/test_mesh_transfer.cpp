// The mesh transfer of the unsteady FSI studies (mesh_transfer.hpp), on fields whose interpolant
// is known, so that a study restarted on a finer mesh starts from the state it was given.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "app/restart.hpp"
#include "mesh/mesh_transfer.hpp"

using namespace biofsi;

namespace {

Mesh box(int nx, int ny) { return make_box_mesh({0, 2, 0, 0.1, nx, 1, {{"all", 0, 1, ny, 1.0}}}); }

// A smooth interior distortion that keeps the boundary where it is, so both meshes cover
// the same domain.
Point wiggle(const Point& p) {
  return {p[0] + 0.07 * std::sin(M_PI * p[0] / 2) * std::sin(M_PI * p[1]),
          p[1] + 0.05 * std::sin(M_PI * p[0]) * std::sin(M_PI * p[1]), p[2]};
}

double linear(const Point& p) { return 1 + 2 * p[0] - 3 * p[1] + 0.5 * p[2]; }

std::vector<int> all_elements(const Mesh& m) {
  std::vector<int> e(m.n_elements());
  for (int i = 0; i < m.n_elements(); ++i) e[i] = i;
  return e;
}

}  // namespace

// Isoparametric trilinear elements reproduce linear fields exactly, distorted or not, so a linear
// field moved from one distorted mesh to another must arrive to round-off.
TEST(MeshTransfer, LinearFieldArrivesExactlyOnAnotherMesh) {
  Mesh from = box(7, 5), to = box(12, 9);
  distort(from, wiggle);
  std::vector<double> f;
  std::vector<Point> v;
  for (const Point& p : from.x) {
    f.push_back(linear(p));
    v.push_back({linear(p), -linear(p), 2.0});
  }
  const NodalInterpolator from_all(from, all_elements(from));
  double error = 0;
  for (const Point& p : to.x) {
    const NodalWeights w = from_all.locate(p);
    EXPECT_LE(w.outside, 1e-9);
    error = std::max(error, std::abs(from_all.interpolate(w, f) - linear(p)));
    const Point q = from_all.interpolate(w, v);
    error = std::max(
        {error, std::abs(q[0] - linear(p)), std::abs(q[1] + linear(p)), std::abs(q[2] - 2.0)});
  }
  EXPECT_LT(error, 1e-12);
}

// A bilinear field is exact only where the meshes share their elements: the same mesh gives it
// back at its own nodes (the weights pick the node itself).
TEST(MeshTransfer, SameMeshReturnsTheNodalValues) {
  Mesh m = box(5, 4);
  distort(m, wiggle);
  std::vector<double> f;
  for (const Point& p : m.x) f.push_back(std::sin(3 * p[0]) * p[1] * p[1]);
  const NodalInterpolator it(m, all_elements(m));
  for (int n = 0; n < m.n_nodes(); ++n)
    EXPECT_NEAR(it.interpolate(it.locate(m.x[n]), f), f[n], 1e-12) << "node " << n;
}

// A point a little outside (a curved boundary's other chord) takes the nearest element; one far
// outside is an error that names the point.
TEST(MeshTransfer, OutsidePointsNearestOrError) {
  const Mesh m = box(4, 4);
  const NodalInterpolator it(m, all_elements(m), 0.05);
  const NodalWeights near = it.locate({2.005, 0.5, 0.05});  // 0.02 outside in reference units
  EXPECT_GT(near.outside, 0.0);
  EXPECT_LT(near.outside, 0.05);
  double sum = 0;
  for (double n : near.n) sum += n;
  EXPECT_NEAR(sum, 1.0, 1e-14);
  EXPECT_THROW(it.locate({2.5, 0.5, 0.05}), std::runtime_error);
}

// A flow checkpoint's state on a two-block channel (structure below, fluid above) moved onto a
// finer one (restart.hpp): linear fields arrive exactly on each field's nodes, and on the shared
// interface the fluid mesh takes the structure's displacement and the fluid its velocity, however
// the checkpoint's fluid fields differ there.
TEST(MeshTransfer, FlowStateKeepsEachFieldOnItsBlocksAndTheInterfaceCoupled) {
  auto channel = [](int nx, int ny) {
    return make_box_mesh(
        {0, 1, 0, 0.1, nx, 1, {{"solid", 0.0, 0.25, ny, 1.0}, {"fluid", 0.25, 1.0, 3 * ny, 1.0}}});
  };
  const Mesh from = channel(5, 2), to = channel(9, 3);
  auto vec = [](const Point& p, double s) {
    return Point{s * linear(p), -s * linear(p), 0.5 * s * linear(p)};
  };
  FlowState s;
  for (const Point& p : from.x) {
    for (int k = 0; k < 4; ++k) s.fluid.push_back((k + 1) * linear(p));
    s.displacement.push_back(vec(p, 1e-3));
    s.velocity.push_back(vec(p, 2e-3));
    s.mesh_displacement.push_back(vec(p, 3e-3));  // not the structure's: moved, then coupled
    s.mesh_velocity.push_back(vec(p, 4e-3));
  }
  const FlowState t = transfer(from, s, to, FieldBlocks{{1}, {0}});
  ASSERT_EQ(t.fluid.size(), 4u * to.n_nodes());
  double worst = 0;
  int interface = 0;
  for (int a = 0; a < to.n_nodes(); ++a) {
    const Point& p = to.x[a];
    const bool solid = p[1] <= 0.25 + 1e-12, fluid = p[1] >= 0.25 - 1e-12;
    if (solid) {
      for (int k = 0; k < 3; ++k) {
        worst = std::max(worst, std::abs(t.displacement[a][k] - vec(p, 1e-3)[k]) / 1e-3);
        worst = std::max(worst, std::abs(t.velocity[a][k] - vec(p, 2e-3)[k]) / 2e-3);
      }
    }
    if (fluid && !solid) {
      for (int k = 0; k < 4; ++k)
        worst = std::max(worst, std::abs(t.fluid[4 * a + k] - (k + 1) * linear(p)));
      for (int k = 0; k < 3; ++k) {
        worst = std::max(worst, std::abs(t.mesh_displacement[a][k] - vec(p, 3e-3)[k]) / 3e-3);
        worst = std::max(worst, std::abs(t.mesh_velocity[a][k] - vec(p, 4e-3)[k]) / 4e-3);
      }
    }
    if (solid && fluid) {
      ++interface;
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(t.mesh_displacement[a][k], t.displacement[a][k]);
        EXPECT_EQ(t.fluid[4 * a + k], t.velocity[a][k]);
      }
      EXPECT_NEAR(t.fluid[4 * a + 3], 4 * linear(p), 1e-12);  // the pressure is the fluid's
    }
  }
  EXPECT_EQ(interface, 2 * 10);  // 10 nodes along x, 2 through the thickness
  std::printf("[ measured ] flow state moved onto the finer channel: max error %.2e\n", worst);
  EXPECT_LT(worst, 1e-12);  // trilinear elements reproduce linear fields: round-off only
}
