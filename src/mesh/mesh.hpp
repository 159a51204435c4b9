// src/mesh: the hex8 mesh on the host, its generators, topology helpers and the dof map.
//
// What lives here: Mesh (coordinates, VTK-ordered connectivity, element blocks, named node and
// face sets, global ids with an owned/ghost split), the structured multi-block box generator,
// element colouring, CSR sparsity patterns, dof maps with Dirichlet constraints, device mirrors
// and mesh-quality measures.
// What it may include: kernels/core, the standard library. Fields, solvers and io depend on it;
// it depends on none of them.
#pragma once

#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "kernels/core/csr.hpp"
#include "kernels/core/element_loop.hpp"
#include "kernels/core/face.hpp"
#include "kernels/core/types.hpp"

namespace biofsi {

using Point = std::array<double, 3>;

// Local faces of a hex8 in VTK order: 0 x-, 1 x+, 2 y-, 3 y+, 4 z-, 5 z+ (reference directions).
constexpr int hex8_face_nodes[6][4] = {{0, 3, 7, 4}, {1, 2, 6, 5}, {0, 1, 5, 4},
                                       {3, 2, 6, 7}, {0, 1, 2, 3}, {4, 5, 6, 7}};

struct BoundaryFace {
  int element;
  int local_face;
};

struct Mesh {
  std::vector<Point> x;
  std::vector<std::array<int, 8>> conn;  // VTK hexahedron order
  std::vector<int> element_block;        // index into block_names
  std::vector<std::string> block_names;
  std::map<std::string, std::vector<int>> node_sets;  // sorted, unique
  std::map<std::string, std::vector<BoundaryFace>> face_sets;
  // Parallel layout (DESIGN.md section 4): nodes [0, n_owned_nodes) are owned, the rest ghosts.
  std::vector<long long> global_node_id;
  int n_owned_nodes = 0;

  int n_nodes() const { return static_cast<int>(x.size()); }
  int n_elements() const { return static_cast<int>(conn.size()); }
  int block_index(const std::string& name) const;  // -1 if absent
  std::vector<int> elements_of_block(int block) const;
  // Nodes touched by the elements of a block.
  std::vector<int> nodes_of_block(int block) const;
};

// One box of a stack along y. Grading is the ratio of the last to the first element height.
struct BoxBlock {
  std::string name;
  double y0 = 0, y1 = 1;
  int ny = 1;
  double grading = 1.0;
};

// Several boxes stacked along y with conforming shared faces, one x and z division for all.
// Node sets and face sets: left, right, bottom, top, front (z-), back (z+) of the whole stack;
// <block>_left/_right/_front/_back and, per shared face, <lower>_<upper> (the lower block's faces,
// so their outward normal points into the upper block).
struct BoxSpec {
  double x0 = 0, x1 = 1, z0 = 0, z1 = 1;
  int nx = 1, nz = 1;
  std::vector<BoxBlock> blocks;
};

Mesh make_box_mesh(const BoxSpec& spec);

// The corners of the axis-aligned box around element e: (lower, upper).
std::pair<Point, Point> element_bounds(const Mesh& mesh, int e);

// The reference coordinates of point x in hex8 element e: Newton on the trilinear map, each
// coordinate kept within [-3, 3] so that a point far outside cannot send it off. Inside the
// element means every |xi| <= 1; the caller decides how much outside it accepts.
std::array<double, 3> hex8_reference_coordinates(const Mesh& mesh, int e, const Point& x);
// The trilinear shape functions (VTK corner order) at reference point xi.
std::array<double, 8> hex8_shape_values(const std::array<double, 3>& xi);
// jac[c][d] = dx_c/dxi_d of the trilinear map through these corner nodes (VTK order) at xi; the
// corners need not be an element of the mesh yet.
void hex8_jacobian(const Mesh& mesh, const std::array<int, 8>& corners,
                   const std::array<double, 3>& xi, double jac[3][3]);

// Moves every node by a smooth map (for distorted-mesh verification).
template <class Map>
void distort(Mesh& mesh, const Map& map) {
  for (auto& p : mesh.x) p = map(p);
}

// Greedy element colouring: no two elements of one colour share a node.
std::vector<std::vector<int>> colour_elements(const Mesh& mesh, const std::vector<int>& elements);

// Element groups for the element-loop drivers over `elements` with the given scatter policy.
ElementGroups make_element_groups(const Mesh& mesh, const std::vector<int>& elements,
                                  Scatter scatter);

// Sparsity pattern of a field with n_components per node, coupling all dofs of nodes that share an
// element (restricted to `elements`); values zeroed.
CsrMatrix make_sparsity(const Mesh& mesh, const std::vector<int>& elements, int n_components);

// Device copies of coordinates, connectivity and element blocks.
struct DeviceMesh {
  CoordView x;
  ConnView conn;
  IndexView element_block;
};
DeviceMesh to_device(const Mesh& mesh);
// Device copy of a face set: (element, local face) per face.
FaceView to_device(const std::vector<BoundaryFace>& faces);
void copy_coordinates_to_device(const Mesh& mesh, CoordView x);

// The sets as one set `name`: the union of their node sets (shared nodes once) and face sets (a
// force on it counts a node shared by two of them once).
void add_union_set(Mesh& mesh, const std::vector<std::string>& sets, const std::string& name);

// Scaled Jacobian of each element: min over the 8 corners of det[e1 e2 e3] / (|e1||e2||e3|) of
// the corner's edge vectors; 1 for a cube, <= 0 for an inverted or degenerate element.
std::vector<double> scaled_jacobians(const Mesh& mesh);
// The scaled Jacobian at each corner of the hex8 through these nodes (VTK order), signed: 1 at a
// cube's corners, negative at a corner where the element is turned inside out, 0 where an edge
// has zero length.
std::array<double, 8> corner_scaled_jacobians(const Mesh& mesh, const std::array<int, 8>& corners);

// What the 8 corner scaled Jacobians say about a hex8: valid (all above kDegenerateJacobian);
// mirrored (all below -kDegenerateJacobian: a valid element whose nodes are listed left-handed,
// made valid by reorient()); degenerate (a corner within kDegenerateJacobian of zero, or not a
// number); folded (signs differ and a face is a bow-tie: its edges cross); inverted (signs differ
// otherwise, e.g. a node moved inside the element).
enum class ElementShape { Valid, Mirrored, Degenerate, Folded, Inverted };
constexpr double kDegenerateJacobian = 1e-8;
struct ElementCheck {
  ElementShape shape = ElementShape::Valid;
  int corner = 0;    // the worst corner (0..7)
  double value = 1;  // its scaled Jacobian
};
ElementCheck check_element(const Mesh& mesh, const std::array<int, 8>& corners);
const char* shape_name(ElementShape shape);
// The same element listed right-handed: mirrors the node order through the plane of nodes 0, 2,
// 4, 6 (swaps 1 with 3 and 5 with 7), which turns every corner Jacobian's sign.
std::array<int, 8> reorient(std::array<int, 8> corners);

// Memory (bytes) this process can have now: the system's MemAvailable, lowered to the room left
// under a cgroup memory limit; 0 when neither can be read.
unsigned long long available_memory();
// The least memory a run needs per mesh node (bytes): the mesh, one scalar field's state, its
// stored tangent and matrices. The cheapest run, scalar transport alone on a box, peaks at
// 2.2-2.3 kB per node (51k and 202k nodes, one thread); the fluid and structure need more.
constexpr double kRunBytesPerNode = 2000;
// Empty when a mesh of `nodes` nodes fits in available_memory() at kRunBytesPerNode, otherwise
// why not, with the numbers: "N nodes need at least X GB, more than the Y GB available".
std::string memory_shortfall(long long nodes);

// Outward (out of its element) area vector of a boundary face: half the cross product of the
// diagonals, exact for planar quadrilaterals.
Point face_area_vector(const Mesh& mesh, const BoundaryFace& face);
// Area-weighted nodal normals of a face set, pointing out of the faces' elements, for the nodes of
// node_sets[set] in that order.
std::vector<Point> nodal_normals(const Mesh& mesh, const std::string& set);
// The faces of a face set that belong to elements of `block`: one side of an interface whose faces
// are listed once per side (a Gmsh mesh), or the whole set where it has one side only.
std::vector<BoundaryFace> faces_of_block(const Mesh& mesh, const std::string& set, int block);
// Whether a face set lists some face twice, once from each element beside it (an interface
// between blocks as a Gmsh mesh lists it).
bool lists_both_sides(const Mesh& mesh, const std::string& set);
// The interface node of a face set whose area vectors cancel most: `ratio` is
// |sum of the area vectors of its faces| / (sum of their areas) there (1 where they agree, 0 where
// two opposite sides of one face are both listed). Sets without faces give ratio 1, node -1.
struct WeakestNormal {
  double ratio = 1;
  int node = -1;
};
WeakestNormal weakest_nodal_normal(const Mesh& mesh, const std::string& set);
// The coordinate axis a unit wall normal is aligned with; throws for a wall that is not
// axis-aligned (nodes slide only along those).
int wall_axis(const Point& normal, const std::string& set);
// Index of a node in a sorted node list, -1 if absent.
int position_in_sorted(const std::vector<int>& sorted, int node);

// Dof map of a field with n_components per node over all mesh nodes. Single rank: global dof ids
// equal local ones; owned dofs come first (the owned/ghost split of the nodes).
struct DofMap {
  int n_components = 1;
  int n_nodes = 0;
  int n_owned_nodes = 0;
  int n_dofs() const { return n_nodes * n_components; }
  int n_owned_dofs() const { return n_owned_nodes * n_components; }
  int dof(int node, int component) const { return node * n_components + component; }
};
DofMap make_dof_map(const Mesh& mesh, int n_components);

// Dirichlet constraints: dof -> prescribed value. Later additions of the same dof overwrite.
struct Constraints {
  std::map<int, double> value;
  void add(int dof, double v) { value[dof] = v; }
  // A device mask (1 = constrained) and the lists of dofs and values.
  Kokkos::View<char*, MemSpace> mask(int n_dofs) const;
  IndexView dofs() const;
  Vector values() const;
};

}  // namespace biofsi
