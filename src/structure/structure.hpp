// src/structure: the structure field (paper eq. 1) — finite-strain elastodynamics of the biofilm,
// total Lagrangian, on hex8 with the pointwise physics of kernels/structure: boundary conditions
// (Dirichlet per component from expressions in x, y, z, t; dead-load tractions; the out-of-plane
// constraint of pseudo-2-D runs), one-step-theta in time or quasi-static load steps, Newton-Krylov
// with BoomerAMG on the assembled tangent, and stresses and energies for output and verification.
// What it may include: kernels/core, kernels/structure, src/mesh, src/solvers; only its
// scene-section reader (parameters.hpp) includes src/io's reader helpers. The driver and the scene
// depend on it.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "kernels/core/face.hpp"
#include "kernels/core/stored_tangent.hpp"
#include "kernels/structure/pointwise.hpp"
#include "mesh/mesh.hpp"
#include "solvers/solvers.hpp"

namespace biofsi {

// Value at a point and time (the same type as the scalar field's boundary data).
using SpaceTimeFunction = std::function<double(const Point& x, double t)>;

struct StructureMaterial {
  StructureModel model = SaintVenantKirchhoff;
  double lambda = 0, mu = 0;  // Lame parameters
  double density = 0;
  Point gravity{0, 0, 0};  // body force per unit mass
  // From Young's modulus and Poisson ratio (nu in (-1, 0.5)).
  static StructureMaterial from_young(StructureModel model, double youngs_modulus,
                                      double poisson_ratio, double density);
};

// Total displacement d_i = value_i(X, t) on the nodes of a node set, for the components whose
// `value` is set (an empty function leaves that component free).
struct StructureDirichlet {
  std::string set;
  std::array<SpaceTimeFunction, 3> value;
};

// Dead load: traction per reference area on a face set, fixed in direction and size as the body
// deforms (evaluated at the nodes and interpolated).
struct StructureTraction {
  std::string set;
  std::array<SpaceTimeFunction, 3> traction;
};

// Which BoomerAMG variant preconditions the tangent (bench/README.md has the measurements).
enum class StructureAmg {
  Scalar,           // one function per dof: x, y and z couplings all seen as one graph
  Systems,          // 3 functions per node, nodal coarsening (hypre's "unknown-based" + nodal)
  SystemsRigidBody  // Systems plus the rigid-body rotations as interpolation vectors (GM-2)
};

// How the volumetric term of the strain energy is integrated (kernels/structure's EnergyTerms).
enum class VolumetricIntegration {
  Full,    // at the 2x2x2 points like the rest: hex8 locks as nu -> 0.5
  Reduced  // at the element centre (selective reduced integration): no volumetric locking
};

struct StructureSettings {
  // Per block index of the mesh; only the materials of active blocks are used (and checked).
  std::vector<StructureMaterial> materials;
  // Blocks that hold the structure (empty: all). The other blocks' nodes are held at rest, so the
  // field can live on a mesh shared with the fluid (FSI) and keep that mesh's node numbers.
  std::vector<std::string> blocks;
  bool quasi_static = false;
  double theta = 0.66;  // one-step-theta, in [0.5, 1]
  // Pseudo-2-D: hold the z displacement of every node at zero (plane strain on a one-element-thick
  // mesh).
  bool plane_strain = false;
  VolumetricIntegration volumetric_integration = VolumetricIntegration::Full;
  Scatter scatter = Scatter::Colored;
  // Linear solves to at least 1e-4 (Eisenstat-Walker may ask for more): with the looser 1e-2 of
  // NewtonOptions, Newton oscillated on the slender Turek-Hron flag (CSM1), whose bending modes
  // are 1e4 times softer than its membrane modes.
  NewtonOptions newton = [] {
    NewtonOptions o;
    o.eta_max = 1e-4;
    return o;
  }();
  StructureAmg amg = StructureAmg::Systems;
  bool use_cg = false;  // the tangent is symmetric but may be indefinite (buckling): FGMRES default
  // A step whose Newton solve fails is retried as 2, 4, ... 2^max_step_cuts sub-steps.
  int max_step_cuts = 6;
};

struct StructureStats {
  int steps = 0, newton_iterations = 0, krylov_iterations = 0, amg_setups = 0, cut_steps = 0;
  // Krylov iterations of each Newton iteration of the last step (AMG comparisons).
  std::vector<int> last_step_krylov;
  double seconds_residual = 0, seconds_tangent = 0, seconds_linearise = 0, seconds_assembly = 0,
         seconds_amg_setup = 0, seconds_solve = 0;
};

class StructureField {
 public:
  StructureField(const Mesh& mesh, const StructureSettings& settings,
                 std::vector<StructureDirichlet> dirichlet,
                 std::vector<StructureTraction> tractions = {});
  ~StructureField();

  // Body force per reference volume b(X, t) (manufactured solutions), evaluated at the nodes.
  void set_body_force(std::array<SpaceTimeFunction, 3> b);
  // Initial displacement and velocity (host, per node); time t0.
  void set_state(const std::vector<Point>& d, const std::vector<Point>& v, double t0);

  // One step from t to t + dt: one-step-theta, or in quasi-static mode equilibrium under the loads
  // and Dirichlet data of t + dt. Throws SolveError (field "structure", the step label, why with
  // the residual history) if Newton fails even with cut steps; the state is then left at t.
  NewtonResult step(double dt, const std::string& label);

  double time() const { return time_; }
  std::vector<Point> displacement() const;
  std::vector<Point> velocity() const;
  // Kinetic (consistent mass) and strain energy of the current state.
  double kinetic_energy() const;
  double strain_energy() const;
  // Per element at its centre: Cauchy stress (xx, yy, zz, xy, yz, zx) and von Mises stress.
  std::vector<std::array<double, 6>> cauchy_stress() const;
  std::vector<double> von_mises_stress() const;

  const StructureStats& stats() const { return stats_; }
  const Mesh& mesh() const { return mesh_; }
  const StructureSettings& settings() const { return settings_; }
  // One-step-theta's theta from the next step on, in [0.5, 1] (std::invalid_argument otherwise).
  void set_theta(double theta);
  // Quasi-static (true) or dynamic from the next step on: a dynamic structure is solved at
  // equilibrium for the steady state a transient coupled run starts from (its velocity then 0).
  void set_quasi_static(bool quasi_static) { settings_.quasi_static = quasi_static; }
  // The blocks' elements and nodes (sorted).
  const std::vector<int>& elements() const { return elements_; }
  const std::vector<int>& active_nodes() const { return active_nodes_; }

  // A growth step moved the reference configuration (total Lagrangian): take the new reference
  // coordinates; displacement and velocity stay as nodal values relative to it.
  void set_reference_coordinates(const Mesh& moved);

  // ---- the pieces of a step, for a coupled (monolithic) solve that owns the Newton loop ----
  // Sets up the step t -> t + dt (quasi-static: equilibrium under the data of t + dt; dt = 0 is
  // allowed there, equilibrium at the current time) and predicts the increment: constant
  // velocity (dynamics) or none (quasi-static), with the prescribed increments on the constrained
  // dofs.
  void begin_step(double dt);
  // The increment u = d_{n+1} - d_n of the step being solved (read and written by the coupling).
  Vector increment() { return u_; }
  // Accepts the increment: v_{n+1}, d_{n+1}, t + dt.
  void end_step(double dt);
  // v_{n+1} = (u/dt - (1 - theta) v_n)/theta per unknown, as the time integrator defines it:
  // dv_{n+1}/du = velocity_coefficient() (0 in quasi-static mode, where v = 0).
  double velocity_coefficient() const;
  ConstVector displacement_device() const { return d_; }
  ConstVector velocity_device() const { return v_; }
  // AMG on the current matrix() (after assemble(u, true) and any change the coupling made).
  void setup_amg();
  void precondition(ConstVector r, Vector z) const;
  // The next Newton iteration sets the preconditioner up afresh, whatever its age (a checkpoint:
  // a run continued from it starts that way).
  void invalidate_preconditioner() { reuse_.invalidate(); }
  Kokkos::View<const char*, MemSpace> constrained_mask() const { return fixed_; }
  // Verification access: residual and tangent of the step being set up by prepare_step (the
  // unknown is the increment u = d_{n+1} - d_n), the assembled tangent (constrained rows and
  // columns eliminated when `constrained`), and the matrix-free diagonal.
  void prepare_step(double dt);
  void residual(ConstVector u, Vector r) const;
  // Element and face terms on every dof, constrained ones included: there, the reaction.
  void residual_unconstrained(ConstVector u, Vector r) const;
  void apply_tangent(ConstVector u, ConstVector du, Vector y) const;
  // The tangent stored at the quadrature points at u (what the Krylov solves apply):
  // apply_linearised(du, y) equals apply_tangent(u, du, y) for the u of the last linearise(u), as
  // long as the step's data stay as they were.
  void linearise(ConstVector u);
  void apply_linearised(ConstVector du, Vector y) const;
  void diagonal(ConstVector u, Vector d) const;
  void assemble(ConstVector u, bool constrained);
  const CsrMatrix& matrix() const { return matrix_; }
  ConstIndexView constrained_dofs() const { return fixed_dofs_; }
  int n_dofs() const { return 3 * mesh_.n_nodes(); }

 private:
  struct FaceTerm;
  NewtonResult step_once(double dt, const std::string& label);
  void set_step_data(double dt);
  void predict_dirichlet(const std::string& label);
  double roundoff_floor() const;
  double energy(bool kinetic) const;  // kinetic or strain energy of the current state
  void setup_preconditioner(ConstVector u);
  bool reduced_volumetric() const {
    return settings_.volumetric_integration == VolumetricIntegration::Reduced;
  }
  // Element terms (both rules where the volumetric one is reduced), accumulated into the output.
  void element_residual(ConstVector u, Vector r) const;
  void element_tangent(ConstVector u, ConstVector du, Vector y) const;

  Mesh mesh_;
  StructureSettings settings_;
  DeviceMesh dmesh_;
  std::vector<int> elements_, active_nodes_;
  ElementGroups groups_;
  NodalView aux_;  // [d_n, v_n, b]
  // With VolumetricIntegration::Reduced op_ integrates all but the volumetric terms and
  // centre_op_ those; with Full, op_ everything and centre_op_ is not used.
  ElementOperator<StructurePhysics> op_;
  ElementOperator<StructurePhysics, Hex8Centre> centre_op_;
  Linearisation<StructurePhysics> linearisation_, centre_linearisation_;
  std::vector<FaceTerm> faces_;
  std::array<SpaceTimeFunction, 3> body_force_;
  std::vector<std::pair<int, SpaceTimeFunction>> dirichlet_;  // (dof, total displacement)
  Kokkos::View<char*, MemSpace> fixed_;
  IndexView fixed_dofs_;
  Vector fixed_values_;  // prescribed increments of the step
  Vector d_, v_, u_;     // displacement and velocity at t_n; increment of the step
  Vector scratch_;
  CsrMatrix matrix_;
  std::unique_ptr<BoomerAmg> amg_;
  PreconditionerReuse reuse_;  // of amg_ in this field's own Newton solves
  double time_ = 0, step_dt_ = 0;
  double element_size_ = 0;  // a typical element edge (round-off floor of Neo-Hooke's residual)
  StructureStats stats_;
};

}  // namespace biofsi
