// The Turek & Hron (2006) flag alone, for CSM1 and CSM3 (test_csm1.cpp, test_csm3.cpp): the solid
// block of cases/meshes/turek_hron.geo at a refinement the build made (BIOFSI_MESH_DIR), clamped
// on "solid_clamp", and its St. Venant-Kirchhoff material (rho 1000 kg/m^3, mu 0.5e6 Pa, nu 0.4).
#pragma once

#include <string>

#include "mesh/gmsh.hpp"
#include "structure/structure_test_support.hpp"

namespace biofsi {
namespace test {

inline Mesh turek_hron_flag_mesh(int refine) {
  const std::string path =
      std::string(BIOFSI_MESH_DIR) + "/turek_hron_r" + std::to_string(refine) + ".msh";
  return submesh(read_gmsh(path, 0.01), {"solid"});
}

inline StructureMaterial turek_hron_flag_material() {
  const double mu = 0.5e6, nu = 0.4;
  StructureMaterial m;
  m.model = SaintVenantKirchhoff;
  m.mu = mu;
  m.lambda = 2 * mu * nu / (1 - 2 * nu);
  m.density = 1000;
  return m;
}

}  // namespace test
}  // namespace biofsi
