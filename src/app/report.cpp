#include "app/report.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <set>
#include <sstream>

namespace biofsi {

Progress::Progress(int total) : total_(total), tty_(isatty(STDOUT_FILENO)), start_(Clock::now()) {}

void Progress::update(int step, double time, double change) {
  const double elapsed = seconds();
  const double left = step > 0 ? elapsed / step * (total_ - step) : 0.0;
  std::ostringstream s;
  s << "step " << step << "/" << total_ << "  t = " << std::setprecision(6) << time << "  change "
    << std::scientific << std::setprecision(2) << change << std::fixed << std::setprecision(1)
    << "  elapsed " << elapsed << " s  left ~" << left << " s";
  if (tty_) {
    std::cout << "\r" << s.str() << "   " << std::flush;
  } else if (elapsed - last_log_ >= 5.0 || step == total_) {
    std::cout << s.str() << "\n";
    last_log_ = elapsed;
  }
}

void Progress::done() {
  if (tty_) std::cout << "\n";
}

namespace {

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

}  // namespace

void print_active_fields(const Scene& scene) {
  std::cout
      << "active fields (derived from the scene):\n"
      << "  scalar transport: " << (scene.scalar.enabled ? "on" : "off (disabled in scene)") << "\n"
      << "  fluid:     "
      << (scene.fluid.enabled
              ? "on (" +
                    std::string(scene.fluid.mode == FlowMode::Steady ? "steady" : "transient") +
                    " incompressible Navier-Stokes on blocks " + join(scene.fluid.settings.blocks) +
                    "; other blocks " +
                    (scene.structure.enabled ? std::string("elastic")
                                             : std::string("held at rest")) +
                    (scene.scalar.enabled ? "; convects the scalar" : "") +
                    (scene.growth.enabled && scene.growth.settings.k2 > 0
                         ? ", wall shear erodes the biofilm)"
                         : ")")
              : std::string("off (the scene has no fields.fluid section)"))
      << "\n"
      << "  structure: "
      << (scene.structure.enabled
              ? "on (" +
                    std::string(scene.structure.settings.quasi_static ? "quasi-static"
                                                                      : "dynamic") +
                    " finite-strain elasticity on blocks " + join(scene.structure.settings.blocks) +
                    (scene.fluid.enabled
                         ? ", coupled to the fluid by monolithic FSI on '" + scene.fsi.interface +
                               "'; its motion moves the fluid mesh and the transport mesh)"
                         : std::string(", alone under its body force and boundary data)"))
              : std::string("off (the scene has no fields.structure section: the biofilm "
                            "is rigid)"))
      << "\n"
      << "  growth:    "
      << (scene.growth.enabled
              ? "on (" + std::to_string(scene.growth.steps) + " growth steps of " +
                    std::to_string(scene.growth.settings.dt_bio) + " ms, interface '" +
                    scene.growth.settings.interface_set + "')"
              : std::string("off (the scene has no growth section, or it is disabled)"))
      << "\n";
  if (scene.growth.enabled)
    std::cout << "  mesh motion: on (pseudo-elastic, moves the biofilm and fluid meshes in each "
                 "growth step)\n";
}

int flux_block(const Mesh& mesh, const std::string& set) {
  std::set<int> blocks;
  for (const auto& f : mesh.face_sets.at(set)) blocks.insert(mesh.element_block[f.element]);
  if (mesh.block_names.size() < 2 || blocks.empty()) return -1;
  if (blocks.size() == 1) return *blocks.begin();
  if (blocks.size() > 2 || !lists_both_sides(mesh, set)) return -1;
  for (int b : blocks)
    if (set.rfind(mesh.block_names[b] + "_", 0) == 0) return b;
  return *blocks.begin();
}

namespace {

// Average iterations per Newton step, the solver-cost measure that stays comparable across
// scenes and meshes (the deterministic counts, not the noisy times).
std::string per_newton_step(long iterations, long newton_steps) {
  std::ostringstream o;
  o << std::fixed << std::setprecision(1) << double(iterations) / std::max(1L, newton_steps);
  return o.str();
}

}  // namespace

std::string format_range(const std::vector<QualityRange>& q, const Mesh& mesh) {
  std::ostringstream o;
  for (size_t b = 0; b < q.size(); ++b)
    o << (b ? ", " : "") << mesh.block_names[b] << " [" << q[b].min << ", " << q[b].max << "]";
  return o.str();
}

void write_flux_tables(const Simulation& sim, const std::filesystem::path& directory) {
  for (const auto& set : sim.scene.output.flux_boundaries) {
    const BoundaryFlux f = sim.scalar.boundary_flux(set, flux_block(sim.mesh, set));
    std::ostringstream out;
    out << "x,y,z,nodal_flux,lumped_area,flux_density\n" << std::setprecision(12);
    for (size_t i = 0; i < f.nodes.size(); ++i) {
      const Point& p = sim.mesh.x[f.nodes[i]];
      out << p[0] << ',' << p[1] << ',' << p[2] << ',' << f.nodal_flux[i] << ',' << f.lumped_area[i]
          << ',' << f.density[i] << '\n';
    }
    write_text_file((directory / ("flux_" + set + ".csv")).string(), out.str());
  }
}

std::string summarise(const Simulation& sim, const RunTotals& totals, double seconds) {
  const TransportStats& s = sim.scalar.stats();
  std::ostringstream o;
  o << std::setprecision(6);
  o << "summary\n"
    << "  scene: " << sim.scene.file << "\n";
  if (!sim.scene.fidelity.level.empty())
    o << "  fidelity: " << sim.scene.fidelity.level << " (mesh resolution x"
      << sim.scene.fidelity.mesh_factor << ")\n";
  o << "  nodes " << sim.mesh.n_nodes() << ", elements " << sim.mesh.n_elements() << "\n"
    << "  scalar: " << s.steps << " solves, " << s.newton_iterations << " Newton and "
    << s.krylov_iterations << " Krylov iterations, " << s.preconditioner_setups
    << " preconditioner set-ups, " << s.cut_steps << " time steps cut into sub-steps, "
    << s.continued_steps << " solved by continuation in Monod's K, " << s.pseudo_steps
    << " pseudo-time steps\n";
  if (sim.fluid && !sim.fsi) {
    const FluidStats& f = sim.fluid->stats();
    o << "  fluid: " << f.steps << " solves, " << f.newton_iterations << " Newton and "
      << f.krylov_iterations << " Krylov iterations, " << f.preconditioner_setups
      << " preconditioner set-ups, " << f.cut_steps << " time steps cut, " << f.pseudo_steps
      << " pseudo-time steps; per Newton step "
      << per_newton_step(f.krylov_iterations, f.newton_iterations) << " Krylov\n";
  }
  if (sim.structure && !sim.fsi) {
    const StructureStats& f = sim.structure->stats();
    o << "  structure: " << f.steps << " steps, " << f.newton_iterations << " Newton and "
      << f.krylov_iterations << " Krylov iterations, " << f.amg_setups << " AMG set-ups, "
      << f.cut_steps << " time steps cut\n";
  }
  if (sim.fsi) {
    const FsiStats& f = sim.fsi->stats();
    double d_max = 0;
    for (const auto& p : sim.structure->displacement())
      d_max = std::max(d_max, std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]));
    o << "  fsi: " << f.solves << " monolithic solves, " << f.newton_iterations << " Newton and "
      << f.krylov_iterations << " outer Krylov iterations (inner: structure "
      << f.inner_iterations[0] << ", fluid " << f.inner_iterations[1] << ", fluid mesh "
      << f.inner_iterations[2] << "), " << f.cut_steps << " time steps cut; per Newton step "
      << per_newton_step(f.krylov_iterations, f.newton_iterations) << " outer Krylov (inner "
      << "fluid " << per_newton_step(f.inner_iterations[1], f.newton_iterations) << "); "
      << f.preconditioner_setups << " preconditioner set-ups, " << f.preconditioner_reuses
      << " reused; max structure "
      << "displacement " << d_max << ", smallest scaled Jacobian of the deformed mesh "
      << sim.min_deformed_quality << "\n";
  }
  o << "  time [s]: total " << seconds << "; scalar " << s.seconds_solve << " (residual "
    << s.seconds_residual << ", tangent " << s.seconds_tangent << ", linearisation "
    << s.seconds_linearise << ", assembly " << s.seconds_assembly << ", preconditioner set-up "
    << s.seconds_preconditioner_setup << ")";
  if (sim.fsi) {
    const FsiStats& f = sim.fsi->stats();
    // Shape derivatives are part of the Jacobian action; the block Krylov solves are the
    // preconditioner's (its remainder: the coupling-block products).
    o << "; fsi " << f.seconds_solve << " (residual " << f.seconds_residual << ", jacobian action "
      << f.seconds_tangent << ", shape derivatives " << f.seconds_shape << ", assembly "
      << f.seconds_assembly << ", preconditioner set-up " << f.seconds_preconditioner_setup
      << ", preconditioner " << f.seconds_preconditioner << ", block Krylov structure "
      << f.seconds_inner[0] << ", block Krylov fluid " << f.seconds_inner[1]
      << ", block Krylov fluid mesh " << f.seconds_inner[2] << ")";
  } else if (sim.structure) {
    const StructureStats& f = sim.structure->stats();
    o << "; structure " << f.seconds_solve << " (residual " << f.seconds_residual << ", tangent "
      << f.seconds_tangent << ", linearisation " << f.seconds_linearise << ", assembly "
      << f.seconds_assembly << ", AMG set-up " << f.seconds_amg_setup << ")";
  } else if (sim.fluid) {
    const FluidStats& f = sim.fluid->stats();
    o << "; fluid " << f.seconds_solve << " (residual " << f.seconds_residual << ", tangent "
      << f.seconds_tangent << ", linearisation " << f.seconds_linearise << ", assembly "
      << f.seconds_assembly << ", preconditioner set-up " << f.seconds_preconditioner_setup << ")";
  }
  if (sim.scene.growth.enabled)
    o << "; growth + mesh motion " << totals.seconds_growth << " (" << totals.steps << " steps, "
      << totals.mesh_krylov_iterations << " CG iterations, " << totals.mesh_amg_setups
      << " AMG set-ups)";
  o << "\n";
  if (sim.scene.growth.enabled)
    o << "  mesh quality (scaled Jacobian) over the run: [" << totals.min_quality << ", "
      << totals.max_quality << "]\n"
      << "  interface '" << sim.scene.growth.settings.interface_set << "' moved up to "
      << totals.interface_moved << " mm over the run (at most " << totals.largest_interface_step
      << " mm in a growth step)\n";
  if (sim.scene.scalar.enabled)
    o << "  final time " << sim.scalar.time() << ", integral of phi " << sim.scalar.integral()
      << ", consumption rate " << sim.scalar.reaction_integral() << "\n";
  for (const auto& set : sim.scene.output.force_boundaries) {
    const Point f = sim.fluid->force(set);
    o << "  fluid force on '" << set << "': (" << f[0] << ", " << f[1] << ", " << f[2] << ")\n";
  }
  for (const auto& set : sim.scene.output.flux_boundaries) {
    const int block = flux_block(sim.mesh, set);
    const BoundaryFlux f = sim.scalar.boundary_flux(set, block);
    const auto [lo, hi] = std::minmax_element(f.density.begin(), f.density.end());
    o << "  flux through '" << set << "' into "
      << (block < 0 ? std::string("the domain") : "block '" + sim.mesh.block_names[block] + "'")
      << ": total " << f.total << ", density min " << *lo << " max " << *hi << "\n";
  }
  return o.str();
}

Series::Series(const Simulation& sim) : sim_(sim) {
  const OutputSpec& o = sim.scene.output;
  for (size_t i = 0; i < o.probes.size(); ++i) probes_.push_back(probe_nodes(o.probes[i], i));
}

void Series::open(const std::filesystem::path& out) {
  const OutputSpec& o = sim_.scene.output;
  if (o.probes.empty() && o.force_boundaries.empty()) return;
  file_ = TextLog((out / "series.csv").string());
  std::ostringstream header;
  header << "step,time";
  for (const auto& set : o.force_boundaries)
    for (const char* c : {"x", "y", "z"}) header << ",force_" << set << "_" << c;
  for (const auto& p : o.probes)
    if (p.quantity == ProbeSpec::Quantity::Pressure)
      header << "," << p.name << "_pressure";
    else
      for (const char* c : {"x", "y", "z"})
        header << "," << p.name
               << (p.quantity == ProbeSpec::Quantity::Velocity ? "_velocity_" : "_displacement_")
               << c;
  file_.append(header.str() + "\n");
}

std::vector<int> Series::probe_nodes(const ProbeSpec& p, size_t index) const {
  std::vector<int> nodes;
  for (int n = 0; n < sim_.mesh.n_nodes(); ++n) {
    bool at = true;
    for (size_t d = 0; d < p.point.size(); ++d)
      at = at && std::abs(sim_.mesh.x[n][d] - p.point[d]) <= 1e-9 * (1 + std::abs(p.point[d]));
    if (at) nodes.push_back(n);
  }
  if (nodes.empty()) {
    std::ostringstream msg;
    msg << sim_.scene.file << ":" << p.line << ": output.probes[" << index
        << "].point: no mesh node at (";
    for (size_t d = 0; d < p.point.size(); ++d) msg << (d ? ", " : "") << p.point[d];
    msg << "); expected a point that is a node of the mesh (or, with 2 coordinates, nodes "
           "through its thickness)";
    throw SceneError(msg.str());
  }
  return nodes;
}

void Series::record(int step, double time) {
  if (!file_.is_open()) return;
  std::ostringstream row;
  row << std::setprecision(12) << step << "," << time;
  for (const auto& set : sim_.scene.output.force_boundaries) {
    const Point f = sim_.fluid->force(set);
    row << "," << f[0] << "," << f[1] << "," << f[2];
  }
  std::vector<Point> displacement, velocity;
  std::vector<double> pressure;
  for (size_t i = 0; i < probes_.size(); ++i) {
    const auto quantity = sim_.scene.output.probes[i].quantity;
    const auto& nodes = probes_[i];
    Point mean{0, 0, 0};
    for (int n : nodes) {
      if (quantity == ProbeSpec::Quantity::Pressure) {
        if (pressure.empty()) pressure = sim_.fluid->pressure();
        mean[0] += pressure[n] / nodes.size();
        continue;
      }
      std::vector<Point>& v = quantity == ProbeSpec::Quantity::Velocity ? velocity : displacement;
      if (v.empty())
        v = quantity == ProbeSpec::Quantity::Velocity ? sim_.fluid->velocity()
                                                      : sim_.displacement();
      for (int d = 0; d < 3; ++d) mean[d] += v[n][d] / nodes.size();
    }
    if (quantity == ProbeSpec::Quantity::Pressure)
      row << "," << mean[0];
    else
      row << "," << mean[0] << "," << mean[1] << "," << mean[2];
  }
  row << "\n";
  file_.append(row.str());
}

}  // namespace biofsi
