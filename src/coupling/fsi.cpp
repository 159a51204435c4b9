#include "coupling/fsi.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "kernels/core/constraints.hpp"

namespace biofsi {

namespace {

using Range = std::pair<int, int>;

// The columns of a CSR matrix that belong to condensed dofs, for the rows of free dofs, as a
// matrix of their own (rows of the source, columns renumbered); values are refreshed from the
// source through the stored positions, so the pattern is searched once.
struct CouplingBlock {
  CsrMatrix m;
  Kokkos::View<int*, MemSpace> position;  // index of each entry in the source's val

  void refresh(const CsrMatrix& source) {
    auto pos = position;
    auto val = m.val;
    auto src = source.val;
    Kokkos::parallel_for(
        "biofsi::coupling_refresh", Kokkos::RangePolicy<ExecSpace>(0, pos.extent(0)),
        KOKKOS_LAMBDA(int k) { val(k) = src(pos(k)); });
  }
};

// row_of[r] >= 0: source row r becomes that row (of n_rows); column_of[c] >= 0: source column c
// becomes that column. Entries outside both maps are dropped.
CouplingBlock make_coupling(const CsrMatrix& source, const std::vector<int>& row_of,
                            const std::vector<int>& column_of, int n_rows) {
  auto rp = Kokkos::create_mirror_view_and_copy(HostSpace(), source.row_ptr);
  auto col = Kokkos::create_mirror_view_and_copy(HostSpace(), source.col);
  std::vector<int> source_row(n_rows, -1);
  for (int r = 0; r < source.n_rows; ++r)
    if (row_of[r] >= 0) source_row[row_of[r]] = r;
  std::vector<int> row_ptr{0}, cols, pos;
  for (int t = 0; t < n_rows; ++t) {
    const int r = source_row[t];
    if (r >= 0)
      for (int k = rp(r); k < rp(r + 1); ++k)
        if (column_of[col(k)] >= 0) {
          cols.push_back(column_of[col(k)]);
          pos.push_back(k);
        }
    row_ptr.push_back(static_cast<int>(cols.size()));
  }
  CouplingBlock b;
  b.m.n_rows = n_rows;
  b.m.row_ptr = Kokkos::View<int*, MemSpace>("biofsi::coupling_row_ptr", row_ptr.size());
  b.m.col = Kokkos::View<int*, MemSpace>("biofsi::coupling_col", cols.size());
  b.m.val = Kokkos::View<Real*, MemSpace>("biofsi::coupling_val", cols.size());
  b.position = Kokkos::View<int*, MemSpace>("biofsi::coupling_pos", pos.size());
  auto h_rp = Kokkos::create_mirror_view(b.m.row_ptr);
  auto h_col = Kokkos::create_mirror_view(b.m.col);
  auto h_pos = Kokkos::create_mirror_view(b.position);
  for (size_t i = 0; i < row_ptr.size(); ++i) h_rp(i) = row_ptr[i];
  for (size_t i = 0; i < cols.size(); ++i) {
    h_col(i) = cols[i];
    h_pos(i) = pos[i];
  }
  Kokkos::deep_copy(b.m.row_ptr, h_rp);
  Kokkos::deep_copy(b.m.col, h_col);
  Kokkos::deep_copy(b.position, h_pos);
  return b;
}

}  // namespace

struct FsiProblem::Impl {
  FluidField& fluid;
  StructureField& structure;
  FsiSettings settings;
  int nn;
  Range s_range, f_range, g_range;
  std::vector<char> structure_node;  // host: node of the structure's blocks
  IndexView interface;               // interface nodes
  Kokkos::View<char*, MemSpace> interface_node;
  Kokkos::View<const char*, MemSpace> structure_fixed, fluid_fixed;

  // The fluid mesh: pseudo-elasticity on the reference coordinates, over the fluid's elements.
  MeshMotion mesh_motion;
  CoordView x_work;
  IndexView mesh_fixed_dofs;  // walls and nodes outside the fluid, not the interface
  Vector mesh_fixed_values;
  Kokkos::View<char*, MemSpace> mesh_eliminated;  // fixed or condensed
  CouplingBlock mesh_coupling;   // free mesh rows x condensed mesh columns (= structure dofs)
  CouplingBlock fluid_coupling;  // free fluid rows x condensed velocity columns
  CouplingBlock force_coupling;  // interface momentum rows (structure rows) x free fluid columns
  double fd_length = 1;          // smallest fluid element size, for the shape-derivative step

  // The solve being set up: u_F = a s + b on Γ, grid velocity (d_G - d_G,n) inv_dt.
  double a = 0, inv_dt = 0;
  // The fluid solves on X + g_old + w (g - g_old): w = theta, the time level of every fluid
  // term (kernels/fluid/pointwise.hpp); 1 for steady solves and between steps.
  double configuration_weight = 1;
  Vector b, g_old, g_now, grid_velocity;
  // The assembled preconditioner's age (FsiSettings::reuse_preconditioner).
  PreconditionerReuse reuse;
  // Work vectors.
  Vector xs, dxs, r_base, f_work, g_dir, pre_work;
  Vector xs_lin;    // the synced state the Jacobian is taken at
  Mesh trial_mesh;  // host: a line-search trial's configuration, for its element check

  Impl(const Mesh& mesh, FluidField& f, StructureField& s, const FsiSettings& st)
      : fluid(f),
        structure(s),
        settings(st),
        nn(mesh.n_nodes()),
        s_range(0, 3 * nn),
        f_range(3 * nn, 7 * nn),
        g_range(7 * nn, 10 * nn),
        mesh_motion(mesh, st.mesh_motion, f.elements()) {}

  Vector part(Vector v, Range r) const { return Kokkos::subview(v, r); }
  ConstVector part(ConstVector v, Range r) const { return Kokkos::subview(v, r); }
};

FsiProblem::FsiProblem(const Mesh& mesh, FluidField& fluid, StructureField& structure,
                       const FsiSettings& settings)
    : impl_(std::make_unique<Impl>(mesh, fluid, structure, settings)), n_nodes_(mesh.n_nodes()) {
  Impl& m = *impl_;
  const int nn = n_nodes_;
  if (fluid.mesh().n_nodes() != nn || structure.mesh().n_nodes() != nn)
    throw std::invalid_argument("fsi: fluid, structure and coupling must share one mesh");
  if (!mesh.node_sets.count(settings.interface))
    throw std::invalid_argument("fsi: the mesh has no interface node set '" + settings.interface +
                                "'");
  const std::vector<int>& gamma = mesh.node_sets.at(settings.interface);
  m.structure_node.assign(nn, 0);
  for (int n : structure.active_nodes()) m.structure_node[n] = 1;
  std::vector<char> fluid_node(nn, 0), on_gamma(nn, 0);
  for (int e : fluid.elements())
    for (int a : mesh.conn[e]) fluid_node[a] = 1;
  const std::vector<char> fluid_fixed = to_host(fluid.constrained_mask());
  for (int n : gamma) {
    if (!m.structure_node[n] || !fluid_node[n])
      throw std::invalid_argument("fsi: interface node " + std::to_string(n) + " of '" +
                                  settings.interface +
                                  "' is not shared by the structure and the fluid");
    for (int c = 0; c < 3; ++c)
      if (!fluid_fixed[4 * n + c])
        throw std::invalid_argument(
            "fsi: the fluid needs a no_slip (velocity) condition on the "
            "interface '" +
            settings.interface + "': its velocity there is condensed");
    on_gamma[n] = 1;
  }
  m.interface = to_device(gamma, "biofsi::fsi_interface");
  m.interface_node = to_device(on_gamma, "biofsi::fsi_interface_mask");
  m.structure_fixed = structure.constrained_mask();
  m.fluid_fixed = fluid.constrained_mask();

  // Coupling patterns of the fluid Jacobian: free fluid rows x condensed velocity columns (as
  // structure dofs), and interface momentum rows (as structure rows) x free fluid columns.
  {
    const std::vector<char> structure_fixed = to_host(structure.constrained_mask());
    std::vector<int> free_rows(4 * nn, -1), velocity_columns(4 * nn, -1), gamma_rows(4 * nn, -1),
        free_columns(4 * nn, -1);
    for (int i = 0; i < 4 * nn; ++i)
      if (!fluid_fixed[i]) free_rows[i] = free_columns[i] = i;
    for (int n : gamma)
      for (int c = 0; c < 3; ++c) {
        velocity_columns[4 * n + c] = 3 * n + c;
        if (!structure_fixed[3 * n + c]) gamma_rows[4 * n + c] = 3 * n + c;
      }
    m.fluid_coupling = make_coupling(fluid.matrix(), free_rows, velocity_columns, 4 * nn);
    m.force_coupling = make_coupling(fluid.matrix(), gamma_rows, free_columns, 3 * nn);
  }

  // The fluid mesh's constraints: walls and every non-fluid node, except the condensed interface.
  {
    MeshDisplacementBc walls = wall_constraints(mesh, settings.mesh_motion.fixed_walls,
                                                settings.mesh_motion.sliding_walls);
    for (int n = 0; n < nn; ++n)
      if (!fluid_node[n]) walls.fix({n}, {true, true, true});
    Constraints fixed;
    std::vector<char> eliminated(3 * nn, 0);
    for (const auto& [node, mask] : walls.fixed)
      for (int c = 0; c < 3; ++c)
        if (mask[c] && !on_gamma[node]) {
          fixed.add(3 * node + c, 0.0);
          eliminated[3 * node + c] = 1;
        }
    for (int n : gamma)
      for (int c = 0; c < 3; ++c) eliminated[3 * n + c] = 1;
    m.mesh_fixed_dofs = fixed.dofs();
    m.mesh_fixed_values = fixed.values();
    m.mesh_eliminated = to_device(eliminated, "biofsi::fsi_mesh_eliminated");
  }
  m.x_work = CoordView("biofsi::fsi_x", nn);
  m.b = Vector("biofsi::fsi_b", 3 * nn);
  m.g_old = Vector("biofsi::fsi_g_old", 3 * nn);
  m.g_now = Vector("biofsi::fsi_g", 3 * nn);
  m.grid_velocity = Vector("biofsi::fsi_grid_velocity", 3 * nn);
  m.xs = Vector("biofsi::fsi_xs", n_dofs());
  m.dxs = Vector("biofsi::fsi_dxs", n_dofs());
  m.xs_lin = Vector("biofsi::fsi_xs_lin", n_dofs());
  m.r_base = Vector("biofsi::fsi_r_base", 4 * nn);
  m.f_work = Vector("biofsi::fsi_f_work", 4 * nn);
  m.g_dir = Vector("biofsi::fsi_g_dir", 3 * nn);
  m.pre_work = Vector("biofsi::fsi_pre_work", n_dofs());
  x_ = Vector("biofsi::fsi_x", n_dofs());
  set_reference(mesh);
}

FsiProblem::~FsiProblem() = default;

void FsiProblem::set_reference(const Mesh& mesh) {
  Impl& m = *impl_;
  m.reuse.invalidate();
  m.mesh_motion.set_coordinates(mesh);
  m.structure.set_reference_coordinates(mesh);
  // The smallest fluid element edge, for the size of the finite-difference shape perturbation.
  double h_min = std::numeric_limits<double>::infinity();
  for (int e : m.fluid.elements()) {
    const auto& c = mesh.conn[e];
    for (int k = 0; k < 3; ++k) {
      const int nb = k == 0 ? 1 : (k == 1 ? 3 : 4);  // VTK: edges 0-1 (x), 0-3 (y), 0-4 (z)
      double l = 0;
      for (int d = 0; d < 3; ++d) l += std::pow(mesh.x[c[nb]][d] - mesh.x[c[0]][d], 2);
      h_min = std::min(h_min, std::sqrt(l));
    }
  }
  m.fd_length = std::isfinite(h_min) && h_min > 0 ? h_min : 1.0;
  // The fluid mesh's matrix on the new reference, its coupling columns, then the elimination.
  {
    ScopedTimer t(stats_.seconds_assembly);
    m.mesh_motion.linearise();
  }
  {
    const std::vector<char> eliminated = to_host(m.mesh_eliminated);
    std::vector<int> row_of(3 * n_nodes_, -1), column_of(3 * n_nodes_, -1);
    for (int i = 0; i < 3 * n_nodes_; ++i)
      if (!eliminated[i]) row_of[i] = i;
    for (int n : mesh.node_sets.at(m.settings.interface))
      for (int c = 0; c < 3; ++c) column_of[3 * n + c] = 3 * n + c;
    m.mesh_coupling = make_coupling(m.mesh_motion.matrix(), row_of, column_of, 3 * n_nodes_);
    m.mesh_coupling.refresh(m.mesh_motion.matrix());
  }
  csr_eliminate_constrained(m.mesh_motion.matrix(), m.mesh_eliminated);
  {
    ScopedTimer t(stats_.seconds_preconditioner_setup);
    m.mesh_motion.setup_preconditioner();
  }
  // The fluid sees the new reference moved by the fluid mesh displacement it had.
  auto x = m.x_work;
  auto x0 = m.mesh_motion.coordinates();
  auto g = m.g_now;
  Kokkos::parallel_for(
      "biofsi::fsi_geometry", Kokkos::RangePolicy<ExecSpace>(0, n_nodes_), KOKKOS_LAMBDA(int n) {
        for (int d = 0; d < 3; ++d) x(n, d) = x0(n, d) + g(3 * n + d);
      });
  fill(m.grid_velocity, 0);
  m.fluid.set_geometry(m.x_work, m.grid_velocity);
  m.fluid.sync_host_coordinates();
}

namespace {

// f(n, c) for every interface node n and component c.
template <class F>
void for_interface_dofs(const FsiProblem::Impl& m, const char* label, F f) {
  auto iface = m.interface;
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<ExecSpace>(0, iface.extent(0)), KOKKOS_LAMBDA(int i) {
        for (int c = 0; c < 3; ++c) f(iface(i), c);
      });
}

// xs = x with the condensed entries recomputed from the structure's: u_F = a s + b, d_G = d_n + s
// for a state; du_F = a ds, dd_G = ds for a direction (b and d_n empty).
void sync_condensed(const FsiProblem::Impl& m, ConstVector x, Vector xs, ConstVector b,
                    ConstVector d_n) {
  copy(x, xs);
  const int nn = m.nn;
  const double a = m.a;
  const bool state = b.extent(0) > 0;
  for_interface_dofs(
      m, "biofsi::fsi_sync", KOKKOS_LAMBDA(int n, int c) {
        const Real s = xs(3 * n + c);
        xs(3 * nn + 4 * n + c) = a * s + (state ? b(3 * n + c) : 0.0);
        xs(7 * nn + 3 * n + c) = (state ? d_n(3 * n + c) : 0.0) + s;
      });
}

void sync_state(const FsiProblem::Impl& m, ConstVector x, Vector xs, ConstVector d_n) {
  sync_condensed(m, x, xs, m.b, d_n);
}

void sync_direction(const FsiProblem::Impl& m, ConstVector dx, Vector dxs) {
  sync_condensed(m, dx, dxs, ConstVector(), ConstVector());
}

// x_work = X + g_old + w (g - g_old), grid velocity (g - g_old) inv_dt, handed to the fluid.
void move_fluid_mesh(FsiProblem::Impl& m, ConstVector g) {
  auto x = m.x_work;
  auto x0 = m.mesh_motion.coordinates();
  auto ug = m.grid_velocity;
  auto g_old = m.g_old;
  const double inv_dt = m.inv_dt, w = m.configuration_weight;
  Kokkos::parallel_for(
      "biofsi::fsi_move_mesh", Kokkos::RangePolicy<ExecSpace>(0, m.nn), KOKKOS_LAMBDA(int n) {
        for (int d = 0; d < 3; ++d) {
          const Real dg = g(3 * n + d) - g_old(3 * n + d);
          x(n, d) = x0(n, d) + g_old(3 * n + d) + w * dg;
          ug(3 * n + d) = dg * inv_dt;
        }
      });
  m.fluid.set_geometry(m.x_work, m.grid_velocity);
}

// Interface force: the fluid's interface momentum rows added to the structure's free rows.
void add_interface_rows(const FsiProblem::Impl& m, ConstVector fluid_rows, Vector structure_rows) {
  auto fixed = m.structure_fixed;
  for_interface_dofs(
      m, "biofsi::fsi_interface_force", KOKKOS_LAMBDA(int n, int c) {
        if (!fixed(3 * n + c)) structure_rows(3 * n + c) += fluid_rows(4 * n + c);
      });
}

// Condensed rows: identity in the tangent (y = dx) or zero residual (dx = 0).
void condensed_rows(const FsiProblem::Impl& m, ConstVector from, Vector y_fluid, Vector y_mesh,
                    bool zero) {
  const int nn = m.nn;
  for_interface_dofs(
      m, "biofsi::fsi_condensed_rows", KOKKOS_LAMBDA(int n, int c) {
        y_fluid(4 * n + c) = zero ? 0.0 : from(3 * nn + 4 * n + c);
        y_mesh(3 * n + c) = zero ? 0.0 : from(7 * nn + 3 * n + c);
      });
}

// The condensed velocity entries of a fluid direction, from the structure's.
void set_condensed_velocity(const FsiProblem::Impl& m, ConstVector ds, Vector df) {
  const double a = m.a;
  for_interface_dofs(
      m, "biofsi::fsi_condensed_velocity",
      KOKKOS_LAMBDA(int n, int c) { df(4 * n + c) = a * ds(3 * n + c); });
}

}  // namespace

void FsiProblem::residual(ConstVector x, Vector r) {
  Impl& m = *impl_;
  ScopedTimer t(stats_.seconds_residual);
  sync_state(m, x, m.xs, m.structure.displacement_device());
  const ConstVector s = m.part(ConstVector(m.xs), m.s_range),
                    f = m.part(ConstVector(m.xs), m.f_range),
                    g = m.part(ConstVector(m.xs), m.g_range);
  Vector rs = m.part(r, m.s_range), rf = m.part(r, m.f_range), rg = m.part(r, m.g_range);
  move_fluid_mesh(m, g);
  m.structure.residual(s, rs);
  m.fluid.residual_unconstrained(f, rf);
  add_interface_rows(m, rf, rs);
  constrained_residual(m.fluid.constrained_dofs(), m.fluid.constrained_values(), f, rf);
  fill(rg, 0);
  m.mesh_motion.add_residual(g, rg);
  constrained_residual(m.mesh_fixed_dofs, m.mesh_fixed_values, g, rg);
  condensed_rows(m, x, rf, rg, true);
}

namespace {

// y = J dx at the state the caller synced into m.xs_lin (fluid mesh already placed there), with
// the unconstrained fluid residual there in m.r_base when shape derivatives are on.
void apply_jacobian(FsiProblem::Impl& m, FsiStats& stats, ConstVector dx, Vector y) {
  ScopedTimer t(stats.seconds_tangent);
  const ConstVector xl = m.xs_lin;
  const ConstVector f = m.part(xl, m.f_range), g = m.part(xl, m.g_range);
  sync_direction(m, dx, m.dxs);
  Vector ds = m.part(m.dxs, m.s_range), df = m.part(m.dxs, m.f_range),
         dg = m.part(m.dxs, m.g_range);
  Vector ys = m.part(y, m.s_range), yf = m.part(y, m.f_range), yg = m.part(y, m.g_range);
  m.structure.apply_linearised(ds, ys);
  // Fluid: the direction without its constrained entries, except the condensed velocities.
  zero_constrained(m.fluid.constrained_dofs(), df);
  set_condensed_velocity(m, ds, df);
  m.fluid.tangent_linearised_unconstrained(df, yf);
  // Fluid mesh: the direction without its fixed entries (the condensed ones are ds).
  zero_constrained(m.mesh_fixed_dofs, dg);
  if (m.settings.shape_derivatives == ShapeDerivatives::FiniteDifference) {
    const double dg_max = max_abs(dg);
    if (dg_max > 0) {
      ScopedTimer ts(stats.seconds_shape);
      // A step that moves the nodes by 1e-7 of the smallest element: truncation ~1e-7, round-off
      // ~eps/1e-7 ~ 2e-9 of the derivative.
      const double h = 1e-7 * m.fd_length / dg_max;
      copy(g, m.g_dir);
      axpy(h, dg, m.g_dir);
      move_fluid_mesh(m, m.g_dir);
      m.fluid.residual_unconstrained(f, m.f_work);
      axpy(-1.0, m.r_base, m.f_work);
      axpy(1.0 / h, m.f_work, yf);
      move_fluid_mesh(m, g);
    }
  }
  add_interface_rows(m, yf, ys);
  copy_constrained(m.fluid.constrained_dofs(), m.part(dx, m.f_range), yf);
  fill(yg, 0);
  m.mesh_motion.add_linearised(dg, yg);
  copy_constrained(m.mesh_fixed_dofs, m.part(dx, m.g_range), yg);
  condensed_rows(m, dx, yf, yg, false);
}

// Takes the Jacobian at x: synced state, fluid mesh, the fields' stored tangents, base residual
// for the shape derivative.
void linearise(FsiProblem::Impl& m, ConstVector x) {
  sync_state(m, x, m.xs_lin, m.structure.displacement_device());
  move_fluid_mesh(m, m.part(ConstVector(m.xs_lin), m.g_range));
  m.structure.linearise(m.part(ConstVector(m.xs_lin), m.s_range));
  m.fluid.linearise(m.part(ConstVector(m.xs_lin), m.f_range));
  if (m.settings.shape_derivatives == ShapeDerivatives::FiniteDifference)
    m.fluid.residual_unconstrained(m.part(ConstVector(m.xs_lin), m.f_range), m.r_base);
}

// S += a F_ΓΓ: the fluid's interface velocity block, condensed into the structure's rows.
void condense_fluid_block(const FsiProblem::Impl& m, const CsrMatrix& fluid,
                          const CsrMatrix& structure) {
  auto iface = m.interface;
  auto on_gamma = m.interface_node;
  auto fixed = m.structure_fixed;
  const double a = m.a;
  auto frp = fluid.row_ptr;
  auto fcol = fluid.col;
  auto fval = fluid.val;
  auto srp = structure.row_ptr;
  auto scol = structure.col;
  auto sval = structure.val;
  Kokkos::parallel_for(
      "biofsi::fsi_condense", Kokkos::RangePolicy<ExecSpace>(0, iface.extent(0)),
      KOKKOS_LAMBDA(int i) {
        const int n = iface(i);
        for (int c = 0; c < 3; ++c) {
          const int row = 3 * n + c;
          if (fixed(row)) continue;
          const int fr = 4 * n + c;
          for (int k = frp(fr); k < frp(fr + 1); ++k) {
            const int node = fcol(k) / 4, comp = fcol(k) % 4;
            if (comp == 3 || !on_gamma(node) || fixed(3 * node + comp)) continue;
            const int kk = csr_find(srp.data(), scol.data(), row, 3 * node + comp);
            if (kk >= 0) sval(kk) += a * fval(k);
          }
        }
      });
}

void setup_preconditioner(FsiProblem::Impl& m, FsiStats& stats) {
  const ConstVector xl = m.xs_lin;
  const CsrMatrix* fluid_matrix = nullptr;
  {
    ScopedTimer t(stats.seconds_assembly);
    m.structure.assemble(m.part(xl, m.s_range), true);
    fluid_matrix = &m.fluid.assemble_jacobian(m.part(xl, m.f_range), false);
    if (m.a != 0) {
      condense_fluid_block(m, *fluid_matrix, m.structure.matrix());
      m.fluid_coupling.refresh(*fluid_matrix);
    }
    m.force_coupling.refresh(*fluid_matrix);
    csr_eliminate_constrained(*fluid_matrix, m.fluid_fixed);
  }
  ScopedTimer t(stats.seconds_preconditioner_setup);
  m.structure.setup_amg();
  m.fluid.setup_preconditioner_on_matrix();
}

// A block's approximate inverse: a few Krylov iterations on its assembled matrix (cheap CSR
// products) preconditioned by the field's own AMG, to a loose relative tolerance; or, with
// inner_tolerance = 0, the field's preconditioner applied once.
void block_solve(const CsrMatrix& a, const ApplyFn& field_preconditioner, bool spd, double tol,
                 int max_iterations, ConstVector rhs, Vector z, int& iterations, double& seconds) {
  ScopedTimer timer(seconds);
  if (tol <= 0) {
    field_preconditioner(rhs, z);
    ++iterations;
    return;
  }
  KrylovOptions k;
  k.rel_tol = tol;
  k.max_iterations = max_iterations;
  k.restart = max_iterations;
  fill(z, 0);
  const ApplyFn apply = [&a](ConstVector x, Vector y) { csr_multiply(a, x, y); };
  const KrylovResult r = spd ? cg(apply, field_preconditioner, rhs, z, k)
                             : fgmres(apply, field_preconditioner, rhs, z, k);
  iterations += r.iterations;
}

// One block Gauss-Seidel sweep: fluid first (the interface moving as the residual says), then the
// structure under the fluid force that correction causes, then the fluid mesh following the
// structure. Left out: the fluid's dependence on the structure's motion (the interface velocity
// a F_IΓ, partly condensed into the structure block, and the shape derivatives).
void apply_preconditioner(FsiProblem::Impl& m, FsiStats& stats, ConstVector r, Vector z) {
  ScopedTimer t(stats.seconds_preconditioner);
  Vector zs = m.part(z, m.s_range), zf = m.part(z, m.f_range), zg = m.part(z, m.g_range);
  Vector rs = m.part(m.pre_work, m.s_range), rg = m.part(m.pre_work, m.g_range);
  const FsiSettings& st = m.settings;
  const double tol = st.inner_tolerance;
  const int max_it = st.inner_max_iterations;
  block_solve(
      m.fluid.matrix(), [&m](ConstVector x, Vector y) { m.fluid.precondition(x, y); }, false, tol,
      max_it, m.part(r, m.f_range), zf, stats.inner_iterations[1], stats.seconds_inner[1]);
  copy(m.part(r, m.s_range), rs);
  csr_multiply_add(m.force_coupling.m, -1.0, zf, 1.0, rs);
  block_solve(
      m.structure.matrix(), [&m](ConstVector x, Vector y) { m.structure.precondition(x, y); },
      false, tol, max_it, rs, zs, stats.inner_iterations[0], stats.seconds_inner[0]);
  copy(m.part(r, m.g_range), rg);
  csr_multiply_add(m.mesh_coupling.m, -1.0, zs, 1.0, rg);
  block_solve(
      m.mesh_motion.matrix(), [&m](ConstVector x, Vector y) { m.mesh_motion.precondition(x, y); },
      true, tol, max_it, rg, zg, stats.inner_iterations[2], stats.seconds_inner[2]);
}

// Displacement of every node: the structure's d on its nodes, the fluid mesh's g elsewhere (the
// two agree on Γ); both 3 values per node.
std::vector<Point> node_displacement(const FsiProblem::Impl& m, const std::vector<double>& d,
                                     const std::vector<double>& g) {
  std::vector<Point> out(m.nn);
  for (int n = 0; n < m.nn; ++n)
    for (int c = 0; c < 3; ++c) out[n][c] = m.structure_node[n] ? d[3 * n + c] : g[3 * n + c];
  return out;
}

// out.x := reference.x + displacement (out has reference's connectivity).
void place_nodes(const Mesh& reference, const std::vector<Point>& displacement, Mesh& out) {
  for (size_t n = 0; n < displacement.size(); ++n)
    for (int c = 0; c < 3; ++c) out.x[n][c] = reference.x[n][c] + displacement[n][c];
}

// Whether the configuration x keeps every element of the structure and of the fluid mesh the
// right way round (scaled Jacobian > 0 at all corners). Why the line search asks: St. Venant-
// Kirchhoff's energy depends on C = F^T F alone, so an element turned inside out (a reflection)
// costs it nothing, and a long Newton step can land on such a state, a solution of the discrete
// equations that no material reaches. Measured on Turek-Hron FSI2 (refine 1, after the flag's
// swing had reached +-0.07): steps that converged onto a flag element near the tip with scaled
// Jacobian -1, or a fluid cell under the tip at -0.44, with the drag falling from ~250 to 12-66.
bool keeps_elements_upright(FsiProblem::Impl& m, ConstVector x) {
  sync_state(m, x, m.xs, m.structure.displacement_device());
  const auto xs = to_host_vector(m.xs);
  std::vector<double> d = to_host_vector(m.structure.displacement_device());
  for (size_t i = 0; i < d.size(); ++i) d[i] += xs[i];  // d_n + s
  const std::vector<double> g(xs.begin() + 7 * m.nn, xs.end());
  const Mesh& reference = m.structure.mesh();
  if (m.trial_mesh.conn.size() != reference.conn.size()) m.trial_mesh = reference;
  place_nodes(reference, node_displacement(m, d, g), m.trial_mesh);
  for (double q : scaled_jacobians(m.trial_mesh))
    if (!(q > 0)) return false;
  return true;
}

}  // namespace

void FsiProblem::tangent(ConstVector x, ConstVector dx, Vector y) {
  linearise(*impl_, x);
  apply_jacobian(*impl_, stats_, dx, y);
}

void FsiProblem::prepare_step(double dt) {
  Impl& m = *impl_;
  if (!(dt > 0) || !std::isfinite(dt))
    throw SolveError("fsi", "prepare", "time step must be positive and finite");
  m.structure.begin_step(dt);
  m.fluid.begin_step(dt);
  m.inv_dt = 1.0 / dt;
  m.configuration_weight = m.fluid.settings().theta;
  if (m.structure.settings().quasi_static) {
    m.a = 1.0 / dt;
    fill(m.b, 0);
  } else {
    const double theta = m.structure.settings().theta;
    m.a = m.structure.velocity_coefficient();
    axpby(-(1 - theta) / theta, m.structure.velocity_device(), 0.0, m.b);
  }
  copy(m.g_now, m.g_old);
  copy(m.structure.increment(), m.part(x_, m.s_range));
  copy(m.fluid.state(), m.part(x_, m.f_range));
  // The fluid mesh predicted with its last velocity, as the structure is with its own (the
  // structure's predictor moves Γ by dt v_n): holding the interior at g_n squeezed the cells next
  // to the flag of Turek-Hron FSI2/FSI3 flat in the first iterate once Γ moved by about their
  // thickness per step (9 mm), and those steps were cut or jumped to an unphysical state.
  copy(m.g_now, m.part(x_, m.g_range));
  axpy(dt, m.grid_velocity, m.part(x_, m.g_range));
}

void FsiProblem::prepare_steady() {
  Impl& m = *impl_;
  if (!m.structure.settings().quasi_static)
    throw std::invalid_argument("fsi: a steady coupled solve needs a quasi-static structure");
  m.structure.begin_step(0.0);
  m.fluid.begin_steady();
  m.inv_dt = 0;
  m.configuration_weight = 1;
  m.a = 0;
  fill(m.b, 0);
  copy(m.g_now, m.g_old);
  copy(m.structure.increment(), m.part(x_, m.s_range));
  copy(m.fluid.state(), m.part(x_, m.f_range));
  copy(m.g_now, m.part(x_, m.g_range));
}

namespace {

// The residual of each field is a sum of terms of size ~ |J_kk x_k| that cancel at the solution;
// their round-off (~eps of their size, times the number of element contributions summed) is a
// floor below which no Newton iteration can go. Measured on the fluid mesh, whose Jacobian-based
// stiffening scales its entries by 1/det J ~ 1e4 on small elements: it stagnates at ~1e-14 where
// its relative tolerance asked for 4e-16. 1e4 eps, as the structure field uses. Taken at the
// iterate x being tested, with the last assembled diagonals: taken at the previous linearisation
// point instead, the first step of a run from rest had floors of zero for its first test (the
// state before it is zero), and Newton then chased the fluid mesh's round-off (2.7e-7 on
// Turek-Hron FSI2 refine 1) through 188 Krylov iterations.
std::array<double, 3> roundoff_floors(const FsiProblem::Impl& m, ConstVector state) {
  const CsrMatrix* matrices[3] = {&m.structure.matrix(), &m.fluid.matrix(),
                                  &m.mesh_motion.matrix()};
  const Range ranges[3] = {m.s_range, m.f_range, m.g_range};
  std::array<double, 3> floors{};
  for (int i = 0; i < 3; ++i) {
    Vector d("biofsi::fsi_diag", matrices[i]->n_rows);
    csr_diagonal(*matrices[i], d);
    const ConstVector x = m.part(state, ranges[i]);
    double sum = 0;
    Kokkos::parallel_reduce(
        "biofsi::fsi_floor", Kokkos::RangePolicy<ExecSpace>(0, d.extent(0)),
        KOKKOS_LAMBDA(int k, double& acc) {
          const double t = d(k) * x(k);
          acc += t * t;
        },
        sum);
    floors[i] = 1e4 * std::numeric_limits<double>::epsilon() * std::sqrt(sum);
  }
  return floors;
}

}  // namespace

// Newton on the condensed system with each field's residual measured in its own scale: the
// linear system is solved for the residual scaled field by field to unit norm (so one field's
// units cannot hide another's error), the line search and the forcing term use that scaled norm;
// each field's tolerance is relative to the largest residual it had in the solve. A trial that
// would turn a fluid element inside out is not admissible.
NewtonResult FsiProblem::solve() {
  Impl& m = *impl_;
  ScopedTimer timer(stats_.seconds_solve);
  const FsiSettings& st = m.settings;
  NewtonSystem sys;
  sys.residual = [this](ConstVector x, Vector r) { residual(x, r); };
  sys.tangent = [this, &m](ConstVector, ConstVector dx, Vector y) {
    apply_jacobian(m, stats_, dx, y);
  };
  sys.linearise = [&m](ConstVector x) { linearise(m, x); };
  sys.setup_preconditioner = [this, &m](ConstVector) { setup_preconditioner(m, stats_); };
  sys.reuse = &m.reuse;
  m.reuse.require({m.a, m.inv_dt});
  sys.precondition = [this, &m](ConstVector r, Vector z) { apply_preconditioner(m, stats_, r, z); };
  sys.blocks = {m.s_range, m.f_range, m.g_range};
  sys.roundoff_floors = [&m](ConstVector x) {
    const auto f = roundoff_floors(m, x);
    return std::vector<Real>(f.begin(), f.end());
  };
  sys.admissible = [&m](ConstVector x) { return keeps_elements_upright(m, x); };
  NewtonOptions opt;  // Eisenstat-Walker constants; the bounds are the coupling's own
  opt.rel_tol = st.rel_tol;
  opt.abs_tol = st.abs_tol;
  opt.max_iterations = st.max_iterations;
  opt.eta_max = st.eta_max;
  opt.max_backtracks = 10;
  opt.krylov = KrylovOptions{};
  opt.krylov.max_iterations = st.krylov_max_iterations;
  opt.krylov.restart = st.krylov_restart;
  opt.line_search = LineSearch::BlockMerit;
  opt.scale_blocks = true;
  opt.tolerance_from_largest = true;
  // The loosest solve with which every field still meets its tolerance, with a safety factor 10.
  opt.forcing_floor_factor = 0.1;
  opt.floor_includes_roundoff = true;
  // Steady solves start far from their solution (a flow from rest, or the last growth step's),
  // where the Jacobian changes too much between Newton steps: measured on case (c)'s full mesh,
  // 10 growth steps, an aged preconditioner halved the set-ups (13 for 25 Newton steps) but
  // nearly doubled the outer Krylov iterations (256 against 147) and cost more than it saved.
  opt.reuse_preconditioner = st.reuse_preconditioner && m.inv_dt != 0;
  NewtonResult res = newton_solve(sys, x_, opt);
  stats_.preconditioner_setups = m.reuse.setups();
  stats_.preconditioner_reuses = m.reuse.reuses();
  stats_.last_krylov = res.krylov_history;
  stats_.last_residuals.clear();
  for (const auto& n : res.block_history) stats_.last_residuals.push_back({n[0], n[1], n[2]});
  ++stats_.solves;
  stats_.newton_iterations += res.iterations;
  stats_.krylov_iterations += res.krylov_iterations;
  return res;
}

namespace {

std::string failure_report(const NewtonResult& r, const FsiStats& s) {
  std::ostringstream why;
  why << "Newton " << r.reason << " after " << r.iterations
      << " iterations; residual history (structure, fluid, fluid mesh):";
  for (const auto& n : s.last_residuals) why << " (" << n[0] << ", " << n[1] << ", " << n[2] << ")";
  return why.str();
}

}  // namespace

void FsiProblem::commit(double dt) {
  Impl& m = *impl_;
  sync_state(m, x_, m.xs, m.structure.displacement_device());
  copy(m.part(m.xs, m.s_range), m.structure.increment());
  m.structure.end_step(dt);
  copy(m.part(m.xs, m.f_range), m.fluid.state());
  m.fluid.end_step(dt);
  copy(m.part(m.xs, m.g_range), m.g_now);
  // The host coordinates (output, boundary data) at t_{n+1}; the fluid's operator stays on the
  // configuration it was solved on, so tractions taken after the step are the solve's.
  const double w = m.configuration_weight;
  m.configuration_weight = 1;
  move_fluid_mesh(m, m.g_now);
  m.fluid.sync_host_coordinates();
  m.configuration_weight = w;
  move_fluid_mesh(m, m.g_now);
  m.configuration_weight = 1;
}

void FsiProblem::invalidate_preconditioner() { impl_->reuse.invalidate(); }

void FsiProblem::restore() {
  Impl& m = *impl_;
  m.reuse.invalidate();  // a failed solve: the next one starts from a fresh preconditioner
  m.fluid.restore_old_state();
  m.configuration_weight = 1;
  copy(m.g_old, m.g_now);
  fill(m.grid_velocity, 0);
  move_fluid_mesh(m, m.g_now);
}

NewtonResult FsiProblem::step_once(double dt, const std::string& label) {
  prepare_step(dt);
  const NewtonResult r = solve();
  if (!r.converged) {
    restore();
    throw SolveError("fsi", label, failure_report(r, stats_));
  }
  commit(dt);
  return r;
}

NewtonResult FsiProblem::step(double dt, const std::string& label) {
  Impl& m = *impl_;
  try {
    return step_once(dt, label);
  } catch (const SolveError& first) {
    // Cut the step: a failed solve left the fields at the step's start; a failed sub-step after
    // committed ones needs that start back.
    const auto d0 = m.structure.displacement(), v0 = m.structure.velocity();
    const double ts = m.structure.time(), tf = m.fluid.time();
    const auto f0 = m.fluid.solution_host();
    Vector g0("biofsi::fsi_g0", 3 * n_nodes_);
    copy(m.g_now, g0);
    return retry_in_sub_steps(
        first, "fsi", label, dt, m.settings.max_step_cuts,
        [&](double h, const std::string& l) { return step_once(h, l); },
        [&] {
          m.structure.set_state(d0, v0, ts);
          m.fluid.set_solution(f0);
          m.fluid.set_time(tf);
          copy(g0, m.g_now);
          copy(g0, m.g_old);
          restore();
        },
        stats_.cut_steps);
  }
}

NewtonResult FsiProblem::solve_steady(const std::string& label) {
  // A dynamic structure is solved at equilibrium here and switched back, also on a failure.
  struct EquilibriumScope {
    StructureField& structure;
    bool was_quasi_static;
    explicit EquilibriumScope(StructureField& s)
        : structure(s), was_quasi_static(s.settings().quasi_static) {
      s.set_quasi_static(true);
    }
    ~EquilibriumScope() { structure.set_quasi_static(was_quasi_static); }
  } equilibrium(impl_->structure);
  prepare_steady();
  const NewtonResult r = solve();
  if (!r.converged) {
    restore();
    throw SolveError("fsi", label, failure_report(r, stats_));
  }
  commit(0.0);
  fill(impl_->grid_velocity, 0);
  return r;
}

std::vector<char> FsiProblem::free_dofs() const {
  const Impl& m = *impl_;
  const auto s = to_host(m.structure_fixed), f = to_host(m.fluid_fixed),
             g = to_host(m.mesh_eliminated);
  std::vector<char> out;
  for (char c : s) out.push_back(!c);
  for (char c : f) out.push_back(!c);
  for (char c : g) out.push_back(!c);
  return out;
}

std::vector<Point> FsiProblem::displacement() const {
  const Impl& m = *impl_;
  return node_displacement(m, to_host_vector(m.structure.displacement_device()),
                           to_host_vector(m.g_now));
}

Mesh FsiProblem::current_mesh() const {
  const Mesh& reference = impl_->structure.mesh();
  Mesh mesh = reference;
  place_nodes(reference, displacement(), mesh);
  return mesh;
}

std::vector<Point> FsiProblem::mesh_displacement() const {
  const auto g = to_host_vector(impl_->g_now);
  std::vector<Point> out(n_nodes_);
  for (int n = 0; n < n_nodes_; ++n) out[n] = {g[3 * n], g[3 * n + 1], g[3 * n + 2]};
  return out;
}

namespace {

std::vector<double> flatten(const std::vector<Point>& v) {
  std::vector<double> flat(3 * v.size());
  for (size_t n = 0; n < v.size(); ++n)
    for (int c = 0; c < 3; ++c) flat[3 * n + c] = v[n][c];
  return flat;
}

}  // namespace

void FsiProblem::set_mesh_displacement(const std::vector<Point>& g,
                                       const std::vector<Point>& grid_velocity) {
  Impl& m = *impl_;
  if (static_cast<int>(g.size()) != n_nodes_ ||
      (!grid_velocity.empty() && static_cast<int>(grid_velocity.size()) != n_nodes_))
    throw std::invalid_argument("fsi: mesh displacement or grid velocity has the wrong size");
  copy(to_device_vector(flatten(g), "biofsi::fsi_g_in"), m.g_now);
  copy(m.g_now, m.g_old);
  move_fluid_mesh(m, m.g_now);  // g = g_old: no grid velocity
  if (!grid_velocity.empty()) {
    copy(to_device_vector(flatten(grid_velocity), "biofsi::fsi_w_in"), m.grid_velocity);
    m.fluid.set_geometry(m.x_work, m.grid_velocity);
  }
  m.fluid.sync_host_coordinates();
}

std::vector<Point> FsiProblem::grid_velocity() const {
  const auto v = to_host_vector(impl_->grid_velocity);
  std::vector<Point> out(n_nodes_);
  for (int n = 0; n < n_nodes_; ++n) out[n] = {v[3 * n], v[3 * n + 1], v[3 * n + 2]};
  return out;
}

}  // namespace biofsi
