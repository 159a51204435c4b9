#include "app/run.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>

#include "io/expression.hpp"
#include "io/output.hpp"
#include "io/scene.hpp"
#include "scalar/transport.hpp"

namespace biofsi {

namespace {

using Clock = std::chrono::steady_clock;

SpaceTimeFunction to_function(const std::string& text) {
  auto e = std::make_shared<Expression>(text);
  return [e](const Point& x, double t) { return (*e)(x[0], x[1], x[2], t); };
}

TransportSettings transport_settings(const Scene& scene, const Mesh& mesh) {
  TransportSettings s;
  for (size_t b = 0; b < mesh.block_names.size(); ++b) {
    const MaterialSpec& m = scene.materials.at(mesh.block_names[b]);
    s.coefficients.diffusivity[b] = m.diffusivity;
    s.coefficients.monod_rate[b] = m.monod_rate;
    s.coefficients.monod_half_saturation[b] = m.monod_half_saturation;
  }
  s.supg = scene.scalar.supg;
  s.theta = scene.time.mode == TimeMode::Steady ? 1.0 : scene.time.theta;
  s.scatter = scene.solver.scatter == "atomic" ? Scatter::Atomic : Scatter::Colored;
  s.newton.rel_tol = scene.solver.newton_rel_tol;
  s.newton.abs_tol = scene.solver.newton_abs_tol;
  s.newton.max_iterations = scene.solver.newton_max_iterations;
  s.newton.krylov.max_iterations = scene.solver.linear_max_iterations;
  s.newton.krylov.restart = scene.solver.linear_restart;
  s.newton.eta_max = std::max(scene.solver.linear_rel_tol, s.newton.eta_min);
  return s;
}

std::vector<ScalarBoundaryCondition> transport_conditions(const Scene& scene) {
  std::vector<ScalarBoundaryCondition> out;
  for (const auto& bc : scene.scalar.boundary_conditions) {
    ScalarBoundaryCondition c;
    c.set = bc.boundary;
    c.kind = bc.type == BcType::Dirichlet ? ScalarBcKind::Dirichlet
             : bc.type == BcType::Neumann ? ScalarBcKind::Flux
                                          : ScalarBcKind::Robin;
    c.value = to_function(bc.value);
    c.coefficient = bc.coefficient;
    out.push_back(std::move(c));
  }
  return out;
}

// Terminal: one updating line. Otherwise: a plain log line at most every few seconds.
class Progress {
 public:
  Progress(int total) : total_(total), tty_(isatty(STDOUT_FILENO)), start_(Clock::now()) {}
  void update(int step, double time, double change) {
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
  void done() {
    if (tty_) std::cout << "\n";
  }
  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  int total_;
  bool tty_;
  Clock::time_point start_;
  double last_log_ = -1e300;
};

void print_active_fields(const Scene& scene) {
  std::cout << "active fields (derived from the scene):\n"
            << "  scalar transport: " << (scene.scalar.enabled ? "on" : "off (disabled in scene)")
            << "\n"
            << "  fluid:     off (the scene has no inflow, moving wall or body force)\n"
            << "  structure: off (the scene has no load on the biofilm)\n"
            << "  growth:    off (the scene has no growth section)\n";
}

// Relative change between two solutions: max|a - b| / max(max|a|, tiny).
double relative_change(const std::vector<double>& a, const std::vector<double>& b) {
  double diff = 0, scale = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(a[i]));
  }
  return diff / std::max(scale, 1e-300);
}

// Blocks that own the faces of a set: one block gives the flux into that block (an interface
// seen from its lower side), several give the flux into the whole domain.
int flux_block(const Mesh& mesh, const std::string& set) {
  std::set<int> blocks;
  for (const auto& f : mesh.face_sets.at(set)) blocks.insert(mesh.element_block[f.element]);
  return blocks.size() == 1 && mesh.block_names.size() > 1 ? *blocks.begin() : -1;
}

void write_state(XdmfWriter& writer, int step, const TransportField& field) {
  writer.write(step, field.time(), field.mesh(), {{"phi", 1, false, field.solution_host()}});
}

std::string summarise(const Scene& scene, const TransportField& field, double wall) {
  const TransportStats& s = field.stats();
  std::ostringstream o;
  o << std::setprecision(6);
  o << "summary\n"
    << "  scene: " << scene.file << "\n"
    << "  nodes " << field.mesh().n_nodes() << ", elements " << field.mesh().n_elements() << "\n"
    << "  scalar: " << s.steps << " solves, " << s.newton_iterations << " Newton and "
    << s.krylov_iterations << " Krylov iterations, " << s.amg_setups << " AMG set-ups\n"
    << "  time [s]: total " << wall << ", scalar solve " << s.seconds_solve << " (residual "
    << s.seconds_residual << ", tangent " << s.seconds_tangent << ", assembly "
    << s.seconds_assembly << ", AMG set-up " << s.seconds_amg_setup << ")\n"
    << "  final time " << field.time() << ", integral of phi " << field.integral()
    << ", consumption rate " << field.reaction_integral() << "\n";
  for (const auto& set : scene.output.flux_boundaries) {
    const int block = flux_block(field.mesh(), set);
    const BoundaryFlux f = field.boundary_flux(set, block);
    const auto [lo, hi] = std::minmax_element(f.density.begin(), f.density.end());
    o << "  flux through '" << set << "' into "
      << (block < 0 ? std::string("the domain") : "block '" + field.mesh().block_names[block] + "'")
      << ": total " << f.total << ", density min " << *lo << " max " << *hi << "\n";
  }
  return o.str();
}

void write_flux_tables(const Scene& scene, const TransportField& field,
                       const std::filesystem::path& dir) {
  for (const auto& set : scene.output.flux_boundaries) {
    const BoundaryFlux f = field.boundary_flux(set, flux_block(field.mesh(), set));
    const auto path = dir / ("flux_" + set + ".csv");
    std::ofstream out(path.string() + ".tmp");
    out << "x,y,z,nodal_flux,lumped_area,flux_density\n" << std::setprecision(12);
    for (size_t i = 0; i < f.nodes.size(); ++i) {
      const Point& p = field.mesh().x[f.nodes[i]];
      out << p[0] << ',' << p[1] << ',' << p[2] << ',' << f.nodal_flux[i] << ',' << f.lumped_area[i]
          << ',' << f.density[i] << '\n';
    }
    out.close();
    std::filesystem::rename(path.string() + ".tmp", path);
  }
}

int run_transport(const Scene& scene, const std::filesystem::path& out_dir, bool overwrite) {
  const auto wall_start = Clock::now();
  const Mesh mesh = make_box_mesh(scene.box);
  std::cout << "mesh: " << mesh.n_nodes() << " nodes, " << mesh.n_elements() << " hex8 elements, "
            << mesh.block_names.size() << " blocks\n";
  TransportField field(mesh, transport_settings(scene, mesh), transport_conditions(scene));
  const SpaceTimeFunction initial = to_function(scene.scalar.initial);
  field.set_initial(initial, 0.0);
  {
    std::array<SpaceTimeFunction, 3> v;
    for (int d = 0; d < 3; ++d) v[d] = to_function(scene.scalar.velocity[d]);
    std::vector<Point> c(mesh.n_nodes());
    for (int n = 0; n < mesh.n_nodes(); ++n)
      for (int d = 0; d < 3; ++d) c[n][d] = v[d](mesh.x[n], 0.0);
    field.set_convective_velocity(c);
  }
  XdmfWriter writer(out_dir.string(), "scalar", overwrite);
  write_state(writer, 0, field);

  int last_written = 0, step = 0;
  try {
    if (scene.time.mode == TimeMode::Steady) {
      const NewtonResult r = field.solve_steady("steady solve");
      std::cout << "steady solve: " << r.iterations << " Newton iterations, " << r.krylov_iterations
                << " Krylov iterations, residual " << r.residual_history.back() << "\n";
      step = 1;
      write_state(writer, step, field);
      last_written = step;
    } else {
      Progress progress(scene.time.steps);
      std::vector<double> previous = field.solution_host();
      for (step = 1; step <= scene.time.steps; ++step) {
        std::ostringstream label;
        label << "step " << step << " (t = " << field.time() + scene.time.dt << ")";
        field.step(scene.time.dt, label.str());
        const std::vector<double> now = field.solution_host();
        const double change = relative_change(now, previous);
        previous = now;
        progress.update(step, field.time(), change);
        const bool stationary =
            scene.time.steady_tolerance > 0 && change < scene.time.steady_tolerance;
        if (step % scene.output.every == 0 || step == scene.time.steps || stationary) {
          write_state(writer, step, field);
          last_written = step;
        }
        if (stationary) {
          progress.done();
          std::cout << "stationary after " << step << " steps: relative change " << change
                    << " < steady_tolerance " << scene.time.steady_tolerance << "\n";
          break;
        }
        if (step == scene.time.steps) {
          progress.done();
          std::cout << "reached the last step (" << step << ")";
          if (scene.time.steady_tolerance > 0)
            std::cout << " without meeting steady_tolerance " << scene.time.steady_tolerance
                      << " (last change " << change << ")";
          std::cout << "\n";
        }
      }
    }
  } catch (const SolveError& e) {
    std::cout << "\n";
    std::cerr << "biofsi: solve failed: field '" << e.field() << "', " << e.step() << ": "
              << e.why() << "\n";
    if (last_written != step) {
      write_state(writer, step, field);  // the field restored its last valid solution
      std::cerr << "biofsi: wrote the last valid state (t = " << field.time() << ") to "
                << writer.index_path() << "\n";
    }
    return 3;
  }
  write_flux_tables(scene, field, out_dir);
  const double wall = std::chrono::duration<double>(Clock::now() - wall_start).count();
  const std::string summary = summarise(scene, field, wall);
  std::cout << summary;
  std::ofstream(out_dir / "summary.txt") << summary;
  std::cout << "results: " << writer.index_path() << " (open in ParaView)\n";
  return 0;
}

}  // namespace

int run_scene(const RunOptions& options) {
  Scene scene;
  try {
    scene = load_scene(options.scene_path, options.overrides);
  } catch (const SceneError& e) {
    std::cerr << "biofsi: " << e.what() << "\n";
    return 1;
  }
  const std::filesystem::path out_dir =
      options.out_dir.empty() ? scene.output.directory : options.out_dir;
  std::cout << "biofsi: scene " << scene.file << ", output " << out_dir.string() << "\n";
  print_active_fields(scene);
  if (!scene.scalar.enabled) {
    std::cout << "nothing to solve: every field is off\n";
    return 0;
  }
  try {
    return run_transport(scene, out_dir, options.overwrite);
  } catch (const std::exception& e) {
    std::cerr << "biofsi: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace biofsi
