// Gmsh reader (MSH 4.1 ASCII) and sub-meshes, on meshes that Debian's gmsh makes at build time from
// cases/meshes/*.geo and tests/mesh/unit_cube_hex.geo. Volumes and areas are compared with the
// exact geometry up to the polygonal approximation of the circle (bounded in each test), counts
// exactly.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "mesh/gmsh.hpp"

using namespace biofsi;

namespace {

const std::string mesh_dir = BIOFSI_MESH_DIR;
constexpr double pi = 3.14159265358979323846;

// Trilinear hex volume by 2x2x2 Gauss (exact for the trilinear map's Jacobian determinant).
double hex_volume(const Mesh& m, int e) {
  const double g = 1 / std::sqrt(3.0), sx[8] = {-1, 1, 1, -1, -1, 1, 1, -1},
               sy[8] = {-1, -1, 1, 1, -1, -1, 1, 1}, sz[8] = {-1, -1, -1, -1, 1, 1, 1, 1};
  double v = 0;
  for (int q = 0; q < 8; ++q) {
    const double p[3] = {sx[q] * g, sy[q] * g, sz[q] * g};
    double j[3][3] = {};
    for (int a = 0; a < 8; ++a) {
      const double s[3] = {sx[a], sy[a], sz[a]};
      for (int d = 0; d < 3; ++d) {
        const double n = (1 + s[0] * p[0]) * (1 + s[1] * p[1]) * (1 + s[2] * p[2]) / 8;
        for (int k = 0; k < 3; ++k) {
          const double dn = n * s[k] / (1 + s[k] * p[k]);
          j[d][k] += dn * m.x[m.conn[e][a]][d];
        }
      }
    }
    v += j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1]) -
         j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0]) +
         j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0]);
  }
  return v;
}

double block_volume(const Mesh& m, const std::string& block) {
  double v = 0;
  for (int e : m.elements_of_block(m.block_index(block))) v += hex_volume(m, e);
  return v;
}

// Area of the planar faces of a set on the side of `block` (the extruded faces are rectangles).
double face_set_area(const Mesh& m, const std::string& set, const std::string& block) {
  double a = 0;
  for (const auto& f : m.face_sets.at(set)) {
    if (m.element_block[f.element] != m.block_index(block)) continue;
    Point p[4];
    for (int k = 0; k < 4; ++k) p[k] = m.x[m.conn[f.element][hex8_face_nodes[f.local_face][k]]];
    auto cross_norm = [](const Point& o, const Point& u, const Point& v) {
      const double a[3] = {u[0] - o[0], u[1] - o[1], u[2] - o[2]},
                   b[3] = {v[0] - o[0], v[1] - o[1], v[2] - o[2]};
      const double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                           a[0] * b[1] - a[1] * b[0]};
      return std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) / 2;
    };
    a += cross_norm(p[0], p[1], p[2]) + cross_norm(p[0], p[2], p[3]);
  }
  return a;
}

std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

// The unit cube's corners in VTK order.
const std::array<Point, 8> kCube = {
    {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}};

// A MSH 4.1 file of one hexahedron (element tag 7, block "solid") through nodes 1-8 at `x`, listed
// in the order `order` (node tags, VTK order for a right-handed element).
std::string one_hex(const std::array<Point, 8>& x,
                    const std::array<int, 8>& order = {1, 2, 3, 4, 5, 6, 7, 8}) {
  std::ostringstream s;
  s << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"solid\"\n"
    << "$EndPhysicalNames\n$Entities\n0 0 0 1\n1 0 0 0 1 1 1 1 1 0\n$EndEntities\n"
    << "$Nodes\n1 8 1 8\n3 1 0 8\n";
  for (int n = 1; n <= 8; ++n) s << n << "\n";
  for (const Point& p : x) s << p[0] << " " << p[1] << " " << p[2] << "\n";
  s << "$EndNodes\n$Elements\n1 1 1 7\n3 1 5 1\n7";
  for (int n : order) s << " " << n;
  s << "\n$EndElements\n";
  return s.str();
}

// read_gmsh's message for a file with this text, or "no error".
std::string error_reading(const std::string& name, const std::string& text) {
  try {
    read_gmsh(write_file(name, text));
  } catch (const MeshFileError& e) {
    return e.what();
  }
  return "no error";
}

// `text` with the single occurrence of `from` replaced by `to`.
std::string replaced(const std::string& text, const std::string& from, const std::string& to) {
  const size_t p = text.find(from);
  EXPECT_NE(p, std::string::npos) << from;
  return p == std::string::npos ? text : text.substr(0, p) + to + text.substr(p + from.size());
}

}  // namespace

TEST(Gmsh, ReadsHexahedraWithBlocksAndInterfaceSetsOnBothSides) {
  const Mesh m = read_gmsh(mesh_dir + "/unit_cube_hex.msh");
  ASSERT_EQ(m.block_names, (std::vector<std::string>{"left", "right"}));
  EXPECT_EQ(m.n_elements(), 27);
  EXPECT_EQ(m.n_nodes(), 64);
  EXPECT_EQ(m.elements_of_block(0).size(), 9u);
  EXPECT_NEAR(block_volume(m, "left"), 1.0 / 3, 1e-14);
  EXPECT_NEAR(block_volume(m, "right"), 2.0 / 3, 1e-14);
  for (int e = 0; e < m.n_elements(); ++e) EXPECT_GT(hex_volume(m, e), 0);
  EXPECT_EQ(m.face_sets.at("x0").size(), 9u);
  EXPECT_EQ(m.node_sets.at("x1").size(), 16u);
  for (int n : m.node_sets.at("x1")) EXPECT_NEAR(m.x[n][0], 1.0, 1e-14);
  // The interface between the blocks: each quad once per side.
  EXPECT_EQ(m.face_sets.at("cut").size(), 18u);
  EXPECT_NEAR(face_set_area(m, "cut", "left"), 1.0, 1e-14);
  EXPECT_NEAR(face_set_area(m, "cut", "right"), 1.0, 1e-14);
}

TEST(Gmsh, ExtrudesTheDfgChannelIntoOneHexLayer) {
  const double t = 0.01;
  const Mesh m = read_gmsh(mesh_dir + "/dfg_2d1_r1.msh", t);
  ASSERT_EQ(m.block_names, std::vector<std::string>{"fluid"});
  for (int e = 0; e < m.n_elements(); ++e) ASSERT_GT(hex_volume(m, e), 0) << "element " << e;
  // Two node layers, every node used.
  EXPECT_EQ(m.n_nodes() % 2, 0);
  std::set<int> used;
  for (const auto& c : m.conn) used.insert(c.begin(), c.end());
  EXPECT_EQ(static_cast<int>(used.size()), m.n_nodes());
  // The circle is a polygon of >= 32 sides inscribed in it: its area is short of pi r^2 by at most
  // pi r^2 (1 - sin(2 pi/n)/(2 pi/n)) < 0.65 % of the circle, 1.5e-5 of the channel.
  const double r = 0.05, channel = 2.2 * 0.41, circle = pi * r * r;
  EXPECT_NEAR(block_volume(m, "fluid") / t, channel - circle, 0.0065 * circle);
  EXPECT_GT(block_volume(m, "fluid") / t, channel - circle);
  EXPECT_NEAR(face_set_area(m, "inflow", "fluid"), 0.41 * t, 1e-14);
  EXPECT_NEAR(face_set_area(m, "outflow", "fluid"), 0.41 * t, 1e-14);
  EXPECT_NEAR(face_set_area(m, "walls", "fluid"), 2 * 2.2 * t, 1e-13);
  EXPECT_NEAR(face_set_area(m, "cylinder", "fluid"), 2 * pi * r * t, 0.003 * 2 * pi * r * t);
  EXPECT_NEAR(face_set_area(m, "front", "fluid"), (channel - circle), 0.0065 * circle);
  for (int n : m.node_sets.at("back")) EXPECT_DOUBLE_EQ(m.x[n][2], t);
  for (int n : m.node_sets.at("cylinder"))
    EXPECT_NEAR(std::hypot(m.x[n][0] - 0.2, m.x[n][1] - 0.2), r, 1e-12);
  // Refinement 2 halves the element size near the cylinder: about 4x the elements.
  const Mesh fine = read_gmsh(mesh_dir + "/dfg_2d1_r2.msh", t);
  EXPECT_GT(fine.n_elements(), 3 * m.n_elements());
  EXPECT_LT(fine.n_elements(), 5 * m.n_elements());
}

TEST(Gmsh, TurekHronSubmeshesKeepTheirSideOfTheInterface) {
  const double t = 0.02;
  const Mesh m = read_gmsh(mesh_dir + "/turek_hron_r1.msh", t);
  ASSERT_EQ(m.block_names, (std::vector<std::string>{"solid", "fluid"}));
  for (int e = 0; e < m.n_elements(); ++e) ASSERT_GT(hex_volume(m, e), 0) << "element " << e;
  // The flag runs from the circle (its long sides meet it at x = xa) to x = 0.6; its clamped end
  // is the circle's arc, which bulges into the flag by a segment of half-angle asin(0.01/0.05).
  // The mesh's 4 chords on that arc miss 4 sub-segments of r^2/2 (phi - sin phi), phi ~ 0.1: 8e-7.
  const double r = 0.05, xa = 0.2 + std::sqrt(r * r - 0.01 * 0.01), half = std::asin(0.01 / r),
               segment = r * r / 2 * (2 * half - std::sin(2 * half));
  EXPECT_NEAR(block_volume(m, "solid") / t, (0.6 - xa) * 0.02 - segment, 1e-6);
  const auto& fsi = m.face_sets.at("fsi");
  int solid_side = 0;
  for (const auto& f : fsi) solid_side += m.element_block[f.element] == 0;
  EXPECT_EQ(2 * solid_side, static_cast<int>(fsi.size()));
  EXPECT_NEAR(face_set_area(m, "fsi", "solid"), (2 * (0.6 - xa) + 0.02) * t, 1e-12);
  EXPECT_NEAR(face_set_area(m, "fsi", "fluid"), (2 * (0.6 - xa) + 0.02) * t, 1e-12);
  // Point A (the flag tip's centre) is a node.
  bool has_a = false;
  for (int n : m.node_sets.at("fsi"))
    has_a |= std::abs(m.x[n][0] - 0.6) < 1e-12 && std::abs(m.x[n][1] - 0.2) < 1e-12;
  EXPECT_TRUE(has_a);

  std::vector<int> parent;
  const Mesh solid = submesh(m, {"solid"}, &parent);
  ASSERT_EQ(solid.block_names, std::vector<std::string>{"solid"});
  EXPECT_EQ(solid.n_elements(), static_cast<int>(m.elements_of_block(0).size()));
  EXPECT_EQ(solid.face_sets.at("fsi").size(), static_cast<size_t>(solid_side));
  EXPECT_EQ(solid.face_sets.count("cylinder"), 0u);
  EXPECT_TRUE(solid.node_sets.count("solid_clamp"));
  for (int n = 0; n < solid.n_nodes(); ++n) EXPECT_EQ(solid.x[n], m.x[parent[n]]);
  const Mesh fluid = submesh(m, {"fluid"});
  EXPECT_EQ(fluid.face_sets.at("fsi").size(), fsi.size() - solid_side);
  EXPECT_EQ(fluid.node_sets.at("fsi").size(), solid.node_sets.at("fsi").size());
  EXPECT_EQ(fluid.n_elements() + solid.n_elements(), m.n_elements());
}

TEST(Gmsh, BadFilesStopWithFileLineAndWhatWasExpected) {
  auto message = [](const std::string& path, double t = 0) {
    try {
      read_gmsh(path, t);
    } catch (const MeshFileError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("/nonexistent/x.msh").find("/nonexistent/x.msh: cannot open"),
            std::string::npos);
  const auto v2 = write_file("v2.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
  EXPECT_NE(message(v2).find(v2 + ":2: unsupported mesh format 2.2"), std::string::npos)
      << message(v2);
  const auto cut = write_file("cut.msh",
                              "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 1 0\n"
                              "1 0 0 0 1 1 0 1 7\n");
  EXPECT_NE(message(cut).find("the file ends inside"), std::string::npos) << message(cut);
  // A 2-D mesh needs a thickness.
  EXPECT_NE(message(mesh_dir + "/dfg_2d1_r1.msh").find("needs a thickness > 0; got 0"),
            std::string::npos);
  EXPECT_THROW(submesh(read_gmsh(mesh_dir + "/unit_cube_hex.msh"), {"nope"}),
               std::invalid_argument);
}

// Counts and tags are checked before anything is allocated for them: each of these once crashed
// the reader (std::out_of_range, std::length_error, std::bad_alloc).
TEST(Gmsh, MalformedCountsAndTagsStopWithTheLine) {
  const std::string good = one_hex(kCube);
  EXPECT_EQ(error_reading("good.msh", good), "no error");
  auto expect = [&](const std::string& name, const std::string& text, const std::string& part) {
    const std::string m = error_reading(name, text);
    EXPECT_NE(m.find(testing::TempDir() + name + ":"), std::string::npos) << m;
    EXPECT_NE(m.find(part), std::string::npos) << m;
  };
  expect("missing_node.msh", replaced(good, "7 1 2 3 4 5 6 7 8", "7 1 2 3 4 5 6 7 99"),
         ":35: element 7 uses node 99, which $Nodes does not define");
  expect("negative_nodes.msh", replaced(good, "$Nodes\n1 8 1 8", "$Nodes\n1 -8 1 8"),
         "negative number of nodes (-8)");
  expect("negative_block.msh", replaced(good, "3 1 0 8", "3 1 0 -8"),
         "negative number of nodes (-8)");
  expect("negative_elements.msh", replaced(good, "3 1 5 1", "3 1 5 -1"),
         "negative number of elements (-1)");
  expect("negative_physicals.msh", replaced(good, "1 0 0 0 1 1 1 1 1 0", "1 0 0 0 1 1 1 -1 1 0"),
         "negative number of physical tags (-1)");
  expect("negative_names.msh", replaced(good, "$PhysicalNames\n1", "$PhysicalNames\n-1"),
         "negative number of physical names (-1)");
  expect("huge_block.msh",
         replaced(replaced(good, "$Nodes\n1 8 1 8", "$Nodes\n1 1000000000000000 1 8"), "3 1 0 8",
                  "3 1 0 1000000000000000"),
         "1000000000000000 nodes announced, but the rest of the file");
  expect("huge_elements.msh", replaced(good, "3 1 5 1", "3 1 5 1000000000000000"),
         "1000000000000000 elements announced");
  expect("twice.msh", replaced(good, "1\n2\n3\n", "1\n1\n3\n"), "node 1 is defined twice");
  expect("point_in_a_line.msh", replaced(good, "3 1 5 1", "1 1 15 1"),
         "element type 15 in a 1-D entity");
  // A device that never ends is refused before it is read.
  try {
    read_gmsh("/dev/zero");
    ADD_FAILURE() << "/dev/zero was read";
  } catch (const MeshFileError& e) {
    EXPECT_NE(
        std::string(e.what()).find("/dev/zero: cannot open the mesh file: not a regular file"),
        std::string::npos)
        << e.what();
  }
}

// Every element is checked at its 8 corners: a node moved inside the element, a bow-tie face and
// a flat element are refused, naming the element's tag, its block and the scaled Jacobian.
TEST(Gmsh, RejectsInvertedFoldedAndDegenerateElements) {
  auto expect = [](const std::string& name, const std::string& text, const std::string& shape) {
    const std::string m = error_reading(name, text);
    EXPECT_NE(m.find("element 7 of block 'solid' is " + shape + ": scaled Jacobian -"),
              std::string::npos)
        << m;
  };
  std::array<Point, 8> inside = kCube;
  inside[6] = {0.3, 0.3, 0.3};  // the far corner pushed inside: its corner Jacobian is negative
  expect("inverted.msh", one_hex(inside), "inverted");
  expect("folded.msh", one_hex(kCube, {1, 2, 4, 3, 5, 6, 8, 7}), "folded");
  std::array<Point, 8> flat = kCube;
  for (int n = 4; n < 8; ++n) flat[n][2] = 0;
  const std::string m = error_reading("flat.msh", one_hex(flat));
  EXPECT_NE(m.find("element 7 of block 'solid' is degenerate: scaled Jacobian 0"),
            std::string::npos)
      << m;
}

// A hexahedron listed left-handed at all 8 corners is a valid element mirrored: it is re-oriented
// (positive volume) and counted.
TEST(Gmsh, ReorientsAConsistentlyMirroredElementAndCountsIt) {
  int reoriented = -1;
  const Mesh m = read_gmsh(write_file("mirrored.msh", one_hex(kCube, {1, 4, 3, 2, 5, 8, 7, 6})), 0,
                           &reoriented);
  EXPECT_EQ(reoriented, 1);
  ASSERT_EQ(m.n_elements(), 1);
  EXPECT_NEAR(hex_volume(m, 0), 1.0, 1e-14);
  EXPECT_EQ(scaled_jacobians(m)[0], 1.0);
  read_gmsh(mesh_dir + "/unit_cube_hex.msh", 0, &reoriented);
  EXPECT_EQ(reoriented, 0);
}
