#include "ale/mesh_motion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "kernels/core/constraints.hpp"

namespace biofsi {

void MeshDisplacementBc::fix(const std::vector<int>& nodes, std::array<bool, 3> components) {
  for (int n : nodes) {
    auto& f = fixed[n];
    for (int c = 0; c < 3; ++c) f[c] = f[c] || components[c];
    value.emplace(n, Point{0, 0, 0});
  }
}

void MeshDisplacementBc::prescribe(int node, const Point& d) {
  fixed[node] = {true, true, true};
  value[node] = d;
}

MeshDisplacementBc wall_constraints(const Mesh& mesh, const std::vector<std::string>& fixed_walls,
                                    const std::vector<std::string>& sliding_walls) {
  MeshDisplacementBc bc;
  for (const auto& wall : fixed_walls)
    if (mesh.node_sets.count(wall)) bc.fix(mesh.node_sets.at(wall), {true, true, true});
  for (const auto& wall : sliding_walls) {
    if (!mesh.node_sets.count(wall)) continue;
    const auto& nodes = mesh.node_sets.at(wall);
    const auto normal = nodal_normals(mesh, wall);
    for (size_t j = 0; j < nodes.size(); ++j) {
      std::array<bool, 3> mask{false, false, false};
      mask[wall_axis(normal[j], wall)] = true;
      bc.fix({nodes[j]}, mask);
    }
  }
  return bc;
}

namespace {

std::vector<int> all_elements(const Mesh& mesh) {
  std::vector<int> e(mesh.n_elements());
  for (int i = 0; i < mesh.n_elements(); ++i) e[i] = i;
  return e;
}

AmgOptions systems_amg() {
  AmgOptions o;
  o.num_functions = 3;  // interleaved x, y, z per node: systems AMG with nodal coarsening
  o.nodal_coarsening = true;
  return o;
}

}  // namespace

double centre_jacobian(const Mesh& mesh, int element) {
  // dx/dxi at xi = 0 is sum_a x_a (xi_a / 8)^T over the corners xi_a of the reference cube.
  constexpr int corner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  double j[3][3] = {};
  for (int a = 0; a < 8; ++a) {
    const Point& x = mesh.x[mesh.conn[element][a]];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) j[r][c] += x[r] * corner[a][c] / 8.0;
  }
  return j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1]) -
         j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0]) +
         j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0]);
}

PseudoElasticPhysics pseudo_elastic_physics(const MeshMotionSettings& settings, const Mesh& mesh,
                                            const std::vector<int>& elements) {
  // E = 1: only stiffness ratios matter with Dirichlet data on the whole boundary.
  const double nu = settings.poisson_ratio;
  PseudoElasticPhysics p;
  p.lambda = nu / ((1 + nu) * (1 - 2 * nu));
  p.mu = 1 / (2 * (1 + nu));
  p.stiffening = settings.stiffening;
  double smallest = std::numeric_limits<double>::infinity();
  for (int e : elements) smallest = std::min(smallest, centre_jacobian(mesh, e));
  if (!(smallest > 0))
    throw std::invalid_argument(
        "mesh motion: an element of the reference mesh has det J <= 0 at its centre (" +
        std::to_string(smallest) + "); the stiffening needs a valid mesh");
  p.reference_det = smallest;
  return p;
}

MeshMotion::MeshMotion(const Mesh& mesh, const MeshMotionSettings& settings)
    : MeshMotion(mesh, settings, all_elements(mesh)) {}

MeshMotion::MeshMotion(const Mesh& mesh, const MeshMotionSettings& settings,
                       const std::vector<int>& elements)
    : settings_(settings),
      topology_(mesh),
      dmesh_(to_device(mesh)),
      groups_(make_element_groups(mesh, elements, settings.scatter)),
      op_(dmesh_.conn, dmesh_.x, dmesh_.element_block, ConstNodalView{},
          pseudo_elastic_physics(settings, mesh, elements)),
      matrix_(make_sparsity(mesh, elements, 3)),
      amg_(systems_amg()) {}

void MeshMotion::bind(const Mesh& mesh) {
  if (mesh.n_nodes() != topology_.n_nodes() || mesh.n_elements() != topology_.n_elements())
    throw std::invalid_argument("mesh motion: the mesh changed its topology");
  copy_coordinates_to_device(mesh, dmesh_.x);
}

void MeshMotion::set_coordinates(const Mesh& mesh) { bind(mesh); }

void MeshMotion::linearise() {
  const Vector zero("biofsi::zero", 3 * topology_.n_nodes());
  fill(matrix_.val, 0);
  op_.assemble(groups_, zero, matrix_);
  biofsi::linearise(op_, groups_, zero, stored_);
}

void MeshMotion::add_residual(ConstVector d, Vector r) const { op_.residual(groups_, d, r); }

void MeshMotion::add_linearised(ConstVector d, Vector y) const { apply_stored(stored_, d, y); }

void MeshMotion::setup_preconditioner() {
  amg_.setup(matrix_);
  solve_reuse_.invalidate();  // amg_ now holds another problem's hierarchy
}

void MeshMotion::residual(const Mesh& mesh, ConstVector d, Vector r) {
  bind(mesh);
  fill(r, 0);
  add_residual(d, r);
}

void MeshMotion::assemble(const Mesh& mesh, const CsrMatrix& a) {
  bind(mesh);
  fill(a.val, 0);
  op_.assemble(groups_, Vector("biofsi::zero", 3 * mesh.n_nodes()), a);
}

std::vector<Point> MeshMotion::solve(const Mesh& mesh, const MeshDisplacementBc& bc,
                                     const std::string& label, MeshMotionResult* result) {
  bind(mesh);
  const int nn = mesh.n_nodes(), n = 3 * nn;
  Constraints constraints;
  for (const auto& [node, mask] : bc.fixed)
    for (int c = 0; c < 3; ++c)
      if (mask[c]) constraints.add(3 * node + c, bc.value.at(node)[c]);
  const auto fixed = constraints.mask(n);
  const IndexView fixed_dofs = constraints.dofs();
  Vector d("biofsi::mesh_displacement", n);
  set_constrained(fixed_dofs, constraints.values(), d);
  // One Newton step of a linear problem: K_ff delta_f = -(K d0)_f, delta_c = 0.
  Vector rhs("biofsi::mesh_rhs", n), scratch("biofsi::mesh_scratch", n);
  Vector delta("biofsi::mesh_delta", n);
  const ElementGroups& groups = groups_;
  const auto& op = op_;
  fill(rhs, 0);
  op.residual(groups, d, rhs);
  scale(-1.0, rhs);
  zero_constrained(fixed_dofs, rhs);
  biofsi::linearise(op, groups, d, stored_);
  const ApplyFn apply = [&](ConstVector x, Vector y) {
    copy(x, scratch);
    zero_constrained(fixed_dofs, scratch);
    fill(y, 0);
    apply_stored(stored_, scratch, y);
    copy_constrained(fixed_dofs, x, y);
  };
  std::vector<int> constrained;
  for (const auto& entry : constraints.value) constrained.push_back(entry.first);
  if (constrained != solve_constraints_) solve_reuse_.invalidate();
  const bool set_up = !solve_reuse_.still_serves(settings_.krylov.max_iterations);
  if (set_up) {
    fill(matrix_.val, 0);
    op.assemble(groups, d, matrix_);
    csr_eliminate_constrained(matrix_, fixed);
    amg_.setup(matrix_);
    solve_reuse_.record_setup();
    solve_constraints_ = std::move(constrained);
  } else {
    solve_reuse_.record_reuse();
  }
  const KrylovResult kr = cg(apply, amg_.as_function(), rhs, delta, settings_.krylov);
  solve_reuse_.record_solve(kr.iterations);
  if (!kr.converged) {
    std::ostringstream why;
    why << "CG " << kr.reason << " after " << kr.iterations << " iterations (residual "
        << kr.final_residual << " from " << kr.initial_residual << ")";
    throw SolveError("mesh motion", label, why.str());
  }
  axpy(1.0, delta, d);
  if (!all_finite(d)) throw SolveError("mesh motion", label, "non-finite displacement");
  auto dh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), d);
  std::vector<Point> out(nn);
  double max_d = 0;
  for (int i = 0; i < nn; ++i) {
    out[i] = {dh(3 * i), dh(3 * i + 1), dh(3 * i + 2)};
    max_d = std::max(
        max_d, std::sqrt(out[i][0] * out[i][0] + out[i][1] * out[i][1] + out[i][2] * out[i][2]));
  }
  if (result) {
    result->krylov_iterations = kr.iterations;
    result->preconditioner_set_up = set_up;
    result->max_displacement = max_d;
  }
  return out;
}

std::vector<QualityRange> mesh_quality_by_block(const Mesh& mesh) {
  const auto q = scaled_jacobians(mesh);
  std::vector<QualityRange> r(mesh.block_names.size());
  for (int e = 0; e < mesh.n_elements(); ++e) {
    QualityRange& b = r[mesh.element_block[e]];
    if (q[e] < b.min || b.worst_element < 0) {
      b.min = q[e];
      b.worst_element = e;
    }
    b.max = std::max(b.max, q[e]);
  }
  return r;
}

}  // namespace biofsi
