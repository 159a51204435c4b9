// src/app/simulation.hpp: scene assembly — the fields a scene asks for, built on its mesh — and
// the coupling of the flow to the transport after each flow solve. What every run mode of the
// driver steps. What it may include: src/io, the fields, src/coupling.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "coupling/fsi.hpp"
#include "fluid/fluid.hpp"
#include "io/output.hpp"
#include "io/scene.hpp"
#include "scalar/transport.hpp"
#include "structure/structure.hpp"

namespace biofsi {

struct Simulation {
  // Builds the mesh and every field the scene turns on, each from its section's settings and
  // boundary conditions, with the scalar's initial state and prescribed velocity.
  explicit Simulation(const Scene& scene);

  const Scene& scene;
  int reoriented_elements = 0;  // mirrored elements of a Gmsh mesh, re-oriented when it was read
  Mesh mesh;
  TransportField scalar;  // built always (cheap); stepped only when the scene turns it on
  std::unique_ptr<FluidField> fluid;
  std::unique_ptr<StructureField> structure;
  std::unique_ptr<FsiProblem> fsi;
  double min_deformed_quality = 1;  // FSI: of the deformed configuration over all solves

  // The steady flow (coupled with the structure where there is one), then after_flow_solve.
  NewtonResult solve_steady_flow(const std::string& label);
  // One step of the transient flow (coupled where there is a structure; or the structure alone
  // when the scene has no fluid), then after_flow_solve.
  void advance_flow(const std::string& label, double dt);
  // Whether advance_flow steps something: a transient fluid, or a structure alone.
  bool flow_is_transient() const;
  // Every field's and the coupling's preconditioner is set up afresh at its next Newton iteration:
  // a run continued from a checkpoint starts that way, so the run that wrote it does the same
  // and the two take the same steps.
  void invalidate_preconditioners();
  // One-step-theta's theta of the fluid and the structure from the next step on (a time stage's).
  void set_theta(double theta);
  // Per node: the structure's displacement on its nodes, with FSI the fluid mesh's elsewhere.
  std::vector<Point> displacement() const;
  // The configuration a growth step moves: with FSI and ReferenceUpdate::Reset the deformed one
  // (the paper's: the deformed shape grows), otherwise the reference.
  Mesh growth_configuration(ReferenceUpdate update) const;
  // The grown configuration becomes every field's reference. With FSI and Reset the structure's
  // and the fluid mesh's displacements restart from zero on it (the biofilm stress-free, its
  // velocity kept); with Keep they stay relative to the new reference.
  void take_grown_reference(const Mesh& grown, ReferenceUpdate update);
  // The transport sees the flow on the configuration it was solved on: with FSI the deformed
  // mesh (checked against mesh_motion.min_quality), the ALE convective velocity c = u - u_grid in
  // the fluid and the biofilm's own velocity for its Phi div u_S term (c = 0 there: its mesh
  // moves with it). Without FSI the mesh does not move within an inner loop, so c = u.
  void after_flow_solve(const std::string& label);

  // Whether the transport is stepped: a scene with the scalar field or with growth; otherwise the
  // run is a flow run.
  bool transport_runs() const { return scene.scalar.enabled || scene.growth.enabled; }
  // The time of the run: the transport's, or the flow's in a flow run.
  double time() const;
  // The states whose change decides stationarity: the scalar's (when it runs), and with a
  // transient flow the flow's and the structure's displacement (each relative to its own size).
  std::vector<std::vector<double>> inner_states() const;
  // |wall shear stress| at the nodes of a face set.
  std::vector<double> wall_shear(const std::string& set) const;
  // The fields written at an output step (`extra` among them), on the mesh of output_mesh().
  std::vector<OutputField> output_fields(std::vector<OutputField> extra) const;
  Mesh output_mesh() const;

 private:
  void check_deformed_quality(const Mesh& current, const std::string& label);
};

// Relative change between two solutions: max|a - b| / max(max|a|, tiny).
double relative_change(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace biofsi
