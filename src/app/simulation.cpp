#include "app/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "io/expression.hpp"

namespace biofsi {

namespace {

// When boundary data are checked before the run: its start, the end of its first step and the end
// of its time stages. Values at other times are checked where they are used (space_time_function),
// so an expression like 1/(t - 2) stops the run at t = 2, naming its key.
std::vector<double> check_times(const Scene& s) {
  double end = 0;
  for (const auto& stage : s.time.stages) end += stage.dt * stage.steps;
  return {0.0, s.time.dt, end};
}

std::vector<const SpaceTimeFunction*> functions_of(const ScalarBoundaryCondition& bc) {
  return {&bc.value};
}
template <class Bc>
std::vector<const SpaceTimeFunction*> functions_of(const Bc& bc) {
  std::vector<const SpaceTimeFunction*> out;
  for (const auto& f : bc.value)
    if (f) out.push_back(&f);
  return out;
}

// Evaluates each condition's expressions on the nodes of its boundary at check_times: a value
// that is not finite throws NonFiniteExpression before anything is solved or written.
template <class Bc>
std::vector<Bc> checked(std::vector<Bc> bcs, const Mesh& mesh, const std::vector<double>& times) {
  for (const Bc& bc : bcs) {
    auto nodes = mesh.node_sets.find(bc.set);
    if (nodes == mesh.node_sets.end()) continue;
    for (const SpaceTimeFunction* f : functions_of(bc))
      for (double t : times)
        for (int n : nodes->second) (*f)(mesh.x[n], t);
  }
  return bcs;
}

}  // namespace

Simulation::Simulation(const Scene& s)
    : scene(s),
      mesh(make_scene_mesh(s, &reoriented_elements)),
      scalar(mesh, s.scalar.settings,
             checked(scalar_boundary_conditions(s.scalar), mesh, check_times(s))) {
  if (s.fluid.enabled) {
    fluid = std::make_unique<FluidField>(
        mesh, s.fluid.settings, checked(fluid_boundary_conditions(s.fluid), mesh, check_times(s)));
    if (s.fluid.body_force) fluid->set_body_force(fluid_body_force(s.fluid));
  }
  if (s.structure.enabled) {
    structure = std::make_unique<StructureField>(
        mesh, s.structure.settings,
        checked(structure_boundary_conditions(s.structure), mesh, check_times(s)));
    if (s.structure.body_force) structure->set_body_force(structure_body_force(s.structure));
    if (fluid) fsi = std::make_unique<FsiProblem>(mesh, *fluid, *structure, s.fsi);
  }
  // Both evaluated at every node here, so a non-finite value stops the run before it starts.
  scalar.set_initial(space_time_function(s.scalar.initial, "fields.scalar.initial"), 0.0);
  const auto v = space_time_functions(s.scalar.velocity, "fields.scalar.velocity");
  std::vector<Point> c(mesh.n_nodes());
  for (int n = 0; n < mesh.n_nodes(); ++n)
    for (int d = 0; d < 3; ++d) c[n][d] = v[d](mesh.x[n], 0.0);
  scalar.set_convective_velocity(c);
}

NewtonResult Simulation::solve_steady_flow(const std::string& label) {
  const NewtonResult r = fsi ? fsi->solve_steady(label) : fluid->solve_steady(label);
  after_flow_solve(label);
  return r;
}

void Simulation::advance_flow(const std::string& label, double dt) {
  if (fsi)
    fsi->step(dt, label);
  else if (fluid)
    fluid->step(dt, label);
  else
    structure->step(dt, label);
  after_flow_solve(label);
}

bool Simulation::flow_is_transient() const {
  return fluid ? scene.fluid.mode == FlowMode::Transient : structure != nullptr;
}

void Simulation::set_theta(double theta) {
  if (fluid) fluid->set_theta(theta);
  if (structure) structure->set_theta(theta);
}

std::vector<Point> Simulation::displacement() const {
  return fsi ? fsi->displacement() : structure->displacement();
}

Mesh Simulation::growth_configuration(ReferenceUpdate update) const {
  return fsi && update == ReferenceUpdate::Reset ? fsi->current_mesh() : mesh;
}

void Simulation::take_grown_reference(const Mesh& grown, ReferenceUpdate update) {
  mesh.x = grown.x;
  if (!fsi) {
    scalar.update_coordinates(mesh);
    if (fluid) fluid->update_coordinates(mesh, 0.0);
    return;
  }
  fsi->set_reference(mesh);
  if (update == ReferenceUpdate::Reset) {
    const std::vector<Point> zero(mesh.n_nodes(), Point{0, 0, 0});
    structure->set_state(zero, structure->velocity(), structure->time());
    fsi->set_mesh_displacement(zero);
  }
  scalar.update_coordinates(fsi->current_mesh());
}

void Simulation::after_flow_solve(const std::string& label) {
  if (!fsi) {
    if (fluid) scalar.set_convective_velocity(fluid->velocity());
    return;
  }
  const Mesh current = fsi->current_mesh();
  check_deformed_quality(current, label);
  scalar.update_coordinates(current);
  std::vector<Point> c = fluid->velocity(), w = structure->velocity();
  const std::vector<Point> ug = fsi->grid_velocity();
  for (int n = 0; n < mesh.n_nodes(); ++n)
    for (int d = 0; d < 3; ++d) c[n][d] -= ug[n][d];
  scalar.set_convective_velocity(c);
  scalar.set_material_velocity(w);
}

// The deformed configuration must stay valid for the transport on it (and the next flow step).
void Simulation::check_deformed_quality(const Mesh& current, const std::string& label) {
  const auto q = mesh_quality_by_block(current);
  for (size_t b = 0; b < q.size(); ++b) {
    min_deformed_quality = std::min(min_deformed_quality, q[b].min);
    if (q[b].min < scene.fsi.mesh_motion.min_quality) {
      std::ostringstream why;
      why << "element " << q[b].worst_element << " of block '" << mesh.block_names[b]
          << "' has scaled Jacobian " << q[b].min
          << (q[b].min <= 0 ? " (inverted)" : " (degenerate)")
          << " in the deformed configuration, below mesh_motion.min_quality "
          << scene.fsi.mesh_motion.min_quality;
      throw SolveError("fsi", label, why.str());
    }
  }
}

void Simulation::invalidate_preconditioners() {
  scalar.invalidate_preconditioner();
  if (fluid) fluid->invalidate_preconditioner();
  if (structure) structure->invalidate_preconditioner();
  if (fsi) fsi->invalidate_preconditioner();
}

double Simulation::time() const {
  if (transport_runs()) return scalar.time();
  return fluid ? fluid->time() : structure->time();
}

std::vector<std::vector<double>> Simulation::inner_states() const {
  std::vector<std::vector<double>> out;
  if (transport_runs()) out.push_back(scalar.solution_host());
  if (flow_is_transient()) {
    if (fluid) out.push_back(fluid->solution_host());
    if (structure) {
      std::vector<double> d;
      for (const auto& p : structure->displacement()) d.insert(d.end(), p.begin(), p.end());
      out.push_back(std::move(d));
    }
  }
  return out;
}

std::vector<double> Simulation::wall_shear(const std::string& set) const {
  const std::vector<Point> tau = fluid->wall_shear_stress(set);
  std::vector<double> out(tau.size());
  for (size_t i = 0; i < tau.size(); ++i)
    out[i] = std::sqrt(tau[i][0] * tau[i][0] + tau[i][1] * tau[i][1] + tau[i][2] * tau[i][2]);
  return out;
}

std::vector<OutputField> Simulation::output_fields(std::vector<OutputField> extra) const {
  if (structure) {
    std::vector<double> d;
    for (const auto& v : displacement()) d.insert(d.end(), v.begin(), v.end());
    extra.insert(extra.begin(), {"displacement", 3, false, d});
    // The biofilm's stress state per element (zero outside the structure's blocks), and its
    // velocity (zero in quasi-static runs).
    const std::vector<double> all = structure->von_mises_stress();
    std::vector<double> vm(all.size(), 0.0), v;
    for (int e : structure->elements()) vm[e] = all[e];
    for (const auto& p : structure->velocity()) v.insert(v.end(), p.begin(), p.end());
    extra.push_back({"von_mises_stress", 1, true, vm});
    extra.push_back({"structure_velocity", 3, false, v});
  }
  if (fluid) {
    std::vector<double> u, p = fluid->pressure();
    for (const auto& v : fluid->velocity()) u.insert(u.end(), v.begin(), v.end());
    extra.insert(extra.begin(), {"pressure", 1, false, p});
    extra.insert(extra.begin(), {"velocity", 3, false, u});
  }
  if (scene.scalar.enabled) extra.insert(extra.begin(), {"phi", 1, false, scalar.solution_host()});
  return extra;
}

Mesh Simulation::output_mesh() const { return fsi ? fsi->current_mesh() : mesh; }

double relative_change(const std::vector<double>& a, const std::vector<double>& b) {
  double diff = 0, scale = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(a[i]));
  }
  return diff / std::max(scale, 1e-300);
}

}  // namespace biofsi
