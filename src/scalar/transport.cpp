#include "scalar/transport.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

#include "kernels/core/constraints.hpp"
#include "kernels/core/integrands.hpp"

namespace biofsi {

namespace {

void set_aux_column(NodalView aux, int column, ConstVector values) {
  Kokkos::parallel_for(
      "biofsi::set_aux_column", Kokkos::RangePolicy<ExecSpace>(0, values.extent(0)),
      KOKKOS_LAMBDA(int n) { aux(n, column) = values(n); });
}

template <class Physics>
std::vector<double> nodal_integrals(const Mesh& mesh, const DeviceMesh& dm,
                                    const std::vector<int>& elements, const Physics& physics,
                                    ConstVector u) {
  ElementOperator<Physics> op(dm.conn, dm.x, dm.element_block, ConstNodalView{}, physics);
  Vector r("biofsi::nodal_integral", mesh.n_nodes());
  op.residual(make_element_groups(mesh, elements, Scatter::Atomic), u, r);
  return to_host_vector(r);
}

}  // namespace

TransportField::TransportField(const Mesh& mesh, const TransportSettings& settings,
                               std::vector<ScalarBoundaryCondition> conditions)
    : mesh_(mesh),
      settings_(settings),
      dmesh_(to_device(mesh)),
      all_elements_(mesh.n_elements()),
      aux_("biofsi::scalar_aux", mesh.n_nodes(), TransportPhysics::n_aux),
      op_(dmesh_.conn, dmesh_.x, dmesh_.element_block, aux_, TransportPhysics{}) {
  if (settings.preconditioner == ScalarPreconditioner::Direct)
    preconditioner_ = std::make_unique<SparseLu>();
  else
    preconditioner_ = std::make_unique<BoomerAmg>(settings.amg);
  if (static_cast<int>(mesh.block_names.size()) > max_blocks)
    throw std::invalid_argument("scalar transport supports at most " + std::to_string(max_blocks) +
                                " blocks");
  for (int e = 0; e < mesh.n_elements(); ++e) all_elements_[e] = e;
  groups_ = make_element_groups(mesh_, all_elements_, settings_.scatter);
  const int nn = mesh.n_nodes();
  phi_ = Vector("biofsi::phi", nn);
  phi_old_ = Vector("biofsi::phi_old", nn);
  scratch_ = Vector("biofsi::scalar_scratch", nn);
  matrix_ = make_sparsity(mesh_, all_elements_, 1);

  for (auto& bc : conditions) {
    if (!mesh_.face_sets.count(bc.set))
      throw std::invalid_argument("scalar boundary condition on unknown set '" + bc.set + "'");
    if (bc.kind == ScalarBcKind::Dirichlet) {
      for (int n : mesh_.node_sets.at(bc.set)) dirichlet_[n] = bc.value;
    } else {
      FaceTerm term{bc, to_device(mesh_.face_sets.at(bc.set)), NodalView("biofsi::face_aux", nn, 4),
                    FaceOperator<TransportBoundaryPhysics>(ConstFaceView{}, dmesh_.conn, dmesh_.x,
                                                           ConstNodalView{}, {})};
      term.op = FaceOperator<TransportBoundaryPhysics>(term.faces, dmesh_.conn, dmesh_.x, term.aux,
                                                       TransportBoundaryPhysics{});
      faces_.push_back(std::move(term));
    }
  }
  // Which dofs are fixed never changes; their values are set at every step (impose_dirichlet).
  Constraints fixed;
  for (const auto& kv : dirichlet_) fixed.add(kv.first, 0.0);
  fixed_dofs_ = fixed.dofs();
  fixed_values_ = fixed.values();
  fixed_ = fixed.mask(nn);
  volume_weights_ = to_device_vector(
      nodal_integrals(mesh_, dmesh_, all_elements_, UnitVolumeIntegrand{}, phi_), "biofsi::vol");
}

void TransportField::set_initial(const SpaceTimeFunction& phi0, double t0) {
  std::vector<double> v(mesh_.n_nodes());
  for (int n = 0; n < mesh_.n_nodes(); ++n) v[n] = phi0(mesh_.x[n], t0);
  time_ = t0;
  set_solution(v);
}

void TransportField::set_solution(const std::vector<double>& phi) {
  if (static_cast<int>(phi.size()) != mesh_.n_nodes())
    throw std::invalid_argument("scalar solution has the wrong size");
  Kokkos::deep_copy(phi_, to_device_vector(phi, "biofsi::phi_in"));
  copy(phi_, phi_old_);
  set_aux_column(aux_, TransportPhysics::aux_phi_old, phi_old_);
}

void TransportField::set_convective_velocity(const std::vector<Point>& c) {
  if (static_cast<int>(c.size()) != mesh_.n_nodes())
    throw std::invalid_argument("convective velocity has the wrong size");
  auto h = Kokkos::create_mirror_view(aux_);
  Kokkos::deep_copy(h, aux_);
  has_convection_ = false;
  for (int n = 0; n < mesh_.n_nodes(); ++n)
    for (int d = 0; d < 3; ++d) {
      h(n, TransportPhysics::aux_convective_velocity + d) = c[n][d];
      has_convection_ = has_convection_ || c[n][d] != 0.0;
    }
  Kokkos::deep_copy(aux_, h);
  reuse_.invalidate();
}

void TransportField::set_material_velocity(const std::vector<Point>& w) {
  if (static_cast<int>(w.size()) != mesh_.n_nodes())
    throw std::invalid_argument("material velocity has the wrong size");
  auto h = Kokkos::create_mirror_view(aux_);
  Kokkos::deep_copy(h, aux_);
  for (int n = 0; n < mesh_.n_nodes(); ++n)
    for (int d = 0; d < 3; ++d) h(n, TransportPhysics::aux_material_velocity + d) = w[n][d];
  Kokkos::deep_copy(aux_, h);
  reuse_.invalidate();
}

void TransportField::set_source(const SpaceTimeFunction& s) { source_ = s; }

void TransportField::update_source(double t_eval) {
  if (!source_) return;
  std::vector<double> v(mesh_.n_nodes());
  for (int n = 0; n < mesh_.n_nodes(); ++n) v[n] = source_(mesh_.x[n], t_eval);
  set_aux_column(aux_, TransportPhysics::aux_source, to_device_vector(v, "biofsi::source"));
}

void TransportField::update_coordinates(const Mesh& mesh) {
  if (mesh.n_nodes() != mesh_.n_nodes())
    throw std::invalid_argument("moved mesh has a different number of nodes");
  mesh_.x = mesh.x;
  copy_coordinates_to_device(mesh_, dmesh_.x);
  volume_weights_ = to_device_vector(
      nodal_integrals(mesh_, dmesh_, all_elements_, UnitVolumeIntegrand{}, phi_), "biofsi::vol");
  reuse_.invalidate();
}

std::vector<double> TransportField::solution_host() const { return to_host_vector(phi_); }

void TransportField::impose_dirichlet(double t) {
  auto h = Kokkos::create_mirror_view(fixed_values_);
  size_t i = 0;
  for (const auto& [node, f] : dirichlet_) h(i++) = f(mesh_.x[node], t);
  Kokkos::deep_copy(fixed_values_, h);
  set_constrained(fixed_dofs_, fixed_values_, phi_);
}

void TransportField::update_face_data(double t_eval) {
  for (auto& f : faces_) {
    auto h = Kokkos::create_mirror_view(f.aux);
    for (int n : mesh_.node_sets.at(f.bc.set)) {
      const double v = f.bc.value(mesh_.x[n], t_eval);
      const bool robin = f.bc.kind == ScalarBcKind::Robin;
      h(n, TransportBoundaryPhysics::aux_flux) = robin ? 0.0 : v;
      h(n, TransportBoundaryPhysics::aux_coefficient) = robin ? f.bc.coefficient : 0.0;
      h(n, TransportBoundaryPhysics::aux_ambient) = robin ? v : 0.0;
    }
    Kokkos::deep_copy(f.aux, h);
    set_aux_column(f.aux, TransportBoundaryPhysics::aux_phi_old, phi_old_);
  }
}

void TransportField::set_step_physics(double inv_dt, double theta) {
  set_step_physics(inv_dt, theta, settings_.coefficients);
}

void TransportField::set_step_physics(double inv_dt, double theta,
                                      const TransportCoefficients& coefficients) {
  TransportPhysics p;
  p.coef = coefficients;
  p.inv_dt = inv_dt;
  p.theta = theta;
  p.supg = settings_.supg;
  op_.set_physics(p);
  TransportBoundaryPhysics b;
  b.theta = theta;
  for (auto& f : faces_) f.op.set_physics(b);
}

void TransportField::residual(ConstVector phi, Vector r) const {
  fill(r, 0);
  op_.residual(groups_, phi, r);
  for (const auto& f : faces_) f.op.residual(phi, r);
  constrained_residual(fixed_dofs_, fixed_values_, phi, r);
}

void TransportField::residual_of_step(ConstVector phi, Vector r) const {
  fill(r, 0);
  residual_stored(step_states_, phi, r);
  for (const auto& f : faces_) f.op.residual(phi, r);
  constrained_residual(fixed_dofs_, fixed_values_, phi, r);
}

void TransportField::apply_tangent(ConstVector phi, ConstVector dphi, Vector y) const {
  copy(dphi, scratch_);
  zero_constrained(fixed_dofs_, scratch_);
  fill(y, 0);
  op_.apply_tangent(groups_, phi, scratch_, y);
  for (const auto& f : faces_) f.op.apply_tangent(phi, scratch_, y);
  copy_constrained(fixed_dofs_, dphi, y);
}

void TransportField::linearise(ConstVector phi) { linearisation_.update(op_, groups_, phi); }

void TransportField::apply_linearised(ConstVector dphi, Vector y) const {
  copy(dphi, scratch_);
  zero_constrained(fixed_dofs_, scratch_);
  fill(y, 0);
  apply_stored(linearisation_.tangent, scratch_, y);
  // The face terms are a small part of the work: applied on the fly at the linearisation point.
  for (const auto& f : faces_) f.op.apply_tangent(linearisation_.point, scratch_, y);
  copy_constrained(fixed_dofs_, dphi, y);
}

void TransportField::setup_preconditioner(ConstVector phi) {
  {
    ScopedTimer t(stats_.seconds_assembly);
    fill(matrix_.val, 0);
    op_.assemble(groups_, phi, matrix_);
    for (const auto& f : faces_) f.op.assemble(phi, matrix_);
    csr_eliminate_constrained(matrix_, fixed_);
  }
  ScopedTimer t(stats_.seconds_preconditioner_setup);
  preconditioner_->setup(matrix_);
  ++stats_.preconditioner_setups;
}

double TransportField::storage_roundoff(double inv_dt) const {
  // The storage term M phi / dt dominates the residual for tiny dt; its entries carry round-off of
  // ~eps times their size, below which no Newton iteration can reduce ||r||.
  if (inv_dt == 0) return 0;
  const auto w = to_host_vector(volume_weights_);
  const auto phi = to_host_vector(phi_old_);
  double s = 0;
  for (size_t i = 0; i < w.size(); ++i) s += (w[i] * phi[i]) * (w[i] * phi[i]);
  return 100 * std::numeric_limits<double>::epsilon() * std::sqrt(s) * inv_dt;
}

NewtonResult TransportField::advance(const std::string& label, double abs_floor,
                                     bool fresh_preconditioner) {
  NewtonOptions options = settings_.newton;
  options.reuse_preconditioner = options.reuse_preconditioner && !fresh_preconditioner;
  options.abs_tol = std::max(options.abs_tol, abs_floor);
  {
    // Nothing the element terms read of the step (auxiliary fields, coefficients, mesh) changes
    // within the solve: one pass over them here, then every residual and linearisation of its
    // Newton iterations is a pass over phi alone.
    ScopedTimer t(stats_.seconds_residual);
    store_step_states(op_, groups_, phi_, step_states_);
  }
  NewtonSystem sys =
      timed_newton_system([this](ConstVector u, Vector r) { residual_of_step(u, r); },
                          [this](ConstVector u) {
                            ScopedTimer t(stats_.seconds_linearise);
                            linearisation_.update_from(step_states_, u);
                          },
                          [this](ConstVector du, Vector y) { apply_linearised(du, y); },
                          stats_.seconds_residual, stats_.seconds_tangent);
  sys.setup_preconditioner = [this](ConstVector u) { setup_preconditioner(u); };
  sys.reuse = &reuse_;
  sys.precondition = [this](ConstVector r, Vector z) { preconditioner_->apply(r, z); };
  sys.symmetric = !has_convection_;
  NewtonResult result;
  {
    ScopedTimer t(stats_.seconds_solve);
    result = newton_solve(sys, phi_, options);
  }
  ++stats_.steps;
  stats_.newton_iterations += result.iterations;
  stats_.krylov_iterations += result.krylov_iterations;
  if (!result.converged || !all_finite(phi_)) {
    copy(phi_old_, phi_);
    throw SolveError("scalar", label, newton_failure(result));
  }
  return result;
}

NewtonResult TransportField::step_once(double dt, double theta, const std::string& label,
                                       bool fresh_preconditioner) {
  copy(phi_, phi_old_);
  set_aux_column(aux_, TransportPhysics::aux_phi_old, phi_old_);
  const NewtonResult r = solve_step(dt, theta, label, fresh_preconditioner, settings_.coefficients);
  time_ += dt;
  return r;
}

NewtonResult TransportField::solve_step(double dt, double theta, const std::string& label,
                                        bool fresh_preconditioner,
                                        const TransportCoefficients& coefficients) {
  set_step_physics(1.0 / dt, theta, coefficients);
  update_face_data(time_ + theta * dt);
  update_source(time_ + theta * dt);
  impose_dirichlet(time_ + dt);
  // The matrix depends on dt and theta, the mesh and the velocity (which invalidate reuse_) and,
  // through Monod's derivative, on phi, which changes little from one step to the next.
  reuse_.require({dt, theta});
  return advance(label, storage_roundoff(1.0 / dt), fresh_preconditioner);
}

namespace {

// The half-saturation constants a continuation starts from and divides by at each stage. Where
// K is far below the concentrations, the rate k phi/(K + |phi|) is a step of width ~K at phi = 0,
// and Newton's model of it, flat on either side, sends the nodes just above a forming front below
// zero, where the rate jumps: the line search cannot recover. Solved with K' = 1e-2 of the
// largest concentration first and K' divided by 100 at each stage down to K, every stage starts
// from the previous one's solution, within Newton's reach (the steady continuation of
// tests/scalar/test_biofilm.cpp converges in 2-16 iterations per stage down to K = 1e-12).
constexpr double continuation_start = 1e-2, continuation_ratio = 1e-2;

}  // namespace

NewtonResult TransportField::step_or_continue(double dt, double theta, const std::string& label,
                                              bool fresh_preconditioner) {
  try {
    return step_once(dt, theta, label, fresh_preconditioner);
  } catch (const SolveError& failure) {
    // advance() restored phi_ to the step's start, phi_old_.
    const double start = continuation_start * max_abs(phi_old_);
    double smallest = std::numeric_limits<double>::infinity();
    for (int b = 0; b < max_blocks; ++b)
      if (settings_.coefficients.monod_rate[b] > 0)
        smallest = std::min(smallest, settings_.coefficients.monod_half_saturation[b]);
    if (!(smallest < start)) throw;
    try {
      return step_by_half_saturation_continuation(dt, theta, label, start, smallest);
    } catch (const SolveError&) {
      set_step_physics(1.0 / dt, theta);  // the field's own coefficients again
      throw failure;
    }
  }
}

NewtonResult TransportField::step_by_half_saturation_continuation(double dt, double theta,
                                                                  const std::string& label,
                                                                  double start, double smallest) {
  const TransportCoefficients& coef = settings_.coefficients;
  NewtonResult r;
  for (double level = start;; level *= continuation_ratio) {
    const double stage = std::max(level, smallest);
    TransportCoefficients c = coef;
    for (int b = 0; b < max_blocks; ++b)
      if (c.monod_rate[b] > 0)
        c.monod_half_saturation[b] = std::max(c.monod_half_saturation[b], stage);
    std::ostringstream l;
    l << label << " (continuation, K = " << stage << ")";
    r = solve_step(dt, theta, l.str(), true, c);
    if (stage == smallest) break;
  }
  set_step_physics(1.0 / dt, theta);
  time_ += dt;
  ++stats_.continued_steps;
  return r;
}

NewtonResult TransportField::step(double dt, const std::string& label) {
  if (!(dt > 0) || !std::isfinite(dt))
    throw SolveError("scalar", label, "time step must be positive and finite");
  try {
    return step_or_continue(dt, settings_.theta, label, false);
  } catch (const SolveError& first) {
    // Cut the step into 2, 4, ... sub-steps with a fresh preconditioner at every Newton
    // iteration: a steep reaction front (Monod with small K) needs smaller steps to be crossed.
    const double t0 = time_;
    Vector start("biofsi::phi_step_start", phi_.extent(0));
    copy(phi_, start);
    return retry_in_sub_steps(
        first, "scalar", label, dt, settings_.max_step_cuts,
        [&](double h, const std::string& l) {
          return step_or_continue(h, settings_.theta, l, true);
        },
        [&] {
          copy(start, phi_);
          copy(start, phi_old_);
          time_ = t0;
        },
        stats_.cut_steps);
  }
}

NewtonResult TransportField::steady_newton(const std::string& label) {
  copy(phi_, phi_old_);
  set_aux_column(aux_, TransportPhysics::aux_phi_old, phi_old_);
  set_step_physics(0.0, 1.0);
  update_face_data(time_);
  update_source(time_);
  impose_dirichlet(time_);
  reuse_.require({0.0, 1.0});
  reuse_.invalidate();
  return advance(label, 0.0, false);
}

NewtonResult TransportField::solve_steady(const std::string& label) {
  return solve_steady_with_continuation(
      "scalar", label, phi_, time_, settings_.pseudo_transient_steps, settings_.pseudo_dt0,
      [&](const std::string& l) { return steady_newton(l); },
      [&](double dt, const std::string& l) { step_or_continue(dt, 1.0, l, true); }, nullptr,
      stats_.pseudo_steps);
}

double TransportField::integral(int block) const {
  std::vector<double> w;
  if (block < 0)
    w = to_host_vector(volume_weights_);
  else
    w = nodal_integrals(mesh_, dmesh_, mesh_.elements_of_block(block), UnitVolumeIntegrand{}, phi_);
  const auto phi = solution_host();
  double s = 0;
  for (size_t n = 0; n < phi.size(); ++n) s += w[n] * phi[n];
  return s;
}

double TransportField::reaction_integral() const {
  MonodIntegrand m;
  m.coef = settings_.coefficients;
  const auto r = nodal_integrals(mesh_, dmesh_, all_elements_, m, phi_);
  double s = 0;
  for (double v : r) s += v;
  return s;
}

BoundaryFlux TransportField::boundary_flux(const std::string& set, int block) const {
  if (!mesh_.face_sets.count(set))
    throw std::invalid_argument("boundary flux requested on unknown set '" + set + "'");
  const std::vector<int> elements = block < 0 ? all_elements_ : mesh_.elements_of_block(block);
  Vector r("biofsi::flux_residual", mesh_.n_nodes());
  op_.residual(make_element_groups(mesh_, elements, Scatter::Atomic), phi_, r);
  const auto rh = to_host_vector(r);
  // The area of the block's own faces where the set lists both sides of an interface (each face
  // once), all of its faces otherwise.
  std::vector<BoundaryFace> own =
      block < 0 ? std::vector<BoundaryFace>{} : faces_of_block(mesh_, set, block);
  if (own.empty()) own = mesh_.face_sets.at(set);
  Vector area("biofsi::lumped_area", mesh_.n_nodes());
  FaceOperator<UnitAreaIntegrand> faces(to_device(own), dmesh_.conn, dmesh_.x, ConstNodalView{},
                                        UnitAreaIntegrand{});
  faces.residual(phi_, area);
  const auto ah = to_host_vector(area);
  BoundaryFlux out;
  out.nodes = mesh_.node_sets.at(set);
  for (int n : out.nodes) {
    out.nodal_flux.push_back(rh[n]);
    out.lumped_area.push_back(ah[n]);
    out.density.push_back(ah[n] > 0 ? rh[n] / ah[n] : 0.0);
    out.total += rh[n];
  }
  return out;
}

}  // namespace biofsi
