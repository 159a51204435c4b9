// src/growth: the growth model (paper eq. 11) and the growth step — interface velocity
// v = K1 J - K2 sigma along the area-weighted nodal normal of the interface, the interface
// displacement dt_bio v n (nodes where the interface meets a side wall slide along it), and the
// pseudo-elastic motion of the biofilm and fluid meshes that takes the grown biofilm as the new
// reference. What it may include: src/mesh, src/ale, src/solvers (and src/io's reader helpers in
// parameters.hpp, its scene section). The driver depends on it.
#pragma once

#include <string>
#include <vector>

#include "ale/mesh_motion.hpp"
#include "mesh/mesh.hpp"

namespace biofsi {

struct GrowthSettings {
  std::string interface_set =
      "biofilm_fluid";  // face set of the interface, faces on the biofilm side
  double k1 = 0;        // growth per substrate flux density [mm / (amount / (mm^2 ms)) / ms]
  double k2 = 0;        // erosion per wall shear stress
  double dt_bio = 1;    // biological time step [ms]
  // The motion of the biofilm and fluid meshes: its walls (the interface slides on the sliding
  // ones) and the smallest scaled Jacobian a move may leave.
  MeshMotionSettings mesh_motion;
};

// The smallest |nodal normal| / (mean |face normal|) accepted on a growth interface: 0.1 means
// faces turning by more than 168 degrees at one node, a crease along which "normal" has no
// direction (or both sides of the same faces listed); a smooth colony's surface has about 1.
constexpr double kMinInterfaceNormalRatio = 0.1;

// Keeps of the interface's face set only the faces of the biofilm block's elements, so that its
// normals point out of the biofilm into the fluid whatever the mesh lists (a Gmsh mesh lists an
// interface once per side; a box mesh the biofilm's side only). Returns what is wrong with the
// interface then, empty when nothing: no face on the biofilm side, or a node where the normals
// of its faces nearly cancel (kMinInterfaceNormalRatio).
std::string orient_interface(Mesh& mesh, const std::string& set, int biofilm);

struct InterfaceMotion {
  std::vector<int> nodes;           // interface nodes (node_sets[interface_set])
  std::vector<double> velocity;     // v = K1 J - K2 sigma
  std::vector<Point> displacement;  // dt_bio v n, projected onto sliding walls
};

// The interface displacement of one growth step from the flux density J into the biofilm and the
// wall shear stress sigma at the interface nodes (same order as node_sets[interface_set]).
InterfaceMotion interface_motion(const Mesh& mesh, const GrowthSettings& settings,
                                 const std::vector<double>& flux_density,
                                 const std::vector<double>& shear_stress);

struct GrowthStepReport {
  double max_interface_displacement = 0;
  double mean_interface_displacement = 0;  // along y, the wall-normal direction of the box cases
  int krylov_iterations = 0;
  bool preconditioner_set_up = false;  // the mesh motion's AMG (MeshMotionResult)
  std::vector<QualityRange> quality;   // per block, after the move
};

// Moves `mesh` by one growth step. On a move that would leave an element below min_quality (or
// inverted) the mesh is left unchanged and SolveError (field "growth") names the step, element,
// block and quality.
GrowthStepReport grow(Mesh& mesh, MeshMotion& motion, const GrowthSettings& settings,
                      const InterfaceMotion& interface, const std::string& label);

}  // namespace biofsi
