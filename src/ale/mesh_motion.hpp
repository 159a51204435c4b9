// src/ale: mesh motion by quasi-static pseudo-elasticity (paper eqs. 7, 12, 13) — the fluid mesh
// follows the interface, and in a growth step the biofilm mesh takes the grown interface as its
// new reference. Matrix-free operator from kernels/ale, CG with systems BoomerAMG on the assembled
// matrix. Also the mesh-quality check that stops a run before an inverted element is used.
// What it may include: kernels/, src/mesh, src/solvers (and src/io's reader helpers in
// parameters.hpp, its scene section). src/growth, src/coupling and the driver depend on it.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "kernels/ale/pointwise.hpp"
#include "kernels/core/stored_tangent.hpp"
#include "mesh/mesh.hpp"
#include "solvers/solvers.hpp"

namespace biofsi {

// The fluid mesh of the coupled solve at the flow's inflow and outflow boundaries.
enum class InflowOutflow {
  Fixed,  // Eulerian: those nodes do not move within an inner loop (the paper's section 2)
  Walls   // as the wall lists say (on a sliding wall they slide)
};

struct MeshMotionSettings {
  double poisson_ratio = 0.3;  // of the pseudo-material, in [0, 0.5)
  double stiffening = 1.0;     // chi in (1/det J)^chi, >= 0
  // Face sets on which mesh nodes slide (normal displacement zero) and sets held fixed; with
  // inflow_outflow = Fixed the scene adds the flow's inflow and outflow sets to the coupled
  // solve's fixed_walls (hold_inflow_outflow). Interface nodes on a wall follow the interface.
  std::vector<std::string> sliding_walls = {"left", "right", "front", "back"};
  std::vector<std::string> fixed_walls = {"bottom", "top"};
  InflowOutflow inflow_outflow = InflowOutflow::Fixed;
  double min_quality = 0.02;  // smallest scaled Jacobian accepted after a move, in (0, 1)
  KrylovOptions krylov{1e-12, 0.0, 500, 50};
  Scatter scatter = Scatter::Colored;
};

// Prescribed mesh displacement: per node, a mask of fixed components and their values.
struct MeshDisplacementBc {
  std::map<int, std::array<bool, 3>> fixed;
  std::map<int, Point> value;
  // Fixes components of all nodes of a set to zero (walls); `components` e.g. {true,false,false}
  // fixes only x (a wall x = const on which nodes may slide).
  void fix(const std::vector<int>& nodes, std::array<bool, 3> components);
  // Prescribes the full displacement of a node (overrides earlier fixes of that node).
  void prescribe(int node, const Point& d);
};

// Walls of a mesh motion: every component fixed on `fixed_walls`, the wall-normal component on
// `sliding_walls` (axis-aligned walls only); sets the mesh does not have are skipped.
MeshDisplacementBc wall_constraints(const Mesh& mesh, const std::vector<std::string>& fixed_walls,
                                    const std::vector<std::string>& sliding_walls);

struct MeshMotionResult {
  int krylov_iterations = 0;
  bool preconditioner_set_up = false;  // false: the last solve's AMG hierarchy served again
  double max_displacement = 0;
};

// det J of an element's hex8 map at its centre (xi = 0).
double centre_jacobian(const Mesh& mesh, int element);

// The pseudo-material of a mesh motion over `elements` of `mesh`: E = 1, the settings' Poisson
// ratio and stiffening, J_0 the smallest centre det J among those elements (so the stiffness
// lies between E on the smallest element and ~E (J_0 / det J)^chi < E elsewhere). Throws
// std::invalid_argument for an element with det J <= 0.
PseudoElasticPhysics pseudo_elastic_physics(const MeshMotionSettings& settings, const Mesh& mesh,
                                            const std::vector<int>& elements);

class MeshMotion {
 public:
  // Over every element of `mesh`, or only over `elements` (the fluid's, in an FSI); nodes outside
  // them belong to no element of the operator and must be constrained by the caller.
  MeshMotion(const Mesh& mesh, const MeshMotionSettings& settings);
  MeshMotion(const Mesh& mesh, const MeshMotionSettings& settings,
             const std::vector<int>& elements);

  // Solves for the displacement of every node given the boundary data, on the mesh's current
  // coordinates, and returns it (host, per node). Throws SolveError (field "mesh motion") if the
  // linear solve fails.
  std::vector<Point> solve(const Mesh& mesh, const MeshDisplacementBc& bc, const std::string& label,
                           MeshMotionResult* result = nullptr);

  // Residual and tangent of the discrete operator (verification): r = K d with no constraints.
  void residual(const Mesh& mesh, ConstVector d, Vector r);
  void assemble(const Mesh& mesh, const CsrMatrix& a);
  const CsrMatrix& pattern() const { return matrix_; }

  // The operator as one block of a monolithic system (src/coupling), whose solver owns the
  // constraints: K on the coordinates of the last set_coordinates. K does not depend on d (the
  // stiffening uses the element's det J on those coordinates), so one linearise serves until the
  // coordinates change.
  void set_coordinates(const Mesh& mesh);
  ConstCoordView coordinates() const { return dmesh_.x; }
  // Assembles matrix() (no constraints) and stores the tangent.
  void linearise();
  void add_residual(ConstVector d, Vector r) const;    // r += K d, matrix-free
  void add_linearised(ConstVector d, Vector y) const;  // y += K d, stored tangent
  CsrMatrix& matrix() { return matrix_; }              // the caller eliminates its constraints
  const CsrMatrix& matrix() const { return matrix_; }
  void setup_preconditioner();  // BoomerAMG on matrix() as it is now
  void precondition(ConstVector r, Vector z) const { amg_.apply(r, z); }

 private:
  void bind(const Mesh& mesh);

  MeshMotionSettings settings_;
  Mesh topology_;  // connectivity and blocks; coordinates refreshed on every solve
  DeviceMesh dmesh_;
  ElementGroups groups_;
  ElementOperator<PseudoElasticPhysics> op_;
  FieldStoreOf<PseudoElasticPhysics> stored_;  // op_'s tangent on the current coordinates
  CsrMatrix matrix_;
  BoomerAmg amg_;
  // The age of amg_ in solve(): a growth step moves the mesh by a fraction of an element, so the
  // hierarchy of an earlier step keeps serving until CG needs markedly more iterations than right
  // after its set-up, or the constraints differ.
  PreconditionerReuse solve_reuse_;
  std::vector<int> solve_constraints_;  // the constrained dofs amg_ was set up with
};

// Range of the scaled Jacobian per block.
struct QualityRange {
  double min = 1, max = -1;
  int worst_element = -1;
};
std::vector<QualityRange> mesh_quality_by_block(const Mesh& mesh);

}  // namespace biofsi
