#include "fluid/fluid.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "fluid/block_preconditioner.hpp"
#include "kernels/core/constraints.hpp"
#include "kernels/core/integrands.hpp"

namespace biofsi {

namespace {
FluidBoundaryCondition condition_on(const std::string& set, FluidBcKind kind,
                                    std::array<FluidFunction, 3> value = {}) {
  FluidBoundaryCondition bc;
  bc.set = set;
  bc.kind = kind;
  bc.value = std::move(value);
  return bc;
}
}  // namespace

FluidBoundaryCondition fluid_no_slip(const std::string& set) {
  return condition_on(set, FluidBcKind::Velocity);
}

FluidBoundaryCondition fluid_velocity(const std::string& set, FluidFunction ux, FluidFunction uy,
                                      FluidFunction uz) {
  return condition_on(set, FluidBcKind::Velocity, {std::move(ux), std::move(uy), std::move(uz)});
}

FluidBoundaryCondition fluid_slip(const std::string& set) {
  return condition_on(set, FluidBcKind::Slip);
}

FluidBoundaryCondition fluid_traction(const std::string& set, FluidFunction hx, FluidFunction hy,
                                      FluidFunction hz) {
  return condition_on(set, FluidBcKind::Traction, {std::move(hx), std::move(hy), std::move(hz)});
}

FluidBoundaryCondition fluid_pressure(const std::string& set, FluidFunction p) {
  return condition_on(set, FluidBcKind::Pressure, {std::move(p), nullptr, nullptr});
}

FluidBoundaryCondition fluid_do_nothing(const std::string& set) {
  return condition_on(set, FluidBcKind::DoNothing);
}

FluidField::FluidField(const Mesh& mesh, const FluidSettings& settings,
                       std::vector<FluidBoundaryCondition> conditions)
    : mesh_(mesh),
      settings_(settings),
      conditions_(std::move(conditions)),
      dmesh_(to_device(mesh)),
      aux_("biofsi::fluid_aux", mesh.n_nodes(), FluidPhysics::n_aux),
      op_(dmesh_.conn, dmesh_.x, dmesh_.element_block, aux_, FluidPhysics{}) {
  if (!(settings_.density > 0) || !(settings_.viscosity > 0))
    throw std::invalid_argument("fluid: density and viscosity must be positive");
  if (!(settings_.theta >= 0.5 && settings_.theta <= 1))
    throw std::invalid_argument("fluid: theta must be in [0.5, 1]");
  const int nn = mesh_.n_nodes();
  std::vector<char> active(nn, settings_.blocks.empty() ? 1 : 0);
  if (settings_.blocks.empty()) {
    for (int e = 0; e < mesh_.n_elements(); ++e) elements_.push_back(e);
  } else {
    for (const auto& name : settings_.blocks) {
      const int b = mesh_.block_index(name);
      if (b < 0) throw std::invalid_argument("fluid: unknown block '" + name + "'");
      for (int e : mesh_.elements_of_block(b)) {
        elements_.push_back(e);
        for (int n : mesh_.conn[e]) active[n] = 1;
      }
    }
    std::sort(elements_.begin(), elements_.end());
  }
  groups_ = make_element_groups(mesh_, elements_, settings_.scatter);
  state_ = Vector("biofsi::fluid_state", 4 * nn);
  state_old_ = Vector("biofsi::fluid_state_old", 4 * nn);
  scratch_ = Vector("biofsi::fluid_scratch", 4 * nn);
  matrix_ = make_sparsity(mesh_, elements_, 4);

  // Fixed dofs, later entries winning: the conditions in order, then w = 0 (pseudo-2-D), then the
  // nodes outside the fluid blocks (all four unknowns zero).
  std::map<int, const FluidFunction*> fixed;
  for (auto& bc : conditions_) {
    const bool faces_needed = bc.kind == FluidBcKind::Traction || bc.kind == FluidBcKind::Slip;
    if (faces_needed ? !mesh_.face_sets.count(bc.set) : !mesh_.node_sets.count(bc.set))
      throw std::invalid_argument("fluid boundary condition on unknown set '" + bc.set + "'");
    switch (bc.kind) {
      case FluidBcKind::Velocity:
        for (int n : mesh_.node_sets.at(bc.set))
          for (int c = 0; c < 3; ++c)
            if (bc.components[c]) fixed[4 * n + c] = bc.value[c] ? &bc.value[c] : nullptr;
        break;
      case FluidBcKind::Slip: {
        const int axis = axis_normal_of(bc.set);
        for (int n : mesh_.node_sets.at(bc.set)) fixed[4 * n + axis] = nullptr;
        break;
      }
      case FluidBcKind::Pressure:
        for (int n : mesh_.node_sets.at(bc.set))
          fixed[4 * n + 3] = bc.value[0] ? &bc.value[0] : nullptr;
        break;
      case FluidBcKind::Traction: {
        FaceTerm term{bc.set, bc.value, to_device(mesh_.face_sets.at(bc.set)),
                      NodalView("biofsi::fluid_face_aux", nn, 3),
                      FaceOperator<FluidTractionPhysics>(ConstFaceView{}, dmesh_.conn, dmesh_.x,
                                                         ConstNodalView{}, {})};
        term.op = FaceOperator<FluidTractionPhysics>(term.faces, dmesh_.conn, dmesh_.x, term.aux,
                                                     FluidTractionPhysics{});
        faces_.push_back(std::move(term));
        break;
      }
      case FluidBcKind::DoNothing:
        break;
    }
  }
  if (settings_.pseudo_2d)
    for (int n = 0; n < nn; ++n) fixed[4 * n + 2] = nullptr;
  for (int n = 0; n < nn; ++n)
    if (!active[n])
      for (int c = 0; c < 4; ++c) fixed[4 * n + c] = nullptr;
  Constraints constraints;
  for (const auto& [dof, f] : fixed) {
    fixed_list_.push_back({dof, f});
    constraints.add(dof, 0.0);
  }
  fixed_dofs_ = constraints.dofs();
  fixed_values_ = constraints.values();
  fixed_ = constraints.mask(4 * nn);

  if (settings_.preconditioner == FluidPreconditioner::MonolithicAmg) {
    AmgOptions o;
    o.num_functions = 4;  // (u, v, w, p) interleaved: one C/F choice per node
    o.nodal_coarsening = true;
    preconditioner_ = std::make_unique<BoomerAmg>(o);
  } else if (settings_.preconditioner == FluidPreconditioner::Direct) {
    preconditioner_ = std::make_unique<SparseLu>();
  } else {
    preconditioner_ = std::make_unique<SimplePreconditioner>(
        settings_.preconditioner == FluidPreconditioner::SimpleC,
        settings_.velocity_strong_threshold);
  }
  prepare(0.0, 1.0);
}

FluidField::~FluidField() = default;

int FluidField::axis_normal_of(const std::string& set) const {
  int axis = -1;
  for (const auto& f : mesh_.face_sets.at(set)) {
    const Point a = face_area_vector(mesh_, f);
    const double len = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    int best = 0;
    for (int d = 1; d < 3; ++d)
      if (std::abs(a[d]) > std::abs(a[best])) best = d;
    // 1e-8: round-off of the coordinates of a plane wall, far below any real tilt.
    if (std::abs(a[best]) < (1 - 1e-8) * len || (axis >= 0 && best != axis))
      throw std::invalid_argument("fluid: slip condition on '" + set +
                                  "' needs a plane wall normal to a coordinate axis");
    axis = best;
  }
  if (axis < 0) throw std::invalid_argument("fluid: slip condition on empty set '" + set + "'");
  return axis;
}

void FluidField::prepare(double inv_dt, double theta) {
  FluidPhysics p;
  p.density = settings_.density;
  p.viscosity = settings_.viscosity;
  p.inv_dt = inv_dt;
  p.theta = theta;
  p.supg = settings_.supg;
  p.grad_div = settings_.grad_div;
  p.symmetric_viscous = settings_.symmetric_viscous;
  p.transient_tau = settings_.transient_tau;
  p.linearisation = settings_.linearisation;
  op_.set_physics(p);
}

void FluidField::set_initial(const FluidVectorFunction& velocity, const FluidFunction& pressure,
                             double t0) {
  std::vector<double> s(4 * mesh_.n_nodes(), 0.0);
  for (int n = 0; n < mesh_.n_nodes(); ++n) {
    const Point u = velocity ? velocity(mesh_.x[n], t0) : Point{0, 0, 0};
    for (int d = 0; d < 3; ++d) s[4 * n + d] = u[d];
    s[4 * n + 3] = pressure ? pressure(mesh_.x[n], t0) : 0.0;
  }
  time_ = t0;
  set_solution(s);
}

void FluidField::set_solution(const std::vector<double>& s) {
  if (static_cast<int>(s.size()) != n_dofs())
    throw std::invalid_argument("fluid state has the wrong size");
  auto h = Kokkos::create_mirror_view(state_);
  for (size_t i = 0; i < s.size(); ++i) h(i) = s[i];
  Kokkos::deep_copy(state_, h);
  save_old_state();
}

void FluidField::save_old_state() {
  copy(state_, state_old_);
  auto aux = aux_;
  auto s = state_old_;
  Kokkos::parallel_for(
      "biofsi::fluid_old_velocity", Kokkos::RangePolicy<ExecSpace>(0, mesh_.n_nodes()),
      KOKKOS_LAMBDA(int n) {
        for (int d = 0; d < 3; ++d) aux(n, FluidPhysics::aux_velocity_old + d) = s(4 * n + d);
      });
}

void FluidField::set_body_force(const FluidVectorFunction& b) { body_force_ = b; }

void FluidField::update_body_force(double t) {
  if (!body_force_) return;
  auto h = Kokkos::create_mirror_view(aux_);
  Kokkos::deep_copy(h, aux_);
  for (int n = 0; n < mesh_.n_nodes(); ++n) {
    const Point b = body_force_(mesh_.x[n], t);
    for (int d = 0; d < 3; ++d) h(n, FluidPhysics::aux_body_force + d) = b[d];
  }
  Kokkos::deep_copy(aux_, h);
}

void FluidField::set_grid_velocity(const std::vector<Point>& ug) {
  if (static_cast<int>(ug.size()) != mesh_.n_nodes())
    throw std::invalid_argument("fluid: grid velocity has the wrong size");
  auto h = Kokkos::create_mirror_view(aux_);
  Kokkos::deep_copy(h, aux_);
  for (int n = 0; n < mesh_.n_nodes(); ++n)
    for (int d = 0; d < 3; ++d) h(n, FluidPhysics::aux_grid_velocity + d) = ug[n][d];
  Kokkos::deep_copy(aux_, h);
}

void FluidField::update_coordinates(const Mesh& moved, double dt) {
  if (moved.n_nodes() != mesh_.n_nodes())
    throw std::invalid_argument("fluid: moved mesh has a different number of nodes");
  if (dt > 0) {
    std::vector<Point> ug(mesh_.n_nodes());
    for (int n = 0; n < mesh_.n_nodes(); ++n)
      for (int d = 0; d < 3; ++d) ug[n][d] = (moved.x[n][d] - mesh_.x[n][d]) / dt;
    set_grid_velocity(ug);
    previous_x_ = mesh_.x;
  } else {
    previous_x_.clear();
  }
  mesh_.x = moved.x;
  copy_coordinates_to_device(mesh_, dmesh_.x);
}

void FluidField::place_configuration(double weight) {
  if (previous_x_.empty() || weight == 1) {
    copy_coordinates_to_device(mesh_, dmesh_.x);
    return;
  }
  Mesh m;
  m.x.resize(mesh_.x.size());
  for (size_t n = 0; n < m.x.size(); ++n)
    for (int d = 0; d < 3; ++d)
      m.x[n][d] = weight * mesh_.x[n][d] + (1 - weight) * previous_x_[n][d];
  copy_coordinates_to_device(m, dmesh_.x);
}

void FluidField::impose_dirichlet(double t) {
  auto h = Kokkos::create_mirror_view(fixed_values_);
  for (size_t i = 0; i < fixed_list_.size(); ++i) {
    const auto& f = fixed_list_[i];
    h(i) = f.value ? (*f.value)(mesh_.x[f.dof / 4], t) : 0.0;
  }
  Kokkos::deep_copy(fixed_values_, h);
  set_constrained(fixed_dofs_, fixed_values_, state_);
}

void FluidField::update_face_data(double t) {
  for (auto& f : faces_) {
    auto h = Kokkos::create_mirror_view(f.aux);
    for (int n : mesh_.node_sets.at(f.set))
      for (int d = 0; d < 3; ++d) h(n, d) = f.value[d] ? f.value[d](mesh_.x[n], t) : 0.0;
    Kokkos::deep_copy(f.aux, h);
  }
}

void FluidField::residual_unconstrained(ConstVector u, Vector r) const {
  fill(r, 0);
  op_.residual(groups_, u, r);
  for (const auto& f : faces_) f.op.residual(u, r);
}

void FluidField::tangent_unconstrained(ConstVector u, ConstVector du, Vector y) const {
  fill(y, 0);
  op_.apply_tangent(groups_, u, du, y);
  for (const auto& f : faces_) f.op.apply_tangent(u, du, y);
}

void FluidField::linearise(ConstVector u) {
  ScopedTimer t(stats_.seconds_linearise);
  linearisation_.update(op_, groups_, u);
}

void FluidField::tangent_linearised_unconstrained(ConstVector du, Vector y) const {
  fill(y, 0);
  apply_stored(linearisation_.tangent, du, y);
  for (const auto& f : faces_) f.op.apply_tangent(linearisation_.point, du, y);
}

void FluidField::apply_linearised(ConstVector du, Vector y) const {
  copy(du, scratch_);
  zero_constrained(fixed_dofs_, scratch_);
  tangent_linearised_unconstrained(scratch_, y);
  copy_constrained(fixed_dofs_, du, y);
}

void FluidField::residual(ConstVector u, Vector r) const {
  residual_unconstrained(u, r);
  constrained_residual(fixed_dofs_, fixed_values_, u, r);
}

void FluidField::apply_tangent(ConstVector u, ConstVector du, Vector y) const {
  copy(du, scratch_);
  zero_constrained(fixed_dofs_, scratch_);
  tangent_unconstrained(u, scratch_, y);
  copy_constrained(fixed_dofs_, du, y);
}

void FluidField::set_geometry(ConstCoordView x, ConstVector grid_velocity) {
  previous_x_.clear();  // the caller places the configuration
  Kokkos::deep_copy(dmesh_.x, x);
  auto aux = aux_;
  Kokkos::parallel_for(
      "biofsi::fluid_grid_velocity", Kokkos::RangePolicy<ExecSpace>(0, mesh_.n_nodes()),
      KOKKOS_LAMBDA(int n) {
        for (int d = 0; d < 3; ++d)
          aux(n, FluidPhysics::aux_grid_velocity + d) = grid_velocity(3 * n + d);
      });
}

void FluidField::sync_host_coordinates() {
  auto h = Kokkos::create_mirror_view_and_copy(HostSpace(), dmesh_.x);
  for (int n = 0; n < mesh_.n_nodes(); ++n)
    for (int d = 0; d < 3; ++d) mesh_.x[n][d] = h(n, d);
}

void FluidField::diagonal(ConstVector u, Vector d) const {
  fill(d, 0);
  op_.diagonal(groups_, u, d);
  for (const auto& f : faces_) f.op.diagonal(u, d);
  auto dofs = fixed_dofs_;
  Kokkos::parallel_for(
      "biofsi::fluid_unit_diagonal", Kokkos::RangePolicy<ExecSpace>(0, dofs.extent(0)),
      KOKKOS_LAMBDA(int i) { d(dofs(i)) = 1.0; });
}

const CsrMatrix& FluidField::assemble_jacobian(ConstVector u, bool eliminate) {
  ScopedTimer t(stats_.seconds_assembly);
  fill(matrix_.val, 0);
  op_.assemble(groups_, u, matrix_);
  for (const auto& f : faces_) f.op.assemble(u, matrix_);
  if (eliminate) csr_eliminate_constrained(matrix_, fixed_);
  return matrix_;
}

void FluidField::setup_preconditioner(ConstVector u) {
  assemble_jacobian(u);
  setup_preconditioner_on_matrix();
}

void FluidField::setup_preconditioner_on_matrix() {
  ScopedTimer t(stats_.seconds_preconditioner_setup);
  preconditioner_->setup(matrix_);
  ++stats_.preconditioner_setups;
  // The matrix may be the coupled problem's block: only this field's Newton, through
  // record_setup, knows that the preconditioner is its own.
  reuse_.invalidate();
}

void FluidField::precondition(ConstVector r, Vector z) const { preconditioner_->apply(r, z); }

NewtonResult FluidField::advance(const std::string& label) {
  NewtonOptions options = settings_.newton_options;
  // The storage term rho M u / dt dominates the residual for tiny dt; its round-off (~eps of its
  // size) is a floor below which no Newton iteration can reduce ||r||.
  const double inv_dt = op_.physics().inv_dt;
  if (inv_dt > 0) {
    double s = 0;
    const auto old = to_host_vector(state_old_);
    for (double v : old) s += v * v;
    double h3 = 0;  // a typical element volume
    for (int e : elements_) {
      const auto [lo, hi] = element_bounds(mesh_, e);
      h3 += (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    }
    h3 /= std::max<size_t>(1, elements_.size());
    options.abs_tol = std::max(options.abs_tol, 100 * std::numeric_limits<double>::epsilon() *
                                                    settings_.density * h3 * std::sqrt(s) * inv_dt);
  }
  NewtonSystem sys = timed_newton_system(
      [this](ConstVector u, Vector r) { residual(u, r); }, [this](ConstVector u) { linearise(u); },
      [this](ConstVector du, Vector y) { apply_linearised(du, y); }, stats_.seconds_residual,
      stats_.seconds_tangent);
  sys.setup_preconditioner = [this](ConstVector u) { setup_preconditioner(u); };
  sys.precondition = [this](ConstVector r, Vector z) { precondition(r, z); };
  sys.symmetric = false;
  // Steady solves start far from their solution (a flow from rest), where the Jacobian changes
  // too much between Newton steps: measured, an aged preconditioner doubled the Krylov iterations
  // of the cavity at Re 100 (LU: 13 for 5 Newton steps instead of 5) and left the Couette flow's
  // wall shear stress 1.003e-6 off instead of below 1e-6 (tests/fluid, tests/growth).
  options.reuse_preconditioner = options.reuse_preconditioner && inv_dt != 0;
  reuse_.require({inv_dt, op_.physics().theta});
  sys.reuse = &reuse_;
  NewtonResult result;
  {
    ScopedTimer t(stats_.seconds_solve);
    result = newton_solve(sys, state_, options);
  }
  ++stats_.steps;
  stats_.newton_iterations += result.iterations;
  stats_.krylov_iterations += result.krylov_iterations;
  if (!result.converged || !all_finite(state_)) {
    restore_old_state();
    throw SolveError("fluid", label, newton_failure(result));
  }
  return result;
}

void FluidField::begin_step(double dt) {
  const double theta = settings_.theta;
  save_old_state();
  prepare(1.0 / dt, theta);
  update_face_data(time_ + theta * dt);
  update_body_force(time_ + theta * dt);
  impose_dirichlet(time_ + dt);
}

void FluidField::begin_steady() {
  save_old_state();
  place_configuration(1.0);
  prepare(0.0, 1.0);
  update_face_data(time_);
  update_body_force(time_);
  impose_dirichlet(time_);
}

void FluidField::end_step(double dt) {
  time_ += dt;
  ++stats_.steps;
}

void FluidField::set_theta(double theta) {
  if (!(theta >= 0.5 && theta <= 1))
    throw std::invalid_argument("fluid: theta must be in [0.5, 1]");
  settings_.theta = theta;
}

NewtonResult FluidField::step_once(double dt, double theta, const std::string& label) {
  save_old_state();
  place_configuration(theta);
  prepare(1.0 / dt, theta);
  update_face_data(time_ + theta * dt);
  update_body_force(time_ + theta * dt);
  impose_dirichlet(time_ + dt);
  NewtonResult r = advance(label);
  time_ += dt;
  return r;
}

NewtonResult FluidField::step(double dt, const std::string& label) {
  if (!(dt > 0) || !std::isfinite(dt))
    throw SolveError("fluid", label, "time step must be positive and finite");
  try {
    return step_once(dt, settings_.theta, label);
  } catch (const SolveError& first) {
    const double t0 = time_;
    Vector start("biofsi::fluid_step_start", state_.extent(0));
    copy(state_, start);
    return retry_in_sub_steps(
        first, "fluid", label, dt, settings_.max_step_cuts,
        [&](double h, const std::string& l) { return step_once(h, settings_.theta, l); },
        [&] {
          copy(start, state_);
          save_old_state();
          time_ = t0;
        },
        stats_.cut_steps);
  }
}

NewtonResult FluidField::steady_newton(const std::string& label) {
  begin_steady();
  return advance(label);
}

NewtonResult FluidField::solve_steady(const std::string& label) {
  return solve_steady_with_continuation(
      "fluid", label, state_, time_, settings_.pseudo_transient_steps, settings_.pseudo_dt0,
      [&](const std::string& l) { return steady_newton(l); },
      [&](double dt, const std::string& l) { step_once(dt, 1.0, l); }, [&] { save_old_state(); },
      stats_.pseudo_steps);
}

std::vector<double> FluidField::solution_host() const { return to_host_vector(state_); }

std::vector<Point> FluidField::velocity() const {
  const auto s = solution_host();
  std::vector<Point> v(mesh_.n_nodes());
  for (int n = 0; n < mesh_.n_nodes(); ++n) v[n] = {s[4 * n], s[4 * n + 1], s[4 * n + 2]};
  return v;
}

std::vector<double> FluidField::pressure() const {
  const auto s = solution_host();
  std::vector<double> p(mesh_.n_nodes());
  for (int n = 0; n < mesh_.n_nodes(); ++n) p[n] = s[4 * n + 3];
  return p;
}

std::array<double, 4> FluidField::probe(const Point& x) const {
  const auto s = solution_host();
  for (int e : elements_) {
    const auto [lo, hi] = element_bounds(mesh_, e);
    bool inside = true;
    for (int d = 0; d < 3; ++d) {
      const double tol = 1e-10 * (hi[d] - lo[d] + 1);
      inside = inside && x[d] >= lo[d] - tol && x[d] <= hi[d] + tol;
    }
    if (!inside) continue;
    const std::array<double, 3> xi = hex8_reference_coordinates(mesh_, e, x);
    if (std::abs(xi[0]) > 1 + 1e-8 || std::abs(xi[1]) > 1 + 1e-8 || std::abs(xi[2]) > 1 + 1e-8)
      continue;
    const std::array<double, 8> n = hex8_shape_values(xi);
    std::array<double, 4> out{0, 0, 0, 0};
    for (int a = 0; a < 8; ++a)
      for (int k = 0; k < 4; ++k) out[k] += n[a] * s[4 * mesh_.conn[e][a] + k];
    return out;
  }
  std::ostringstream m;
  m << "fluid: probe point (" << x[0] << ", " << x[1] << ", " << x[2] << ") is in no element";
  throw std::invalid_argument(m.str());
}

BoundaryTraction FluidField::boundary_traction(const std::string& set) const {
  if (!mesh_.face_sets.count(set) || !mesh_.node_sets.count(set))
    throw std::invalid_argument("fluid: traction requested on unknown set '" + set + "'");
  // The element residual without constraints or face terms: at a converged state its value at a
  // wall node is the force the wall exerts on the fluid, r_a = int_wall N_a sigma n_fluid.
  Vector r("biofsi::fluid_reaction", n_dofs());
  op_.residual(groups_, state_, r);
  const auto rh = to_host_vector(r);
  Vector area("biofsi::fluid_lumped_area", mesh_.n_nodes());
  FaceOperator<UnitAreaIntegrand> faces(to_device(mesh_.face_sets.at(set)), dmesh_.conn, dmesh_.x,
                                        ConstNodalView{}, UnitAreaIntegrand{});
  faces.residual(Vector("biofsi::fluid_dummy", mesh_.n_nodes()), area);
  const auto ah = to_host_vector(area);
  std::vector<Point> normal_sum(mesh_.n_nodes(), Point{0, 0, 0});
  for (const auto& f : mesh_.face_sets.at(set)) {
    const Point a = face_area_vector(mesh_, f);
    for (int k = 0; k < 4; ++k) {
      const int n = mesh_.conn[f.element][hex8_face_nodes[f.local_face][k]];
      for (int d = 0; d < 3; ++d) normal_sum[n][d] += a[d];
    }
  }
  BoundaryTraction out;
  out.nodes = mesh_.node_sets.at(set);
  for (int n : out.nodes) {
    // Pseudo-2-D: the z reaction is the force that holds w = 0 on the front and back planes
    // (the pressure on them), not a force of this set's walls.
    Point force{-rh[4 * n], -rh[4 * n + 1], settings_.pseudo_2d ? 0.0 : -rh[4 * n + 2]};
    Point nrm = normal_sum[n];
    const double len = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
    for (double& v : nrm) v = len > 0 ? v / len : 0.0;
    Point t{0, 0, 0}, sh{0, 0, 0};
    if (ah[n] > 0) {
      for (int d = 0; d < 3; ++d) t[d] = force[d] / ah[n];
      const double tn = t[0] * nrm[0] + t[1] * nrm[1] + t[2] * nrm[2];
      for (int d = 0; d < 3; ++d) sh[d] = t[d] - tn * nrm[d];
    }
    for (int d = 0; d < 3; ++d) out.total[d] += force[d];
    out.force.push_back(force);
    out.area.push_back(ah[n]);
    out.normal.push_back(nrm);
    out.traction.push_back(t);
    out.shear.push_back(sh);
  }
  return out;
}

std::vector<Point> FluidField::wall_shear_stress(const std::string& set) const {
  return boundary_traction(set).shear;
}

}  // namespace biofsi
