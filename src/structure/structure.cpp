#include "structure/structure.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "kernels/core/constraints.hpp"

namespace biofsi {

namespace {

void copy_to_device(const std::vector<double>& v, Vector d) {
  auto h = Kokkos::create_mirror_view(d);
  for (size_t i = 0; i < v.size(); ++i) h(i) = v[i];
  Kokkos::deep_copy(d, h);
}

// aux(:, first + c) = v(3 n + c)
void set_aux_vector(NodalView aux, int first, ConstVector v) {
  Kokkos::parallel_for(
      "biofsi::structure_aux", Kokkos::RangePolicy<ExecSpace>(0, aux.extent(0)),
      KOKKOS_LAMBDA(int n) {
        for (int c = 0; c < 3; ++c) aux(n, first + c) = v(3 * n + c);
      });
}

StructureMaterials device_materials(const std::vector<StructureMaterial>& m) {
  StructureMaterials out;
  for (size_t b = 0; b < m.size(); ++b) {
    out.model[b] = m[b].model;
    out.lambda[b] = m[b].lambda;
    out.mu[b] = m[b].mu;
    out.density[b] = m[b].density;
    for (int c = 0; c < 3; ++c) out.gravity[b][c] = m[b].gravity[c];
  }
  return out;
}

AmgOptions amg_options(StructureAmg variant, const Mesh& mesh) {
  AmgOptions o;
  if (variant == StructureAmg::Scalar) return o;
  o.num_functions = 3;
  o.nodal_coarsening = true;
  if (variant == StructureAmg::SystemsRigidBody) {
    // The three infinitesimal rotations about the centroid (the translations are what the nodal
    // interpolation reproduces anyway); centring keeps them well scaled against the translations.
    Point c{0, 0, 0};
    for (const auto& p : mesh.x)
      for (int d = 0; d < 3; ++d) c[d] += p[d] / mesh.n_nodes();
    const int n = 3 * mesh.n_nodes();
    o.interpolation_vectors.assign(3, std::vector<Real>(n, 0.0));
    for (int i = 0; i < mesh.n_nodes(); ++i) {
      const double x = mesh.x[i][0] - c[0], y = mesh.x[i][1] - c[1], z = mesh.x[i][2] - c[2];
      auto& rz = o.interpolation_vectors[0];
      auto& rx = o.interpolation_vectors[1];
      auto& ry = o.interpolation_vectors[2];
      rz[3 * i] = -y, rz[3 * i + 1] = x;
      rx[3 * i + 1] = -z, rx[3 * i + 2] = y;
      ry[3 * i] = z, ry[3 * i + 2] = -x;
    }
  }
  return o;
}

}  // namespace

StructureMaterial StructureMaterial::from_young(StructureModel model, double youngs_modulus,
                                                double poisson_ratio, double density) {
  if (!(youngs_modulus > 0) || !(poisson_ratio > -1 && poisson_ratio < 0.5))
    throw std::invalid_argument("structure material: need E > 0 and -1 < nu < 0.5");
  StructureMaterial m;
  m.model = model;
  const double e = youngs_modulus, nu = poisson_ratio;
  m.lambda = e * nu / ((1 + nu) * (1 - 2 * nu));
  m.mu = e / (2 * (1 + nu));
  m.density = density;
  return m;
}

struct StructureField::FaceTerm {
  StructureTraction bc;
  FaceView faces;
  NodalView aux;
  FaceOperator<DeadLoadTraction> op;
};

StructureField::StructureField(const Mesh& mesh, const StructureSettings& settings,
                               std::vector<StructureDirichlet> dirichlet,
                               std::vector<StructureTraction> tractions)
    : mesh_(mesh),
      settings_(settings),
      dmesh_(to_device(mesh)),
      aux_("biofsi::structure_aux", mesh.n_nodes(), StructurePhysics::n_aux),
      op_(dmesh_.conn, dmesh_.x, dmesh_.element_block, aux_, StructurePhysics{}),
      centre_op_(dmesh_.conn, dmesh_.x, dmesh_.element_block, aux_, StructurePhysics{}) {
  const int nb = static_cast<int>(mesh.block_names.size());
  if (nb > max_structure_blocks)
    throw std::invalid_argument("structure: at most " + std::to_string(max_structure_blocks) +
                                " blocks");
  if (static_cast<int>(settings.materials.size()) != nb)
    throw std::invalid_argument("structure: " + std::to_string(settings.materials.size()) +
                                " materials given for " + std::to_string(nb) + " mesh blocks");
  std::vector<char> active_block(nb, settings.blocks.empty() ? 1 : 0);
  for (const auto& name : settings.blocks) {
    const int b = mesh.block_index(name);
    if (b < 0) throw std::invalid_argument("structure: unknown block '" + name + "'");
    active_block[b] = 1;
  }
  for (int b = 0; b < nb; ++b) {
    const auto& m = settings.materials[b];
    if (active_block[b] && (!(m.mu > 0) || !(m.lambda + 2.0 * m.mu / 3.0 > 0) || !(m.density >= 0)))
      throw std::invalid_argument("structure: the material of block '" + mesh.block_names[b] +
                                  "' needs mu > 0, bulk modulus > 0, rho >= 0");
  }
  if (!settings.quasi_static && !(settings.theta >= 0.5 && settings.theta <= 1))
    throw std::invalid_argument("structure: theta must lie in [0.5, 1]");
  std::vector<char> active_node(mesh.n_nodes(), 0);
  for (int e = 0; e < mesh.n_elements(); ++e)
    if (active_block[mesh.element_block[e]]) {
      elements_.push_back(e);
      for (int a : mesh.conn[e]) active_node[a] = 1;
    }
  for (int node = 0; node < mesh.n_nodes(); ++node)
    if (active_node[node]) active_nodes_.push_back(node);
  {
    Point lo = active_nodes_.empty() ? Point{0, 0, 0} : mesh.x[active_nodes_[0]], hi = lo;
    for (int node : active_nodes_)
      for (int c = 0; c < 3; ++c)
        lo[c] = std::min(lo[c], mesh.x[node][c]), hi[c] = std::max(hi[c], mesh.x[node][c]);
    element_size_ = std::cbrt((hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]) /
                              std::max<size_t>(1, elements_.size()));
  }
  groups_ = make_element_groups(mesh_, elements_, settings_.scatter);
  const int n = n_dofs();
  d_ = Vector("biofsi::structure_d", n);
  v_ = Vector("biofsi::structure_v", n);
  u_ = Vector("biofsi::structure_u", n);
  scratch_ = Vector("biofsi::structure_scratch", n);
  matrix_ = make_sparsity(mesh_, elements_, 3);
  amg_ = std::make_unique<BoomerAmg>(amg_options(settings_.amg, mesh_));

  std::map<int, SpaceTimeFunction> by_dof;
  for (const auto& bc : dirichlet) {
    if (!mesh_.node_sets.count(bc.set))
      throw std::invalid_argument("structure Dirichlet condition on unknown node set '" + bc.set +
                                  "'");
    for (int node : mesh_.node_sets.at(bc.set))
      for (int c = 0; c < 3; ++c)
        if (bc.value[c]) by_dof[3 * node + c] = bc.value[c];
  }
  const SpaceTimeFunction zero = [](const Point&, double) { return 0.0; };
  if (settings_.plane_strain)
    for (int node = 0; node < mesh_.n_nodes(); ++node) by_dof[3 * node + 2] = zero;
  for (int node = 0; node < mesh_.n_nodes(); ++node)
    if (!active_node[node])
      for (int c = 0; c < 3; ++c) by_dof[3 * node + c] = zero;
  Constraints fixed;
  for (const auto& [dof, f] : by_dof) {
    dirichlet_.emplace_back(dof, f);
    fixed.add(dof, 0.0);
  }
  fixed_dofs_ = fixed.dofs();
  fixed_values_ = fixed.values();
  fixed_ = fixed.mask(n);

  for (auto& t : tractions) {
    if (!mesh_.face_sets.count(t.set))
      throw std::invalid_argument("structure traction on unknown face set '" + t.set + "'");
    FaceView faces = to_device(mesh_.face_sets.at(t.set));
    NodalView aux("biofsi::traction_aux", mesh_.n_nodes(), 3);
    faces_.push_back(FaceTerm{
        t, faces, aux,
        FaceOperator<DeadLoadTraction>(faces, dmesh_.conn, dmesh_.x, aux, DeadLoadTraction{})});
  }
}

StructureField::~StructureField() = default;

void StructureField::set_body_force(std::array<SpaceTimeFunction, 3> b) { body_force_ = b; }

void StructureField::set_state(const std::vector<Point>& d, const std::vector<Point>& v,
                               double t0) {
  const int nn = mesh_.n_nodes();
  if ((!d.empty() && static_cast<int>(d.size()) != nn) ||
      (!v.empty() && static_cast<int>(v.size()) != nn))
    throw std::invalid_argument("structure state has the wrong size");
  std::vector<double> dh(3 * nn, 0.0), vh(3 * nn, 0.0);
  for (int i = 0; i < nn; ++i)
    for (int c = 0; c < 3; ++c) {
      if (!d.empty()) dh[3 * i + c] = d[i][c];
      if (!v.empty()) vh[3 * i + c] = v[i][c];
    }
  copy_to_device(dh, d_);
  copy_to_device(vh, v_);
  time_ = t0;
}

std::vector<Point> StructureField::displacement() const {
  const auto h = to_host_vector(d_);
  std::vector<Point> out(mesh_.n_nodes());
  for (int i = 0; i < mesh_.n_nodes(); ++i) out[i] = {h[3 * i], h[3 * i + 1], h[3 * i + 2]};
  return out;
}

std::vector<Point> StructureField::velocity() const {
  const auto h = to_host_vector(v_);
  std::vector<Point> out(mesh_.n_nodes());
  for (int i = 0; i < mesh_.n_nodes(); ++i) out[i] = {h[3 * i], h[3 * i + 1], h[3 * i + 2]};
  return out;
}

// The state of the step t_n -> t_n + dt: aux = [d_n, v_n, b(t_{n+theta})], the physics'
// coefficients, the tractions theta t_{n+1} + (1 - theta) t_n, and the prescribed increments
// g(t_{n+1}) - d_n of the constrained dofs.
void StructureField::set_step_data(double dt) {
  const bool qs = settings_.quasi_static;
  const double theta = qs ? 1.0 : settings_.theta;
  const double t1 = time_ + dt;
  step_dt_ = dt;
  StructurePhysics p;
  p.materials = device_materials(settings_.materials);
  p.theta = theta;
  p.dt = qs ? 0.0 : dt;
  p.mass_coefficient = qs ? 0.0 : 1.0 / (theta * dt * dt);
  if (reduced_volumetric()) {
    StructurePhysics centre = p;
    centre.terms = EnergyTerms::Volumetric;
    centre_op_.set_physics(centre);
    p.terms = EnergyTerms::AllButVolumetric;
  }
  op_.set_physics(p);
  set_aux_vector(aux_, StructurePhysics::aux_displacement_old, d_);
  set_aux_vector(aux_, StructurePhysics::aux_velocity_old, v_);
  const int nn = mesh_.n_nodes();
  {
    auto h = Kokkos::create_mirror_view(aux_);
    Kokkos::deep_copy(h, aux_);
    for (int i = 0; i < nn; ++i)
      for (int c = 0; c < 3; ++c) {
        double b = 0;
        if (body_force_[c])
          b = theta * body_force_[c](mesh_.x[i], t1) +
              (theta < 1 ? (1 - theta) * body_force_[c](mesh_.x[i], time_) : 0.0);
        h(i, StructurePhysics::aux_body_force + c) = b;
      }
    Kokkos::deep_copy(aux_, h);
  }
  for (auto& f : faces_) {
    auto h = Kokkos::create_mirror_view(f.aux);
    for (int node : mesh_.node_sets.at(f.bc.set))
      for (int c = 0; c < 3; ++c) {
        double t = 0;
        if (f.bc.traction[c])
          t = theta * f.bc.traction[c](mesh_.x[node], t1) +
              (theta < 1 ? (1 - theta) * f.bc.traction[c](mesh_.x[node], time_) : 0.0);
        h(node, c) = t;
      }
    Kokkos::deep_copy(f.aux, h);
  }
  const auto dn = to_host_vector(d_);
  auto gh = Kokkos::create_mirror_view(fixed_values_);
  for (size_t i = 0; i < dirichlet_.size(); ++i) {
    const int dof = dirichlet_[i].first;
    gh(i) = dirichlet_[i].second(mesh_.x[dof / 3], t1) - dn[dof];
  }
  Kokkos::deep_copy(fixed_values_, gh);
}

void StructureField::prepare_step(double dt) {
  if (!(dt > 0) || !std::isfinite(dt))
    throw SolveError("structure", "prepare", "time step must be positive and finite");
  set_step_data(dt);
}

void StructureField::residual(ConstVector u, Vector r) const {
  residual_unconstrained(u, r);
  constrained_residual(fixed_dofs_, fixed_values_, u, r);
}

void StructureField::element_residual(ConstVector u, Vector r) const {
  op_.residual(groups_, u, r);
  if (reduced_volumetric()) centre_op_.residual(groups_, u, r);
}

void StructureField::element_tangent(ConstVector u, ConstVector du, Vector y) const {
  op_.apply_tangent(groups_, u, du, y);
  if (reduced_volumetric()) centre_op_.apply_tangent(groups_, u, du, y);
}

void StructureField::residual_unconstrained(ConstVector u, Vector r) const {
  fill(r, 0);
  element_residual(u, r);
  for (const auto& f : faces_) f.op.residual(u, r);
}

void StructureField::apply_tangent(ConstVector u, ConstVector du, Vector y) const {
  copy(du, scratch_);
  zero_constrained(fixed_dofs_, scratch_);
  fill(y, 0);
  element_tangent(u, scratch_, y);
  copy_constrained(fixed_dofs_, du, y);
}

void StructureField::linearise(ConstVector u) {
  ScopedTimer t(stats_.seconds_linearise);
  linearisation_.update(op_, groups_, u);
  if (reduced_volumetric()) centre_linearisation_.update(centre_op_, groups_, u);
}

void StructureField::apply_linearised(ConstVector du, Vector y) const {
  copy(du, scratch_);
  zero_constrained(fixed_dofs_, scratch_);
  fill(y, 0);
  apply_stored(linearisation_.tangent, scratch_, y);
  if (reduced_volumetric()) apply_stored<Hex8Centre>(centre_linearisation_.tangent, scratch_, y);
  copy_constrained(fixed_dofs_, du, y);
}

void StructureField::diagonal(ConstVector u, Vector d) const {
  fill(d, 0);
  op_.diagonal(groups_, u, d);
  if (reduced_volumetric()) centre_op_.diagonal(groups_, u, d);
  // Constrained rows of the tangent are identity rows.
  Vector ones("biofsi::ones", fixed_dofs_.extent(0));
  fill(ones, 1.0);
  set_constrained(fixed_dofs_, ones, d);
}

void StructureField::assemble(ConstVector u, bool constrained) {
  fill(matrix_.val, 0);
  op_.assemble(groups_, u, matrix_);
  if (reduced_volumetric()) centre_op_.assemble(groups_, u, matrix_);
  if (constrained) csr_eliminate_constrained(matrix_, fixed_);
}

void StructureField::setup_preconditioner(ConstVector u) {
  {
    ScopedTimer t(stats_.seconds_assembly);
    assemble(u, true);
  }
  setup_amg();
}

void StructureField::setup_amg() {
  ScopedTimer t(stats_.seconds_amg_setup);
  amg_->setup(matrix_);
  ++stats_.amg_setups;
  // The matrix may be the coupled problem's condensed block: only this field's Newton, through
  // record_setup, knows that the hierarchy is its own.
  reuse_.invalidate();
}

void StructureField::precondition(ConstVector r, Vector z) const { amg_->apply(r, z); }

void StructureField::set_reference_coordinates(const Mesh& moved) {
  if (moved.n_nodes() != mesh_.n_nodes())
    throw std::invalid_argument("structure: moved mesh has a different number of nodes");
  mesh_.x = moved.x;
  copy_coordinates_to_device(mesh_, dmesh_.x);
}

double StructureField::velocity_coefficient() const {
  return settings_.quasi_static ? 0.0 : 1.0 / (settings_.theta * step_dt_);
}

void StructureField::begin_step(double dt) {
  const bool static_now = settings_.quasi_static && dt == 0;  // equilibrium at the current time
  if (!static_now && (!(dt > 0) || !std::isfinite(dt)))
    throw SolveError("structure", "prepare", "time step must be positive and finite");
  set_step_data(dt);
  if (settings_.quasi_static)
    fill(u_, 0);
  else
    axpby(dt, v_, 0.0, u_);
  set_constrained(fixed_dofs_, fixed_values_, u_);
}

void StructureField::end_step(double dt) {
  if (settings_.quasi_static) {
    fill(v_, 0);
  } else {
    const double theta = settings_.theta;
    axpby(1.0 / (theta * dt), u_, -(1 - theta) / theta, v_);
  }
  axpy(1.0, u_, d_);
  time_ += dt;
  ++stats_.steps;
}

double StructureField::kinetic_energy() const { return energy(true); }

double StructureField::strain_energy() const { return energy(false); }

double StructureField::energy(bool kinetic) const {
  StructureEnergyIntegrand e;
  e.materials = device_materials(settings_.materials);
  e.kinetic = kinetic;
  NodalView aux("biofsi::energy_aux", mesh_.n_nodes(), 6);
  set_aux_vector(aux, 0, d_);
  set_aux_vector(aux, 3, v_);
  Vector r("biofsi::energy", mesh_.n_nodes()), unused("biofsi::energy_u", mesh_.n_nodes());
  // The energy the discrete equations minimise: with reduced volumetric integration, its
  // volumetric term by the centre rule.
  if (!kinetic && reduced_volumetric()) {
    e.terms = EnergyTerms::Volumetric;
    ElementOperator<StructureEnergyIntegrand, Hex8Centre>(dmesh_.conn, dmesh_.x,
                                                          dmesh_.element_block, aux, e)
        .residual(groups_, unused, r);
    e.terms = EnergyTerms::AllButVolumetric;
  }
  ElementOperator<StructureEnergyIntegrand> op(dmesh_.conn, dmesh_.x, dmesh_.element_block, aux, e);
  op.residual(groups_, unused, r);
  double s = 0;
  for (double x : to_host_vector(r)) s += x;
  return s;
}

std::vector<std::array<double, 6>> StructureField::cauchy_stress() const {
  // At the element centre (xi = 0), where the trilinear gradients are those of the element's
  // mean: one value per element for output, from the same constitutive functions as the kernels.
  const auto d = to_host_vector(d_);
  const StructureMaterials mats = device_materials(settings_.materials);
  constexpr double ref[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  std::vector<std::array<double, 6>> out(mesh_.n_elements());
  for (int e = 0; e < mesh_.n_elements(); ++e) {
    Real jac[3][3] = {}, gref[3][3] = {};
    for (int a = 0; a < 8; ++a) {
      const int node = mesh_.conn[e][a];
      for (int k = 0; k < 3; ++k) {
        const double dn = 0.125 * ref[a][k];  // dN_a/dxi_k at xi = 0
        for (int c = 0; c < 3; ++c) {
          jac[c][k] += mesh_.x[node][c] * dn;
          gref[c][k] += d[3 * node + c] * dn;
        }
      }
    }
    Real inv[3][3];
    invert_jacobian(jac, inv);
    Real g[3][3], sigma[3][3];
    for (int c = 0; c < 3; ++c) physical_gradient(inv, gref[c], g[c]);
    const int b = mesh_.element_block[e];
    biofsi::cauchy_stress(MaterialPoint{mats.model[b], mats.lambda[b], mats.mu[b]}, g, sigma);
    out[e] = {sigma[0][0], sigma[1][1], sigma[2][2], sigma[0][1], sigma[1][2], sigma[2][0]};
  }
  return out;
}

std::vector<double> StructureField::von_mises_stress() const {
  const auto s = cauchy_stress();
  std::vector<double> out(s.size());
  for (size_t e = 0; e < s.size(); ++e) {
    const Real m[3][3] = {
        {s[e][0], s[e][3], s[e][5]}, {s[e][3], s[e][1], s[e][4]}, {s[e][5], s[e][4], s[e][2]}};
    out[e] = von_mises(m);
  }
  return out;
}

// Brings the prescribed increments in through one linearised solve instead of setting them on
// the constrained dofs alone: J_ff(u) delta = -(r_f(u) + J_fc w_c) with w_c = g_c - u_c, then
// u += w + delta. Setting them alone would concentrate the whole boundary motion in the first layer
// of elements, which on a fine mesh inverts them (Neo-Hooke then has no finite residual there) or
// sends Newton to another branch; the lifted state is the tangent response of the whole body.
void StructureField::predict_dirichlet(const std::string& label) {
  const int n = n_dofs();
  Vector w("biofsi::structure_lift", n);
  {
    auto dofs = fixed_dofs_;
    auto g = fixed_values_;
    auto u = u_;
    Kokkos::parallel_for(
        "biofsi::structure_lift", Kokkos::RangePolicy<ExecSpace>(0, dofs.extent(0)),
        KOKKOS_LAMBDA(int i) { w(dofs(i)) = g(i) - u(dofs(i)); });
  }
  if (norm2(w) == 0) return;
  Vector rhs("biofsi::structure_lift_rhs", n), delta("biofsi::structure_lift_delta", n);
  element_residual(u_, rhs);
  for (const auto& f : faces_) f.op.residual(u_, rhs);
  element_tangent(u_, w, rhs);
  scale(-1.0, rhs);
  zero_constrained(fixed_dofs_, rhs);
  setup_preconditioner(u_);
  reuse_.record_setup();
  KrylovOptions k = settings_.newton.krylov;
  k.rel_tol = 1e-6;  // a predictor: Newton corrects what is left
  const ApplyFn apply = [this](ConstVector x, Vector y) { apply_tangent(u_, x, y); };
  const KrylovResult kr = settings_.use_cg ? cg(apply, amg_->as_function(), rhs, delta, k)
                                           : fgmres(apply, amg_->as_function(), rhs, delta, k);
  stats_.krylov_iterations += kr.iterations;
  if (!std::isfinite(kr.final_residual) || !all_finite(delta))
    throw SolveError("structure", label, "the Dirichlet predictor produced non-finite values");
  axpy(1.0, w, u_);
  axpy(1.0, delta, u_);
  set_constrained(fixed_dofs_, fixed_values_, u_);
}

// The residual is a sum of terms (inertia, theta-weighted stresses, loads) each of size ~|A_ii|
// times the displacements, which cancel at the solution; their round-off (~eps times their size)
// is a floor below which no Newton iteration can reduce ||r||. A relative tolerance on a small
// first residual (a step that starts close to its solution) could otherwise never be met.
double StructureField::roundoff_floor() const {
  // The diagonal of the last assembled tangent (zero before the first assembly: no floor then).
  Vector diag("biofsi::structure_floor_diag", n_dofs());
  csr_diagonal(matrix_, diag);
  auto d = d_;
  auto u = u_;
  // St. Venant-Kirchhoff forms its strain from grad d without cancellation, so its round-off is
  // relative to the displacements. Neo-Hooke's stress is an O(1) expression whose small-strain
  // value cancels: its round-off is eps times the modulus, i.e. eps |A_ii| times a length.
  bool neo_hooke = false;
  for (const auto& m : settings_.materials) neo_hooke = neo_hooke || m.model == NeoHooke;
  const double length = neo_hooke ? element_size_ : 0.0;
  double s = 0;
  Kokkos::parallel_reduce(
      "biofsi::structure_floor", Kokkos::RangePolicy<ExecSpace>(0, diag.extent(0)),
      KOKKOS_LAMBDA(int i, double& acc) {
        const double t = diag(i) * (math::fabs(d(i)) + math::fabs(u(i)) + length);
        acc += t * t;
      },
      s);
  // 1e4 eps: the nodal sums of ~80 element contributions with cancelling signs (measured on the
  // CSM1 flag: Newton stagnates at ~1e-12 where 100 eps |A_ii d| was 1e-14).
  return 1e4 * std::numeric_limits<double>::epsilon() * std::sqrt(s);
}

NewtonResult StructureField::step_once(double dt, const std::string& label) {
  set_step_data(dt);
  // The matrix's inertia term scales with 1/dt^2 and theta.
  reuse_.require({settings_.quasi_static ? 0.0 : dt, settings_.theta});
  // Predictor: constant velocity (dynamics) or no increment (quasi-static), then the prescribed
  // increments of the constrained dofs.
  if (settings_.quasi_static)
    fill(u_, 0);
  else
    axpby(dt, v_, 0.0, u_);
  predict_dirichlet(label);

  // The line search on G(s) = du . r(u + s du) (LineSearch::EnergyRegulaFalsi) instead of the
  // residual norm: for slender or soft bodies under large rotations the stiff membrane and
  // thickness directions dominate ||r||, so backtracking on it accepts steps of ~1e-3 and stalls
  // (measured on Cook's membrane and a soft cantilever).
  NewtonOptions options = settings_.newton;
  options.line_search = LineSearch::EnergyRegulaFalsi;
  NewtonSystem sys = timed_newton_system(
      [this](ConstVector u, Vector r) { residual(u, r); }, [this](ConstVector u) { linearise(u); },
      [this](ConstVector du, Vector y) { apply_linearised(du, y); }, stats_.seconds_residual,
      stats_.seconds_tangent);
  sys.setup_preconditioner = [this](ConstVector u) { setup_preconditioner(u); };
  sys.precondition = [this](ConstVector r, Vector z) { amg_->apply(r, z); };
  sys.reuse = &reuse_;
  sys.symmetric = settings_.use_cg;
  sys.roundoff_floors = [this](ConstVector) { return std::vector<Real>{roundoff_floor()}; };
  NewtonResult result;
  {
    ScopedTimer t(stats_.seconds_solve);
    result = newton_solve(sys, u_, options);
  }
  stats_.newton_iterations += result.iterations;
  stats_.krylov_iterations += result.krylov_iterations;
  stats_.last_step_krylov = result.krylov_history;
  if (!result.converged || !all_finite(u_)) {
    reuse_.invalidate();
    throw SolveError("structure", label, newton_failure(result));
  }
  end_step(dt);
  return result;
}

void StructureField::set_theta(double theta) {
  if (!(theta >= 0.5 && theta <= 1))
    throw std::invalid_argument("structure: theta must lie in [0.5, 1]");
  settings_.theta = theta;
}

NewtonResult StructureField::step(double dt, const std::string& label) {
  if (!(dt > 0) || !std::isfinite(dt))
    throw SolveError("structure", label, "time step must be positive and finite");
  const double t0 = time_;
  Vector d0("biofsi::structure_d0", d_.extent(0)), v0("biofsi::structure_v0", v_.extent(0));
  copy(d_, d0);
  copy(v_, v0);
  try {
    return step_once(dt, label);
  } catch (const SolveError& first) {
    // Cut the step: smaller load or time increments keep Newton inside its region of convergence
    // (large rotations of a soft body, a sudden load). A failed step_once may have left the
    // state anywhere: back to the start first.
    auto restore = [&] {
      copy(d0, d_);
      copy(v0, v_);
      time_ = t0;
    };
    restore();
    return retry_in_sub_steps(
        first, "structure", label, dt, settings_.max_step_cuts,
        [&](double h, const std::string& l) { return step_once(h, l); }, restore, stats_.cut_steps);
  }
}

}  // namespace biofsi
