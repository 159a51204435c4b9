// Box generator, named sets, colouring, sparsity and mesh quality. All checks are exact
// (integers) or geometric identities to round-off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "mesh/mesh.hpp"

using namespace biofsi;

namespace {

BoxSpec biofilm_under_fluid() {
  BoxSpec s;
  s.x0 = -5, s.x1 = 5, s.z0 = -0.1, s.z1 = 0.1, s.nx = 10, s.nz = 1;
  s.blocks = {{"biofilm", -5, -3, 4, 1.0}, {"fluid", -3, 5, 8, 2.0}};
  return s;
}

}  // namespace

TEST(BoxMesh, StacksBlocksWithConformingSharedFace) {
  const Mesh m = make_box_mesh(biofilm_under_fluid());
  EXPECT_EQ(m.n_nodes(), 11 * 13 * 2);
  EXPECT_EQ(m.n_elements(), 10 * 12);
  ASSERT_EQ(m.block_names.size(), 2u);
  EXPECT_EQ(m.elements_of_block(0).size(), 40u);
  EXPECT_EQ(m.elements_of_block(1).size(), 80u);
  // The shared face is one node layer: nodes of both blocks meet exactly there.
  const auto lower = m.nodes_of_block(0), upper = m.nodes_of_block(1);
  std::vector<int> shared;
  std::set_intersection(lower.begin(), lower.end(), upper.begin(), upper.end(),
                        std::back_inserter(shared));
  EXPECT_EQ(shared, m.node_sets.at("biofilm_fluid"));
  for (int n : shared) EXPECT_DOUBLE_EQ(m.x[n][1], -3.0);
  EXPECT_EQ(m.face_sets.at("biofilm_fluid").size(), 10u);
}

TEST(BoxMesh, NamesEveryBoundaryAndItsFacesPointOutward) {
  const Mesh m = make_box_mesh(biofilm_under_fluid());
  for (const char* name : {"left", "right", "bottom", "top", "front", "back", "biofilm_left",
                           "fluid_right", "biofilm_front", "fluid_back"})
    EXPECT_TRUE(m.face_sets.count(name)) << name;
  EXPECT_EQ(m.face_sets.at("top").size(), 10u);
  EXPECT_EQ(m.face_sets.at("left").size(), 12u);
  EXPECT_EQ(m.face_sets.at("fluid_left").size(), 8u);
  // Outward: the face's centroid minus the element's centroid points along the set's normal.
  auto check = [&](const std::string& set, int axis, double sign) {
    for (const auto& f : m.face_sets.at(set)) {
      double fc = 0, ec = 0;
      for (int k = 0; k < 4; ++k)
        fc += m.x[m.conn[f.element][hex8_face_nodes[f.local_face][k]]][axis] / 4;
      for (int k = 0; k < 8; ++k) ec += m.x[m.conn[f.element][k]][axis] / 8;
      EXPECT_GT(sign * (fc - ec), 0) << set;
    }
  };
  check("left", 0, -1), check("right", 0, 1), check("bottom", 1, -1), check("top", 1, 1);
  check("front", 2, -1), check("back", 2, 1), check("biofilm_fluid", 1, 1);
}

TEST(BoxMesh, GradingIsTheRatioOfLastToFirstElementHeight) {
  const Mesh m = make_box_mesh(biofilm_under_fluid());
  std::set<double> ys;
  for (const auto& p : m.x)
    if (p[1] >= -3.0 - 1e-12) ys.insert(p[1]);
  const std::vector<double> y(ys.begin(), ys.end());
  ASSERT_EQ(y.size(), 9u);
  const double first = y[1] - y[0], last = y[8] - y[7];
  EXPECT_NEAR(last / first, 2.0, 1e-12);  // geometric sizes: exact up to round-off
  EXPECT_DOUBLE_EQ(y.back(), 5.0);
}

TEST(BoxMesh, RejectsGapsBetweenBlocks) {
  BoxSpec s = biofilm_under_fluid();
  s.blocks[1].y0 = -2.9;
  EXPECT_THROW(make_box_mesh(s), std::invalid_argument);
}

TEST(ElementColouring, NoTwoElementsOfAColourShareANode) {
  Mesh m = make_box_mesh(biofilm_under_fluid());
  std::vector<int> all(m.n_elements());
  for (int e = 0; e < m.n_elements(); ++e) all[e] = e;
  const auto colours = colour_elements(m, all);
  size_t total = 0;
  for (const auto& group : colours) {
    std::set<int> seen;
    for (int e : group)
      for (int n : m.conn[e]) EXPECT_TRUE(seen.insert(n).second);
    total += group.size();
  }
  EXPECT_EQ(total, all.size());
  EXPECT_LE(colours.size(), 8u);  // a structured hex mesh needs 8 colours (2 per direction)
}

TEST(Sparsity, CouplesExactlyTheNodesThatShareAnElement) {
  BoxSpec s;
  s.nx = 3, s.nz = 2, s.blocks = {{"b", 0, 1, 2, 1.0}};
  const Mesh m = make_box_mesh(s);
  std::vector<int> all(m.n_elements());
  for (int e = 0; e < m.n_elements(); ++e) all[e] = e;
  const CsrMatrix a = make_sparsity(m, all, 3);
  auto rp = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.row_ptr);
  EXPECT_EQ(a.n_rows, m.n_nodes() * 3);
  // Interior-most node (1,1,1) of a 3x2x2 grid couples with 27 nodes, 3 components each.
  const int node = 1 + 4 * (1 + 3 * 1);
  EXPECT_EQ(rp(node * 3 + 1) - rp(node * 3), 27 * 3);
  // Corner node 0 couples with 8 nodes.
  EXPECT_EQ(rp(1) - rp(0), 8 * 3);
}

TEST(MeshQuality, ScaledJacobianIsOneForCubesAndNegativeWhenInverted) {
  BoxSpec s;
  s.nx = 2, s.nz = 2, s.blocks = {{"b", 0, 1, 2, 1.0}};
  Mesh m = make_box_mesh(s);
  for (double q : scaled_jacobians(m)) EXPECT_NEAR(q, 1.0, 1e-14);
  // Push the centre node through the opposite faces of its elements.
  const int centre = 1 + 3 * (1 + 3 * 1);
  m.x[centre] = {1.2, 0.5, 0.5};
  const auto q = scaled_jacobians(m);
  EXPECT_LT(*std::min_element(q.begin(), q.end()), 0.0);
}

TEST(DofMap, InterleavesComponentsAndSplitsOwnedFirst) {
  const Mesh m = make_box_mesh(biofilm_under_fluid());
  const DofMap d = make_dof_map(m, 3);
  EXPECT_EQ(d.n_dofs(), 3 * m.n_nodes());
  EXPECT_EQ(d.n_owned_dofs(), d.n_dofs());  // single rank owns everything
  EXPECT_EQ(d.dof(5, 2), 17);
  Constraints c;
  c.add(d.dof(0, 1), 2.0);
  c.add(d.dof(0, 1), 3.0);  // later additions overwrite
  EXPECT_EQ(c.value.size(), 1u);
  EXPECT_DOUBLE_EQ(c.value.at(1), 3.0);
}
