// libFuzzer target for the Gmsh reader (read_gmsh, MSH 4.1 ASCII). The input is written to a
// file and read as a mesh; a thickness is given, so a 2-D (quadrilateral) file is extruded and a
// 3-D one read as it is. MeshFileError is the reader's documented answer to a bad file; any other
// exception, a sanitizer report, a crash, a hang or running out of memory is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fuzz_support.hpp"
#include "mesh/gmsh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = biofsi::fuzz::scratch_dir("gmsh") + "/mesh.msh";
  biofsi::fuzz::write_input(path, data, size);
  try {
    int reoriented = 0;
    const biofsi::Mesh mesh = biofsi::read_gmsh(path, 0.5, &reoriented);
    // A mesh accepted must be usable: every block's elements and every set's nodes in range.
    biofsi::fuzz::check_mesh(mesh);
  } catch (const biofsi::MeshFileError&) {
  }
  return 0;
}
