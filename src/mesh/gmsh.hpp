// Gmsh mesh input (MSH 4.1 ASCII) and sub-meshes of selected blocks, for geometries that the box
// generator cannot make (channels with a cylinder, the Turek-Hron flag). Part of src/mesh: may
// include the rest of src/mesh and the standard library only.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace biofsi {

// Malformed or unsupported mesh file; the message names the file, the line and what was expected.
struct MeshFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Reads a MSH 4.1 ASCII file into a hex8 mesh, from either
// - hexahedra (element type 5): physical volumes become element blocks (every hexahedron in
//   exactly one), physical surfaces face sets and node sets, physical curves and points node sets;
// - or, if the file has no hexahedra, a 2-D quadrilateral mesh in the plane z = 0, extruded into
//   one layer of hexahedra of the given thickness (the pseudo-2-D runs): physical surfaces become
//   blocks, physical curves the extruded side faces (face and node sets), and the sets "front"
//   (z = 0) and "back" (z = thickness) are added.
// A face shared by two hexahedra (an interface between blocks) is in its face set once per side,
// so that a sub-mesh of one block keeps that block's side; integrate over one side by filtering on
// the element's block (faces_of_block; a growth interface is cut to the biofilm's side by
// orient_interface). Nodes no hexahedron uses are dropped.
// Every hexahedron is checked at its 8 corners (check_element): a mirrored one (left-handed at
// every corner) is re-oriented and counted in *reoriented; an inverted, folded or degenerate one
// is an error naming the element's tag, its block and the scaled Jacobian.
// Counts are checked against the file's length before anything is allocated for them, and the
// node count against the memory available (memory_shortfall).
// Throws MeshFileError naming the file, the line (or element) and what was expected.
Mesh read_gmsh(const std::string& path, double thickness = 0, int* reoriented = nullptr);

// Meshes a .geo file with Debian's gmsh (found on PATH) into a temporary MSH 4.1 file and reads
// it: 2-D (-2) and extruded when thickness > 0, 3-D (-3) otherwise. `parameters` are passed as
// -setnumber NAME VALUE (e.g. refine). Throws MeshFileError with gmsh's exit status and messages.
Mesh mesh_geo_with_gmsh(const std::string& geo_path,
                        const std::vector<std::pair<std::string, double>>& parameters,
                        double thickness, int* reoriented = nullptr);

// The elements of the named blocks with the nodes they use, renumbered in the parent's order; block
// names keep their order, sets are restricted to what remains (empty ones dropped).
// parent_node, if given, receives for each sub-mesh node its node in `mesh`.
Mesh submesh(const Mesh& mesh, const std::vector<std::string>& blocks,
             std::vector<int>* parent_node = nullptr);

}  // namespace biofsi
