#include "app/run.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>

#include "coupling/fsi.hpp"
#include "fluid/fluid.hpp"
#include "growth/growth.hpp"
#include "io/expression.hpp"
#include "io/output.hpp"
#include "io/scene.hpp"
#include "scalar/transport.hpp"

namespace biofsi {

namespace {

using Clock = std::chrono::steady_clock;

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
            << "  fluid:     "
            << (scene.fluid.enabled
                    ? "on (" +
                          std::string(scene.fluid.mode == FlowMode::Steady ? "steady"
                                                                           : "transient") +
                          " incompressible Navier-Stokes on blocks " +
                          [&] {
                            std::string b;
                            for (const auto& n : scene.fluid.settings.blocks)
                              b += (b.empty() ? "" : ", ") + n;
                            return b;
                          }() +
                          "; other blocks " +
                          (scene.structure.enabled ? std::string("elastic")
                                                   : std::string("held at rest")) +
                          "; convects the scalar" +
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
                          " finite-strain elasticity on blocks " +
                          [&] {
                            std::string b;
                            for (const auto& n : scene.structure.settings.blocks)
                              b += (b.empty() ? "" : ", ") + n;
                            return b;
                          }() +
                          ", coupled to the fluid by monolithic FSI on '" + scene.fsi.interface +
                          "'; its motion moves the fluid mesh and the transport mesh)"
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

// A nodal field that is zero off a node set.
std::vector<double> on_nodes(const Mesh& mesh, const std::vector<int>& nodes,
                             const std::vector<double>& values) {
  std::vector<double> out(mesh.n_nodes(), 0.0);
  for (size_t i = 0; i < nodes.size(); ++i) out[nodes[i]] = values[i];
  return out;
}

std::string format_range(const std::vector<QualityRange>& q, const Mesh& mesh) {
  std::ostringstream o;
  for (size_t b = 0; b < q.size(); ++b)
    o << (b ? ", " : "") << mesh.block_names[b] << " [" << q[b].min << ", " << q[b].max << "]";
  return o.str();
}

struct InnerLoopResult {
  int steps = 0;
  bool stationary = false;
  double change = 0;
};

struct GrowthTotals {
  int steps = 0, inner_steps = 0, stationary_loops = 0, mesh_krylov_iterations = 0;
  double seconds_growth = 0;
  double min_quality = 1, max_quality = -1;
  double min_deformed_quality = 1;  // FSI: of the deformed configuration over all solves
};

class Driver {
 public:
  Driver(const Scene& scene, const std::filesystem::path& out, bool overwrite)
      : scene_(scene),
        out_(out),
        mesh_(make_scene_mesh(scene)),
        field_(mesh_, scene.scalar.settings, scalar_boundary_conditions(scene.scalar)),
        writer_(out.string(), "scalar", overwrite),
        start_(Clock::now()) {
    if (scene.fluid.enabled)
      fluid_ = std::make_unique<FluidField>(mesh_, scene.fluid.settings,
                                            fluid_boundary_conditions(scene.fluid));
    if (scene.structure.enabled) {
      structure_ = std::make_unique<StructureField>(mesh_, scene.structure.settings,
                                                    structure_boundary_conditions(scene.structure));
      fsi_ = std::make_unique<FsiProblem>(mesh_, *fluid_, *structure_, scene.fsi);
    }
    std::cout << "mesh: " << mesh_.n_nodes() << " nodes, " << mesh_.n_elements()
              << " hex8 elements, " << mesh_.block_names.size() << " blocks\n";
    field_.set_initial(space_time_function(scene.scalar.initial), 0.0);
    std::array<SpaceTimeFunction, 3> v;
    for (int d = 0; d < 3; ++d) v[d] = space_time_function(scene.scalar.velocity[d]);
    std::vector<Point> c(mesh_.n_nodes());
    for (int n = 0; n < mesh_.n_nodes(); ++n)
      for (int d = 0; d < 3; ++d) c[n][d] = v[d](mesh_.x[n], 0.0);
    field_.set_convective_velocity(c);
    if (!scene.scalar.enabled) open_series();
  }

  // A flow-only scene (scalar disabled): the steady flow, or time.steps steps of it.
  int run_flow() {
    write(0, 0.0, {});
    int step = 0;
    try {
      if (scene_.fluid.mode == FlowMode::Steady) {
        solve_steady_flow("steady flow");
        step = 1;
        write(step, fluid_->time(), {});
        record_series(step, fluid_->time());
      } else {
        Progress progress(scene_.time.steps);
        std::vector<double> previous = fluid_->solution_host();
        bool steady = false;
        for (const TimeSpec::Stage& stage : scene_.time.stages) {
          for (int i = 1; i <= stage.steps && !steady; ++i) {
            ++step;
            advance_flow("flow step " + std::to_string(step), stage.dt);
            std::vector<double> now = fluid_->solution_host();
            const double change = relative_change(now, previous);
            previous = std::move(now);
            progress.update(step, fluid_->time(), change);
            record_series(step, fluid_->time());
            steady = scene_.time.steady_tolerance > 0 && change < scene_.time.steady_tolerance;
            if (step % scene_.output.every == 0 || step == scene_.time.steps)
              write(step, fluid_->time(), {});
          }
        }
        progress.done();
      }
    } catch (const SolveError& e) {
      return failed(e, step, fluid_->time());
    }
    return finish();
  }

  int run_transport() {
    int step = 0;
    try {
      if (fluid_ && scene_.fluid.mode == FlowMode::Steady) solve_steady_flow("steady flow");
      write(0, 0.0, {});
      if (scene_.time.mode == TimeMode::Steady) {
        const NewtonResult r = field_.solve_steady("steady solve");
        std::cout << "steady solve: " << r.iterations << " Newton iterations, "
                  << r.krylov_iterations << " Krylov iterations, residual "
                  << r.residual_history.back() << "\n";
        write(1, field_.time(), {});
        step = 1;
      } else {
        Progress progress(scene_.time.steps);
        const InnerLoopResult r = inner_loop(
            "", [&](int i, double change) { progress.update(i, field_.time(), change); },
            [&](int i) {
              if (i % scene_.output.every == 0) write(i, field_.time(), {});
            });
        progress.done();
        report_inner_loop(r);
        step = r.steps;
        if (step % scene_.output.every != 0) write(step, field_.time(), {});
      }
    } catch (const SolveError& e) {
      return failed(e, step, field_.time());
    }
    return finish();
  }

  int run_growth(const std::string& restart) {
    const GrowthSection& g = scene_.growth;
    const GrowthSettings& gs = g.settings;
    const int biofilm = mesh_.block_index(g.biofilm_block);
    MeshMotion motion(mesh_, gs.mesh_motion);

    int first = 0;
    if (!restart.empty()) first = read_checkpoint(restart);
    note_quality(mesh_quality_by_block(mesh_));

    const std::vector<int> gamma =
        mesh_.node_sets.at(gs.interface_set);  // a copy: grow() replaces mesh_
    int k = first;
    try {
      for (k = first;; ++k) {
        // Inner loop on the current mesh, from the state the previous growth step left; a steady
        // flow is solved once per mesh (the biological time scale is far slower than the flow's).
        if (fluid_ && scene_.fluid.mode == FlowMode::Steady)
          solve_steady_flow("growth " + std::to_string(k) + ": steady flow");
        std::deque<std::vector<double>> window, shear_window;
        const InnerLoopResult r = inner_loop(
            "growth " + std::to_string(k) + "/" + std::to_string(g.steps) + "  ",
            [&](int i, double change) { progress_line(k, i, change); },
            [&](int) {
              if (g.averaging != GrowthAveraging::Window) return;
              window.push_back(field_.boundary_flux(gs.interface_set, biofilm).density);
              if (static_cast<int>(window.size()) > g.window) window.pop_front();
              if (!fluid_) return;
              shear_window.push_back(wall_shear(gs.interface_set));
              if (static_cast<int>(shear_window.size()) > g.window) shear_window.pop_front();
            });
        totals_.inner_steps += r.steps;
        totals_.stationary_loops += r.stationary ? 1 : 0;
        const std::vector<double> flux = growth_flux(window, biofilm);
        const std::vector<double> shear = growth_shear(shear_window, gamma.size());
        const bool last = k == g.steps;
        if (k % g.output_every == 0 || last)
          write(k, k * gs.dt_bio,
                {{"flux_density", 1, false, on_nodes(mesh_, gamma, flux)},
                 {"wall_shear_stress", 1, false, on_nodes(mesh_, gamma, shear)}});
        if (last) break;

        const auto t0 = Clock::now();
        const std::string label = "growth step " + std::to_string(k + 1);
        const InterfaceMotion im = interface_motion(mesh_, gs, flux, shear);
        const GrowthStepReport rep = grow(mesh_, motion, gs, im, label);
        if (fsi_) {
          fsi_->set_reference(mesh_);
          field_.update_coordinates(fsi_->current_mesh());
        } else {
          field_.update_coordinates(mesh_);
          if (fluid_) fluid_->update_coordinates(mesh_, 0.0);
        }
        totals_.seconds_growth += std::chrono::duration<double>(Clock::now() - t0).count();
        totals_.mesh_krylov_iterations += rep.krylov_iterations;
        ++totals_.steps;
        note_quality(rep.quality);
        if (!tty_)
          std::cout << label << ": inner loop " << r.steps << " steps ("
                    << (r.stationary ? "stationary" : "not stationary") << ", change " << r.change
                    << "), interface moved max " << rep.max_interface_displacement << " mm, mesh "
                    << "quality " << format_range(rep.quality, mesh_) << "\n";
        if (g.checkpoint) write_checkpoint(k + 1);
      }
    } catch (const SolveError& e) {
      return failed(e, k, k * gs.dt_bio);
    }
    if (tty_) std::cout << "\n";
    std::cout << "growth: " << totals_.steps << " growth steps, " << totals_.inner_steps
              << " inner steps (" << totals_.stationary_loops
              << " inner loops met steady_tolerance)\n";
    return finish();
  }

 private:
  void solve_steady_flow(const std::string& label) {
    const NewtonResult r = fsi_ ? fsi_->solve_steady(label) : fluid_->solve_steady(label);
    if (!tty_ || !scene_.growth.enabled)
      std::cout << label << ": " << r.iterations << " Newton iterations, " << r.krylov_iterations
                << " Krylov iterations, residual "
                << (r.residual_history.empty() ? 0.0 : r.residual_history.back()) << "\n";
    after_flow_solve(label);
  }

  void advance_flow(const std::string& label, double dt) {
    if (fsi_)
      fsi_->step(dt, label);
    else
      fluid_->step(dt, label);
    after_flow_solve(label);
  }

  // The transport sees the flow on the configuration it was solved on: with FSI the deformed
  // mesh, the ALE convective velocity c = u - u_grid in the fluid and the biofilm's own velocity
  // for its Phi div u_S term (c = 0 there: its mesh moves with it). Without FSI the mesh does not
  // move within an inner loop, so c = u.
  void after_flow_solve(const std::string& label) {
    if (!fsi_) {
      field_.set_convective_velocity(fluid_->velocity());
      return;
    }
    const Mesh current = fsi_->current_mesh();
    check_deformed_quality(current, label);
    field_.update_coordinates(current);
    std::vector<Point> c = fluid_->velocity(), w = structure_->velocity();
    const std::vector<Point> ug = fsi_->grid_velocity();
    for (int n = 0; n < mesh_.n_nodes(); ++n)
      for (int d = 0; d < 3; ++d) c[n][d] -= ug[n][d];
    field_.set_convective_velocity(c);
    field_.set_material_velocity(w);
  }

  // The deformed configuration must stay valid for the transport on it (and the next flow step).
  void check_deformed_quality(const Mesh& current, const std::string& label) {
    const auto q = mesh_quality_by_block(current);
    for (size_t b = 0; b < q.size(); ++b) {
      totals_.min_deformed_quality = std::min(totals_.min_deformed_quality, q[b].min);
      if (q[b].min < scene_.fsi.mesh_motion.min_quality) {
        std::ostringstream why;
        why << "element " << q[b].worst_element << " of block '" << mesh_.block_names[b]
            << "' has scaled Jacobian " << q[b].min
            << (q[b].min <= 0 ? " (inverted)" : " (degenerate)")
            << " in the deformed configuration, below mesh_motion.min_quality "
            << scene_.fsi.mesh_motion.min_quality;
        throw SolveError("fsi", label, why.str());
      }
    }
  }

  // |wall shear stress| at the interface nodes (0 without a fluid).
  std::vector<double> wall_shear(const std::string& set) const {
    const std::vector<Point> tau = fluid_->wall_shear_stress(set);
    std::vector<double> out(tau.size());
    for (size_t i = 0; i < tau.size(); ++i)
      out[i] = std::sqrt(tau[i][0] * tau[i][0] + tau[i][1] * tau[i][1] + tau[i][2] * tau[i][2]);
    return out;
  }

  // sigma at the interface nodes: the flow's at the end of the inner loop, or the window average.
  std::vector<double> growth_shear(const std::deque<std::vector<double>>& window, size_t n) const {
    if (!fluid_) return std::vector<double>(n, 0.0);
    if (window.empty()) return wall_shear(scene_.growth.settings.interface_set);
    std::vector<double> avg(window.front().size(), 0.0);
    for (const auto& w : window)
      for (size_t i = 0; i < avg.size(); ++i) avg[i] += w[i] / window.size();
    return avg;
  }

  // J at the interface nodes: the stationary inner solution's, or the window average.
  std::vector<double> growth_flux(const std::deque<std::vector<double>>& window,
                                  int biofilm) const {
    if (window.empty())
      return field_.boundary_flux(scene_.growth.settings.interface_set, biofilm).density;
    std::vector<double> avg(window.front().size(), 0.0);
    for (const auto& w : window)
      for (size_t i = 0; i < avg.size(); ++i) avg[i] += w[i] / window.size();
    return avg;
  }

  // The states whose change decides stationarity: the scalar's, and with a transient flow the
  // flow's and the structure's displacement (each measured relative to its own size).
  std::vector<std::vector<double>> inner_states() const {
    std::vector<std::vector<double>> out = {field_.solution_host()};
    if (fluid_ && scene_.fluid.mode == FlowMode::Transient) {
      out.push_back(fluid_->solution_host());
      if (structure_) {
        std::vector<double> d;
        for (const auto& p : structure_->displacement()) d.insert(d.end(), p.begin(), p.end());
        out.push_back(std::move(d));
      }
    }
    return out;
  }

  template <class OnStep, class AfterStep>
  InnerLoopResult inner_loop(const std::string& prefix, OnStep on_step, AfterStep after_step) {
    InnerLoopResult r;
    std::vector<std::vector<double>> previous = inner_states();
    for (int i = 1; i <= scene_.time.steps; ++i) {
      std::ostringstream label;
      label << prefix << "inner step " << i << " (t = " << field_.time() + scene_.time.dt << ")";
      if (fluid_ && scene_.fluid.mode == FlowMode::Transient)
        advance_flow(label.str(), scene_.time.dt);
      field_.step(scene_.time.dt, label.str());
      std::vector<std::vector<double>> now = inner_states();
      r.change = 0;
      for (size_t k = 0; k < now.size(); ++k)
        r.change = std::max(r.change, relative_change(now[k], previous[k]));
      previous = std::move(now);
      r.steps = i;
      on_step(i, r.change);
      after_step(i);
      if (scene_.time.steady_tolerance > 0 && r.change < scene_.time.steady_tolerance) {
        r.stationary = true;
        break;
      }
    }
    return r;
  }

  void report_inner_loop(const InnerLoopResult& r) const {
    if (r.stationary)
      std::cout << "stationary after " << r.steps << " steps: relative change " << r.change
                << " < steady_tolerance " << scene_.time.steady_tolerance << "\n";
    else
      std::cout << "reached the last step (" << r.steps << ")"
                << (scene_.time.steady_tolerance > 0
                        ? " without meeting steady_tolerance (last change " +
                              std::to_string(r.change) + ")"
                        : std::string())
                << "\n";
  }

  void progress_line(int k, int i, double change) {
    const double elapsed = seconds();
    const int done = k - first_growth_step_;
    const int total = scene_.growth.steps + 1 - first_growth_step_;
    const double fraction =
        (done + static_cast<double>(i) / scene_.time.steps) / std::max(total, 1);
    const double left = fraction > 0 ? elapsed / fraction * (1 - fraction) : 0.0;
    if (!tty_) return;  // plain logs get one line per growth step instead
    std::ostringstream s;
    s << "\rgrowth " << k << "/" << scene_.growth.steps << "  inner " << i << "/"
      << scene_.time.steps << "  change " << std::scientific << std::setprecision(2) << change
      << std::fixed << std::setprecision(1) << "  elapsed " << elapsed << " s  left ~" << left
      << " s   ";
    std::cout << s.str() << std::flush;
  }

  void note_quality(const std::vector<QualityRange>& q) {
    for (const auto& b : q) {
      totals_.min_quality = std::min(totals_.min_quality, b.min);
      totals_.max_quality = std::max(totals_.max_quality, b.max);
    }
  }

  // series.csv of a flow run: a row per step with the fluid's force on each force boundary and
  // each probe's value (the mean over its nodes), flushed row by row so a run's history survives
  // it being stopped.
  void open_series() {
    const OutputSpec& o = scene_.output;
    if (o.probes.empty() && o.force_boundaries.empty()) return;
    for (size_t i = 0; i < o.probes.size(); ++i) probes_.push_back(probe_nodes(o.probes[i], i));
    series_.open(out_ / "series.csv");
    series_ << "step,time";
    for (const auto& set : o.force_boundaries)
      for (const char* c : {"x", "y", "z"}) series_ << ",force_" << set << "_" << c;
    for (const auto& p : o.probes)
      if (p.quantity == ProbeSpec::Quantity::Pressure)
        series_ << "," << p.name << "_pressure";
      else
        for (const char* c : {"x", "y", "z"})
          series_ << "," << p.name
                  << (p.quantity == ProbeSpec::Quantity::Velocity ? "_velocity_" : "_displacement_")
                  << c;
    series_ << "\n" << std::setprecision(12);
    record_series(0, fluid_->time());
  }

  std::vector<int> probe_nodes(const ProbeSpec& p, size_t index) const {
    std::vector<int> nodes;
    for (int n = 0; n < mesh_.n_nodes(); ++n) {
      bool at = true;
      for (size_t d = 0; d < p.point.size(); ++d)
        at = at && std::abs(mesh_.x[n][d] - p.point[d]) <= 1e-9 * (1 + std::abs(p.point[d]));
      if (at) nodes.push_back(n);
    }
    if (nodes.empty()) {
      std::ostringstream msg;
      msg << scene_.file << ":" << p.line << ": output.probes[" << index << "].point: no mesh node "
          << "at (";
      for (size_t d = 0; d < p.point.size(); ++d) msg << (d ? ", " : "") << p.point[d];
      msg << "); expected a point that is a node of the mesh (or, with 2 coordinates, nodes "
             "through its thickness)";
      throw SceneError(msg.str());
    }
    return nodes;
  }

  void record_series(int step, double time) {
    if (!series_.is_open()) return;
    series_ << step << "," << time;
    for (const auto& set : scene_.output.force_boundaries) {
      const Point f = fluid_->force(set);
      series_ << "," << f[0] << "," << f[1] << "," << f[2];
    }
    std::vector<Point> displacement, velocity;
    std::vector<double> pressure;
    for (size_t i = 0; i < probes_.size(); ++i) {
      const auto quantity = scene_.output.probes[i].quantity;
      const auto& nodes = probes_[i];
      Point mean{0, 0, 0};
      for (int n : nodes) {
        if (quantity == ProbeSpec::Quantity::Pressure) {
          if (pressure.empty()) pressure = fluid_->pressure();
          mean[0] += pressure[n] / nodes.size();
          continue;
        }
        std::vector<Point>& v = quantity == ProbeSpec::Quantity::Velocity ? velocity : displacement;
        if (v.empty())
          v = quantity == ProbeSpec::Quantity::Velocity ? fluid_->velocity() : fsi_->displacement();
        for (int d = 0; d < 3; ++d) mean[d] += v[n][d] / nodes.size();
      }
      if (quantity == ProbeSpec::Quantity::Pressure)
        series_ << "," << mean[0];
      else
        series_ << "," << mean[0] << "," << mean[1] << "," << mean[2];
    }
    series_ << "\n" << std::flush;
  }

  void write(int step, double time, std::vector<OutputField> extra) {
    if (fsi_) {
      std::vector<double> d;
      for (const auto& v : fsi_->displacement()) d.insert(d.end(), v.begin(), v.end());
      extra.insert(extra.begin(), {"displacement", 3, false, d});
      // The biofilm's stress state per element (zero outside the structure's blocks), and its
      // velocity (zero in quasi-static runs).
      const std::vector<double> all = structure_->von_mises_stress();
      std::vector<double> vm(all.size(), 0.0), v;
      for (int e : structure_->elements()) vm[e] = all[e];
      for (const auto& p : structure_->velocity()) v.insert(v.end(), p.begin(), p.end());
      extra.push_back({"von_mises_stress", 1, true, vm});
      extra.push_back({"structure_velocity", 3, false, v});
    }
    if (fluid_) {
      std::vector<double> u, p = fluid_->pressure();
      for (const auto& v : fluid_->velocity()) u.insert(u.end(), v.begin(), v.end());
      extra.insert(extra.begin(), {"pressure", 1, false, p});
      extra.insert(extra.begin(), {"velocity", 3, false, u});
    }
    if (scene_.scalar.enabled)
      extra.insert(extra.begin(), {"phi", 1, false, field_.solution_host()});
    writer_.write(step, time, fsi_ ? fsi_->current_mesh() : mesh_, extra);
  }

  void write_checkpoint(int growth_steps_done) {
    char name[32];
    std::snprintf(name, sizeof name, "checkpoint_%06d.h5", growth_steps_done);
    std::vector<double> xyz;
    for (const auto& p : mesh_.x) xyz.insert(xyz.end(), p.begin(), p.end());
    std::vector<std::pair<std::string, std::vector<double>>> data = {
        {"coordinates", xyz},
        {"phi", field_.solution_host()},
        {"growth_step", {static_cast<double>(growth_steps_done)}},
        {"time", {field_.time()}}};
    if (fluid_) data.push_back({"fluid", fluid_->solution_host()});
    if (fsi_) {
      auto flat = [](const std::vector<Point>& v) {
        std::vector<double> out;
        for (const auto& p : v) out.insert(out.end(), p.begin(), p.end());
        return out;
      };
      data.push_back({"structure_displacement", flat(structure_->displacement())});
      data.push_back({"structure_velocity", flat(structure_->velocity())});
      data.push_back({"fluid_mesh_displacement", flat(fsi_->mesh_displacement())});
    }
    write_h5_datasets((out_ / name).string(), data);
  }

  // Restores mesh, concentration and time; returns the growth step to continue with.
  int read_checkpoint(const std::string& path) {
    const auto xyz = read_h5_dataset(path, "coordinates");
    const auto phi = read_h5_dataset(path, "phi");
    const auto step = read_h5_dataset(path, "growth_step");
    const auto time = read_h5_dataset(path, "time");
    if (xyz.size() != 3 * mesh_.x.size() || phi.size() != mesh_.x.size() || step.size() != 1 ||
        time.size() != 1)
      throw std::runtime_error(path + ": the checkpoint does not match the scene's mesh (" +
                               std::to_string(phi.size()) + " nodes in the checkpoint, " +
                               std::to_string(mesh_.n_nodes()) + " in the scene)");
    for (int n = 0; n < mesh_.n_nodes(); ++n)
      for (int c = 0; c < 3; ++c) mesh_.x[n][c] = xyz[3 * n + c];
    field_.update_coordinates(mesh_);
    field_.set_solution(phi);
    field_.set_time(time[0]);
    if (fluid_) {
      const auto state = read_h5_dataset(path, "fluid");
      if (state.size() != 4 * mesh_.x.size())
        throw std::runtime_error(path + ": the checkpoint has no fluid state for this mesh");
      fluid_->set_solution(state);
      fluid_->set_time(time[0]);
      if (fsi_) {
        auto points = [&](const char* name) {
          const auto v = read_h5_dataset(path, name);
          if (v.size() != 3 * mesh_.x.size())
            throw std::runtime_error(path + ": the checkpoint has no '" + std::string(name) +
                                     "' for this mesh");
          std::vector<Point> out(mesh_.n_nodes());
          for (int n = 0; n < mesh_.n_nodes(); ++n) out[n] = {v[3 * n], v[3 * n + 1], v[3 * n + 2]};
          return out;
        };
        fsi_->set_reference(mesh_);
        structure_->set_state(points("structure_displacement"), points("structure_velocity"),
                              time[0]);
        fsi_->set_mesh_displacement(points("fluid_mesh_displacement"));
        field_.update_coordinates(fsi_->current_mesh());
      } else {
        fluid_->update_coordinates(mesh_, 0.0);
      }
      after_flow_solve("restart");
    }
    first_growth_step_ = static_cast<int>(step[0]);
    if (first_growth_step_ < 0 || first_growth_step_ > scene_.growth.steps)
      throw std::runtime_error(path + ": growth step " + std::to_string(first_growth_step_) +
                               " is outside the scene's 0.." + std::to_string(scene_.growth.steps));
    std::cout << "restart: " << path << " (after growth step " << first_growth_step_
              << ", t = " << time[0] << " ms)\n";
    return first_growth_step_;
  }

  int failed(const SolveError& e, int step, double time) {
    if (tty_) std::cout << "\n";
    std::cerr << "biofsi: solve failed: field '" << e.field() << "', " << e.step() << ": "
              << e.why() << "\n";
    // The fields restored their last valid state; write it unless it is already written.
    try {
      write(step, time, {});
      std::cerr << "biofsi: wrote the last valid state to " << writer_.index_path() << " (step "
                << step << ")\n";
    } catch (const std::exception& w) {
      std::cerr << "biofsi: could not write the last valid state: " << w.what() << "\n";
    }
    return 3;
  }

  int finish() {
    write_flux_tables();
    const std::string summary = summarise();
    std::cout << summary;
    std::ofstream(out_ / "summary.txt") << summary;
    std::cout << "results: " << writer_.index_path() << " (open in ParaView)\n";
    return 0;
  }

  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

  void write_flux_tables() const {
    for (const auto& set : scene_.output.flux_boundaries) {
      const BoundaryFlux f = field_.boundary_flux(set, flux_block(mesh_, set));
      const auto path = out_ / ("flux_" + set + ".csv");
      std::ofstream out(path.string() + ".tmp");
      out << "x,y,z,nodal_flux,lumped_area,flux_density\n" << std::setprecision(12);
      for (size_t i = 0; i < f.nodes.size(); ++i) {
        const Point& p = mesh_.x[f.nodes[i]];
        out << p[0] << ',' << p[1] << ',' << p[2] << ',' << f.nodal_flux[i] << ','
            << f.lumped_area[i] << ',' << f.density[i] << '\n';
      }
      out.close();
      std::filesystem::rename(path.string() + ".tmp", path);
    }
  }

  std::string summarise() const {
    const TransportStats& s = field_.stats();
    std::ostringstream o;
    o << std::setprecision(6);
    o << "summary\n"
      << "  scene: " << scene_.file << "\n"
      << "  nodes " << mesh_.n_nodes() << ", elements " << mesh_.n_elements() << "\n"
      << "  scalar: " << s.steps << " solves, " << s.newton_iterations << " Newton and "
      << s.krylov_iterations << " Krylov iterations, " << s.amg_setups << " AMG set-ups, "
      << s.cut_steps << " time steps cut into sub-steps, " << s.pseudo_steps
      << " pseudo-time steps\n";
    if (fluid_ && !fsi_) {
      const FluidStats& f = fluid_->stats();
      o << "  fluid: " << f.steps << " solves, " << f.newton_iterations << " Newton and "
        << f.krylov_iterations << " Krylov iterations, " << f.preconditioner_setups
        << " preconditioner set-ups, " << f.cut_steps << " time steps cut, " << f.pseudo_steps
        << " pseudo-time steps\n";
    }
    if (fsi_) {
      const FsiStats& f = fsi_->stats();
      double d_max = 0;
      for (const auto& p : structure_->displacement())
        d_max = std::max(d_max, std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]));
      o << "  fsi: " << f.solves << " monolithic solves, " << f.newton_iterations << " Newton and "
        << f.krylov_iterations << " outer Krylov iterations (inner: structure "
        << f.inner_iterations[0] << ", fluid " << f.inner_iterations[1] << ", fluid mesh "
        << f.inner_iterations[2] << "), " << f.cut_steps << " time steps cut; max structure "
        << "displacement " << d_max << ", smallest scaled Jacobian of the deformed mesh "
        << totals_.min_deformed_quality << "\n";
    }
    o << "  time [s]: total " << seconds() << "; scalar " << s.seconds_solve << " (residual "
      << s.seconds_residual << ", tangent " << s.seconds_tangent << ", linearisation "
      << s.seconds_linearise << ", assembly " << s.seconds_assembly << ", AMG set-up "
      << s.seconds_amg_setup << ")";
    if (fsi_) {
      const FsiStats& f = fsi_->stats();
      // Shape derivatives are part of the Jacobian action; the block Krylov solves are the
      // preconditioner's (its remainder: the coupling-block products).
      o << "; fsi " << f.seconds_solve << " (residual " << f.seconds_residual
        << ", jacobian action " << f.seconds_tangent << ", shape derivatives " << f.seconds_shape
        << ", assembly " << f.seconds_assembly << ", AMG set-up " << f.seconds_preconditioner_setup
        << ", preconditioner " << f.seconds_preconditioner << ", block Krylov structure "
        << f.seconds_inner[0] << ", block Krylov fluid " << f.seconds_inner[1]
        << ", block Krylov fluid mesh " << f.seconds_inner[2] << ")";
    } else if (fluid_) {
      const FluidStats& f = fluid_->stats();
      o << "; fluid " << f.seconds_solve << " (residual " << f.seconds_residual << ", tangent "
        << f.seconds_tangent << ", linearisation " << f.seconds_linearise << ", assembly "
        << f.seconds_assembly << ", preconditioner set-up " << f.seconds_preconditioner_setup
        << ")";
    }
    if (scene_.growth.enabled)
      o << "; growth + mesh motion " << totals_.seconds_growth << " (" << totals_.steps
        << " steps, " << totals_.mesh_krylov_iterations << " CG iterations)";
    o << "\n";
    if (scene_.growth.enabled)
      o << "  mesh quality (scaled Jacobian) over the run: [" << totals_.min_quality << ", "
        << totals_.max_quality << "]\n";
    if (scene_.scalar.enabled)
      o << "  final time " << field_.time() << ", integral of phi " << field_.integral()
        << ", consumption rate " << field_.reaction_integral() << "\n";
    for (const auto& set : scene_.output.force_boundaries) {
      const Point f = fluid_->force(set);
      o << "  fluid force on '" << set << "': (" << f[0] << ", " << f[1] << ", " << f[2] << ")\n";
    }
    for (const auto& set : scene_.output.flux_boundaries) {
      const int block = flux_block(mesh_, set);
      const BoundaryFlux f = field_.boundary_flux(set, block);
      const auto [lo, hi] = std::minmax_element(f.density.begin(), f.density.end());
      o << "  flux through '" << set << "' into "
        << (block < 0 ? std::string("the domain") : "block '" + mesh_.block_names[block] + "'")
        << ": total " << f.total << ", density min " << *lo << " max " << *hi << "\n";
    }
    return o.str();
  }

  const Scene& scene_;
  std::filesystem::path out_;
  Mesh mesh_;
  TransportField field_;
  std::unique_ptr<FluidField> fluid_;
  std::unique_ptr<StructureField> structure_;
  std::unique_ptr<FsiProblem> fsi_;
  XdmfWriter writer_;
  Clock::time_point start_;
  bool tty_ = isatty(STDOUT_FILENO);
  int first_growth_step_ = 0;
  GrowthTotals totals_;
  std::vector<std::vector<int>> probes_;  // the nodes of each output probe
  std::ofstream series_;
};

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
  if (!scene.scalar.enabled && !scene.fluid.enabled) {
    std::cout << "nothing to solve: every field is off\n";
    return 0;
  }
  try {
    Driver driver(scene, out_dir, options.overwrite);
    if (scene.growth.enabled) return driver.run_growth(options.restart);
    if (!scene.scalar.enabled) return driver.run_flow();
    if (!options.restart.empty()) {
      std::cerr << "biofsi: --restart needs a scene with a growth section\n";
      return 1;
    }
    return driver.run_transport();
  } catch (const std::exception& e) {
    std::cerr << "biofsi: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace biofsi
