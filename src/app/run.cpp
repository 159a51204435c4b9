#include "app/run.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "app/report.hpp"
#include "app/restart.hpp"
#include "app/simulation.hpp"
#include "growth/growth.hpp"
#include "io/output.hpp"
#include "io/scene.hpp"
#include "mesh/gmsh.hpp"

namespace biofsi {

namespace {

// A nodal field that is zero off a node set.
std::vector<double> on_nodes(const Mesh& mesh, const std::vector<int>& nodes,
                             const std::vector<double>& values) {
  std::vector<double> out(mesh.n_nodes(), 0.0);
  for (size_t i = 0; i < nodes.size(); ++i) out[nodes[i]] = values[i];
  return out;
}

// The largest distance between the nodes' positions and `start` (same order).
double largest_distance(const Mesh& mesh, const std::vector<int>& nodes,
                        const std::vector<Point>& start) {
  double out = 0;
  for (size_t i = 0; i < nodes.size(); ++i) {
    const Point& p = mesh.x[nodes[i]];
    out = std::max(out, std::hypot(p[0] - start[i][0], p[1] - start[i][1], p[2] - start[i][2]));
  }
  return out;
}

struct InnerLoopResult {
  int steps = 0;
  bool stationary = false;
  double change = 0;
};

// What --overwrite removes of an earlier run in the output directory: every file a run writes
// there (the index and step files go with XdmfWriter), and temporary files a killed run left.
bool written_by_a_run(const std::string& name) {
  auto ends_with = [&](const std::string& suffix) {
    return name.size() >= suffix.size() &&
           name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  auto numbered = [&](const std::string& prefix, const std::string& suffix) {
    return name.size() == prefix.size() + 6 + suffix.size() && name.rfind(prefix, 0) == 0 &&
           ends_with(suffix) &&
           std::all_of(name.begin() + prefix.size(), name.end() - suffix.size(),
                       [](char c) { return c >= '0' && c <= '9'; });
  };
  return numbered("checkpoint_", ".h5") || name == "summary.txt" || name == "series.csv" ||
         (name.rfind("flux_", 0) == 0 && ends_with(".csv")) || ends_with(".tmp");
}

// Before anything is written: an earlier run's results are replaced only with --overwrite, and
// then none of its files stays beside the new ones (a stale checkpoint would be taken for this
// run's). The restart file is never removed.
void prepare_output(const std::filesystem::path& out, bool overwrite, const std::string& restart) {
  namespace fs = std::filesystem;
  const fs::path index = out / "scalar.xdmf";
  std::error_code ec;
  if (fs::exists(index, ec) && !overwrite)
    throw SceneError(index.string() +
                     ": the results of an earlier run are here; pass --overwrite to replace them "
                     "or choose another --out directory");
  if (!overwrite || !fs::is_directory(out, ec)) return;
  for (const auto& e : fs::directory_iterator(out, ec)) {
    if (!written_by_a_run(e.path().filename().string())) continue;
    if (!restart.empty() && fs::equivalent(e.path(), restart, ec)) continue;
    if (!fs::remove(e.path(), ec) && ec)
      throw OutputError(e.path().string() + ": cannot remove it (--overwrite): " + ec.message());
  }
}

class Driver {
 public:
  // Everything the run reads is read and checked here — scene, mesh, expressions, probes, the
  // restart file — before the output directory is touched.
  Driver(const Scene& scene, const RunOptions& options, const std::filesystem::path& out)
      : scene_(scene), out_(out), sim_(scene), series_(sim_), start_(Clock::now()) {
    std::cout << "mesh: " << sim_.mesh.n_nodes() << " nodes, " << sim_.mesh.n_elements()
              << " hex8 elements, " << sim_.mesh.block_names.size() << " blocks\n";
    if (sim_.reoriented_elements > 0)
      std::cout << "mesh: re-oriented " << sim_.reoriented_elements
                << " mirrored elements (left-handed at all 8 corners) of " << scene.gmsh_file
                << "\n";
    if (scene.growth.enabled) {
      // Built on the mesh as the scene gives it, as in the uninterrupted run.
      motion_ = std::make_unique<MeshMotion>(sim_.mesh, scene.growth.settings.mesh_motion);
      if (!options.restart.empty()) first_growth_step_ = read_checkpoint(options.restart);
    } else if (!options.restart.empty()) {
      first_flow_step_ = read_flow_checkpoint(options.restart);
    }
    prepare_output(out, options.overwrite, options.restart);
    writer_.emplace(out.string(), "scalar", options.overwrite);
    series_.open(out);
  }

  // A flow run (no scalar field, no growth): the steady flow, or the time stages of it.
  // A transient one writes checkpoint_NNNNNN.h5 (NNNNNN: the step) with every output step, and
  // continues from one with --restart.
  int run_flow() {
    const int first = first_flow_step_;
    int step = first;  // the step being taken: a failed one writes the last valid state under its
                       // number
    try {
      start_transient_flow(first > 0);
      write(first, sim_.time(), {});
      // A restarted run's series continues after the checkpoint's step: the forces at that step
      // are reactions of the step that led there, which the checkpoint does not hold.
      if (first == 0) series_.record(0, sim_.time());
      if (!sim_.flow_is_transient()) {
        solve_steady_flow("steady flow");
        step = 1;
        write(step, sim_.time(), {});
        series_.record(step, sim_.time());
      } else {
        Progress progress(scene_.time.steps);
        step = first + 1;
        const InnerLoopResult r = inner_loop(
            "", [&](int i, double change) { progress.update(i, sim_.time(), change); },
            [&](int i) {
              step = i + 1;
              series_.record(i, sim_.time());
              if (i % scene_.output.every == 0 || i == scene_.time.steps) {
                write(i, sim_.time(), {});
                write_checkpoint(i, flow_checkpoint_data(i));
              }
            },
            first);
        progress.done();
        step = r.steps;
      }
    } catch (const SolveError& e) {
      return failed(e, step, sim_.time());
    }
    return finish();
  }

  int run_transport() {
    int step = 0;
    try {
      if (sim_.fluid && scene_.fluid.mode == FlowMode::Steady) solve_steady_flow("steady flow");
      start_transient_flow(false);
      write(0, 0.0, {});
      if (scene_.time.mode == TimeMode::Steady) {
        const NewtonResult r = sim_.scalar.solve_steady("steady solve");
        std::cout << "steady solve: " << r.iterations << " Newton iterations, "
                  << r.krylov_iterations << " Krylov iterations, residual "
                  << r.residual_history.back() << "\n";
        write(1, sim_.scalar.time(), {});
        step = 1;
      } else {
        Progress progress(scene_.time.steps);
        const InnerLoopResult r = inner_loop(
            "", [&](int i, double change) { progress.update(i, sim_.scalar.time(), change); },
            [&](int i) {
              if (i % scene_.output.every == 0) write(i, sim_.scalar.time(), {});
            });
        progress.done();
        report_inner_loop(r);
        step = r.steps;
        if (step % scene_.output.every != 0) write(step, sim_.scalar.time(), {});
      }
    } catch (const SolveError& e) {
      return failed(e, step, sim_.scalar.time());
    }
    return finish();
  }

  int run_growth() {
    const GrowthSection& g = scene_.growth;
    const GrowthSettings& gs = g.settings;
    const int biofilm = sim_.mesh.block_index(g.biofilm_block);
    MeshMotion& motion = *motion_;
    const int first = first_growth_step_;
    note_quality(mesh_quality_by_block(sim_.mesh));

    const std::vector<int> gamma =
        sim_.mesh.node_sets.at(gs.interface_set);  // a copy: grow() replaces the mesh
    std::vector<Point> gamma_start;
    for (int n : gamma) gamma_start.push_back(sim_.mesh.x[n]);
    int k = first;
    try {
      start_transient_flow(first > 0);
      for (k = first;; ++k) {
        // Inner loop on the current mesh, from the state the previous growth step left; a steady
        // flow is solved once per mesh (the biological time scale is far slower than the flow's).
        if (sim_.fluid && scene_.fluid.mode == FlowMode::Steady)
          solve_steady_flow("growth " + std::to_string(k) + ": steady flow");
        std::deque<std::vector<double>> window, shear_window;
        const InnerLoopResult r = inner_loop(
            "growth " + std::to_string(k) + "/" + std::to_string(g.steps) + "  ",
            [&](int i, double change) { progress_line(k, i, change); },
            [&](int) {
              if (g.averaging != GrowthAveraging::Window) return;
              window.push_back(sim_.scalar.boundary_flux(gs.interface_set, biofilm).density);
              if (static_cast<int>(window.size()) > g.window) window.pop_front();
              if (!sim_.fluid) return;
              shear_window.push_back(sim_.wall_shear(gs.interface_set));
              if (static_cast<int>(shear_window.size()) > g.window) shear_window.pop_front();
            });
        totals_.inner_steps += r.steps;
        totals_.stationary_loops += r.stationary ? 1 : 0;
        const std::vector<double> flux = growth_flux(window, biofilm);
        const std::vector<double> shear = growth_shear(shear_window, gamma.size());
        const bool last = k == g.steps;
        if (k % g.output_every == 0 || last)
          write(k, k * gs.dt_bio,
                {{"flux_density", 1, false, on_nodes(sim_.mesh, gamma, flux)},
                 {"wall_shear_stress", 1, false, on_nodes(sim_.mesh, gamma, shear)}});
        if (last) break;

        const auto t0 = Clock::now();
        const std::string label = "growth step " + std::to_string(k + 1);
        Mesh grown = sim_.growth_configuration(g.reference_update);
        const InterfaceMotion im = interface_motion(grown, gs, flux, shear);
        const GrowthStepReport rep = grow(grown, motion, gs, im, label);
        sim_.take_grown_reference(grown, g.reference_update);
        totals_.seconds_growth += std::chrono::duration<double>(Clock::now() - t0).count();
        totals_.mesh_krylov_iterations += rep.krylov_iterations;
        totals_.mesh_amg_setups += rep.preconditioner_set_up ? 1 : 0;
        totals_.largest_interface_step =
            std::max(totals_.largest_interface_step, rep.max_interface_displacement);
        totals_.interface_moved = largest_distance(sim_.mesh, gamma, gamma_start);
        ++totals_.steps;
        note_quality(rep.quality);
        if (!tty_)
          std::cout << label << ": inner loop " << r.steps << " steps ("
                    << (g.inner_loop == InnerLoop::FixedSteps
                            ? "fixed"
                            : (r.stationary ? "stationary" : "not stationary"))
                    << ", change " << r.change << "), interface moved max "
                    << rep.max_interface_displacement << " mm, mesh "
                    << "quality " << format_range(rep.quality, sim_.mesh) << "\n";
        if (g.checkpoint) write_checkpoint(k + 1, growth_checkpoint_data(k + 1));
      }
    } catch (const SolveError& e) {
      return failed(e, k, k * gs.dt_bio);
    }
    if (tty_) std::cout << "\n";
    std::cout << "growth: " << totals_.steps << " growth steps, " << totals_.inner_steps
              << " inner steps (";
    if (g.inner_loop == InnerLoop::FixedSteps)
      std::cout << "inner_loop fixed_steps: " << scene_.time.steps << " per loop)\n";
    else
      std::cout << totals_.stationary_loops << " inner loops met steady_tolerance)\n";
    return finish();
  }

 private:
  // sigma at the interface nodes: the flow's at the end of the inner loop, or the window average.
  std::vector<double> growth_shear(const std::deque<std::vector<double>>& window, size_t n) const {
    if (!sim_.fluid) return std::vector<double>(n, 0.0);
    if (window.empty()) return sim_.wall_shear(scene_.growth.settings.interface_set);
    std::vector<double> avg(window.front().size(), 0.0);
    for (const auto& w : window)
      for (size_t i = 0; i < avg.size(); ++i) avg[i] += w[i] / window.size();
    return avg;
  }

  // J at the interface nodes: the stationary inner solution's, or the window average.
  std::vector<double> growth_flux(const std::deque<std::vector<double>>& window,
                                  int biofilm) const {
    if (window.empty())
      return sim_.scalar.boundary_flux(scene_.growth.settings.interface_set, biofilm).density;
    std::vector<double> avg(window.front().size(), 0.0);
    for (const auto& w : window)
      for (size_t i = 0; i < avg.size(); ++i) avg[i] += w[i] / window.size();
    return avg;
  }

  // The one inner loop of every transient run: each step the transient flow (coupled with the
  // structure where there is one), then the transport where it runs, over the time stages; stops
  // early when the change of every state falls below time.steady_tolerance.
  // Steps up to `done` were taken by the run a restart continues: the loop goes on after them, in
  // the stage they end in.
  template <class OnStep, class AfterStep>
  InnerLoopResult inner_loop(const std::string& prefix, OnStep on_step, AfterStep after_step,
                             int done = 0) {
    InnerLoopResult r;
    std::vector<std::vector<double>> previous = sim_.inner_states();
    for (const TimeSpec::Stage& stage : scene_.time.stages) {
      if (sim_.flow_is_transient()) sim_.set_theta(stage.theta);
      for (int s = 1; s <= stage.steps; ++s) {
        const int i = r.steps + 1;
        if (i <= done) {
          r.steps = i;
          continue;
        }
        std::ostringstream label;
        label << prefix << "inner step " << i << " (t = " << sim_.time() + stage.dt << ")";
        if (sim_.flow_is_transient()) advance_flow(label.str(), stage.dt);
        if (sim_.transport_runs()) sim_.scalar.step(stage.dt, label.str());
        std::vector<std::vector<double>> now = sim_.inner_states();
        r.change = 0;
        for (size_t k = 0; k < now.size(); ++k)
          r.change = std::max(r.change, relative_change(now[k], previous[k]));
        previous = std::move(now);
        r.steps = i;
        on_step(i, r.change);
        after_step(i);
        if (scene_.time.steady_tolerance > 0 && r.change < scene_.time.steady_tolerance) {
          r.stationary = true;
          return r;
        }
      }
    }
    return r;
  }

  void solve_steady_flow(const std::string& label) {
    const NewtonResult r = sim_.solve_steady_flow(label);
    if (!tty_ || !scene_.growth.enabled)
      std::cout << label << ": " << r.iterations << " Newton iterations, " << r.krylov_iterations
                << " Krylov iterations, residual "
                << (r.residual_history.empty() ? 0.0 : r.residual_history.back()) << "\n";
  }

  // fields.fluid.initial: steady: a transient flow starts from its steady state, solved once before
  // the first step (a restarted run continues from its checkpoint instead).
  void start_transient_flow(bool restarted) {
    if (sim_.fluid && scene_.fluid.mode == FlowMode::Transient &&
        scene_.fluid.initial == FlowStart::Steady && !restarted)
      solve_steady_flow("initial steady flow");
  }

  void advance_flow(const std::string& label, double dt) { sim_.advance_flow(label, dt); }

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

  void write(int step, double time, std::vector<OutputField> extra) {
    writer_->write(step, time, sim_.output_mesh(), sim_.output_fields(std::move(extra)));
  }

  using Datasets = std::vector<std::pair<std::string, std::vector<double>>>;

  // A checkpoint is where a restarted run begins, with fresh preconditioners: the run that writes
  // it sets them up afresh too, so that both take the same steps.
  void write_checkpoint(int index, const Datasets& data) {
    char name[32];
    std::snprintf(name, sizeof name, "checkpoint_%06d.h5", index);
    write_h5_datasets((out_ / name).string(), data);
    sim_.invalidate_preconditioners();
  }

  static std::vector<double> flat(const std::vector<Point>& v) {
    std::vector<double> out;
    for (const auto& p : v) out.insert(out.end(), p.begin(), p.end());
    return out;
  }

  // The flow's and the structure's state: the fluid's (u, p), the structure's displacement and
  // velocity, the fluid mesh's displacement and, for a transient continuation, its velocity.
  Datasets flow_state() const {
    Datasets data;
    if (sim_.fluid) data.push_back({"fluid", sim_.fluid->solution_host()});
    if (sim_.structure) {
      data.push_back({"structure_displacement", flat(sim_.structure->displacement())});
      data.push_back({"structure_velocity", flat(sim_.structure->velocity())});
    }
    if (sim_.fsi) {
      data.push_back({"fluid_mesh_displacement", flat(sim_.fsi->mesh_displacement())});
      data.push_back({"fluid_mesh_velocity", flat(sim_.fsi->grid_velocity())});
    }
    return data;
  }

  Datasets growth_checkpoint_data(int growth_steps_done) const {
    Datasets data = {{"coordinates", flat(sim_.mesh.x)},
                     {"phi", sim_.scalar.solution_host()},
                     {"growth_step", {static_cast<double>(growth_steps_done)}},
                     {"time", {sim_.scalar.time()}}};
    for (auto& d : flow_state()) data.push_back(std::move(d));
    return data;
  }

  // With the mesh itself (connectivity and element blocks), so that a restart on another mesh of
  // the domain can interpolate the state.
  Datasets flow_checkpoint_data(int step) const {
    std::vector<double> conn, block(sim_.mesh.element_block.begin(), sim_.mesh.element_block.end());
    for (const auto& c : sim_.mesh.conn) conn.insert(conn.end(), c.begin(), c.end());
    Datasets data = {{"coordinates", flat(sim_.mesh.x)},
                     {"connectivity", conn},
                     {"element_block", block},
                     {"step", {static_cast<double>(step)}},
                     {"time", {sim_.time()}}};
    for (auto& d : flow_state()) data.push_back(std::move(d));
    return data;
  }

  // A dataset of the restart file; one that cannot be read is bad input, named with --restart.
  static std::vector<double> read_restart(const std::string& path, const char* name) {
    try {
      return read_h5_dataset(path, name);
    } catch (const std::runtime_error& e) {
      throw SceneError(std::string(e.what()) + " (--restart " + path + ")");
    }
  }

  // Restores mesh, concentration and time; returns the growth step to continue with.
  int read_checkpoint(const std::string& path) {
    const auto xyz = read_restart(path, "coordinates");
    const auto phi = read_restart(path, "phi");
    const auto step = read_restart(path, "growth_step");
    const auto time = read_restart(path, "time");
    if (xyz.size() != 3 * sim_.mesh.x.size() || phi.size() != sim_.mesh.x.size() ||
        step.size() != 1 || time.size() != 1)
      throw SceneError(path + ": the checkpoint does not match the scene's mesh (" +
                       std::to_string(phi.size()) + " nodes in the checkpoint, " +
                       std::to_string(sim_.mesh.n_nodes()) + " in the scene)");
    for (int n = 0; n < sim_.mesh.n_nodes(); ++n)
      for (int c = 0; c < 3; ++c) sim_.mesh.x[n][c] = xyz[3 * n + c];
    sim_.scalar.update_coordinates(sim_.mesh);
    sim_.scalar.set_solution(phi);
    sim_.scalar.set_time(time[0]);
    if (sim_.fluid) {
      restore_fluid(path, time[0]);
      if (sim_.fsi) {
        sim_.fsi->set_reference(sim_.mesh);
        sim_.structure->set_state(restart_points(path, "structure_displacement"),
                                  restart_points(path, "structure_velocity"), time[0]);
        sim_.fsi->set_mesh_displacement(restart_points(path, "fluid_mesh_displacement"));
        sim_.scalar.update_coordinates(sim_.fsi->current_mesh());
      } else {
        sim_.fluid->update_coordinates(sim_.mesh, 0.0);
      }
      sim_.after_flow_solve("restart");
    }
    // Compared as a double: a stored value outside int's range must not be converted first.
    if (!(step[0] >= 0 && step[0] <= scene_.growth.steps))
      throw SceneError(path + ": growth step " + std::to_string(step[0]) +
                       " is outside the scene's 0.." + std::to_string(scene_.growth.steps));
    const int first = static_cast<int>(step[0]);
    std::cout << "restart: " << path << " (after growth step " << first << ", t = " << time[0]
              << " ms)\n";
    return first;
  }

  // The fluid's (u, p) of a restart file on a mesh of n nodes.
  static std::vector<double> restart_fluid(const std::string& path, int n) {
    auto state = read_restart(path, "fluid");
    if (state.size() != 4 * static_cast<size_t>(n))
      throw SceneError(path + ": the checkpoint has no fluid state for its mesh");
    return state;
  }

  void restore_fluid(const std::string& path, double time) {
    sim_.fluid->set_solution(restart_fluid(path, sim_.mesh.n_nodes()));
    sim_.fluid->set_time(time);
  }

  // A node's three values of a restart dataset, checked against a mesh of n nodes (the scene's
  // by default).
  std::vector<Point> restart_points(const std::string& path, const char* name, int n = -1) const {
    if (n < 0) n = sim_.mesh.n_nodes();
    const auto v = read_restart(path, name);
    if (v.size() != 3 * static_cast<size_t>(n))
      throw SceneError(path + ": the checkpoint has no '" + std::string(name) +
                       "' for its mesh (--restart " + path + ")");
    std::vector<Point> out(n);
    for (int i = 0; i < n; ++i) out[i] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
    return out;
  }

  // Restores a transient flow run's state from its checkpoint (flow_checkpoint_data): written on
  // the scene's own mesh, or on another mesh of the same domain and blocks, whose state is then
  // interpolated onto the scene's (restart.hpp). Returns the step it was taken after.
  int read_flow_checkpoint(const std::string& path) {
    if (scene_.scalar.enabled || !sim_.flow_is_transient())
      throw SceneError("--restart " + path +
                       ": the scene is neither a growth run nor a transient flow run; expected "
                       "a scene whose steps a checkpoint can continue");
    const auto step = read_restart(path, "step");
    const auto time = read_restart(path, "time");
    if (step.size() != 1 || time.size() != 1)
      throw SceneError(path + ": not a checkpoint of a flow run (--restart " + path + ")");
    if (!(step[0] >= 1 && step[0] < scene_.time.steps))
      throw SceneError(path + ": step " + std::to_string(step[0]) + " is outside the scene's 1.." +
                       std::to_string(scene_.time.steps - 1) + " (--restart " + path + ")");
    const Mesh from = checkpoint_mesh(path);
    FlowState state;
    if (from.n_nodes() > 0) {
      state = transfer(from, read_flow_state(path, from.n_nodes()), sim_.mesh, field_blocks());
      std::cout << "restart: the state of " << from.n_nodes()
                << " nodes interpolated onto the scene's " << sim_.mesh.n_nodes() << "\n";
    } else {
      state = read_flow_state(path, sim_.mesh.n_nodes());
    }
    if (sim_.fluid) {
      sim_.fluid->set_solution(state.fluid);
      sim_.fluid->set_time(time[0]);
    }
    if (sim_.structure) sim_.structure->set_state(state.displacement, state.velocity, time[0]);
    if (sim_.fsi) sim_.fsi->set_mesh_displacement(state.mesh_displacement, state.mesh_velocity);
    sim_.after_flow_solve("restart");
    const int first = static_cast<int>(step[0]);
    std::cout << "restart: " << path << " (after step " << first << ", t = " << time[0] << ")\n";
    return first;
  }

  // The mesh a flow checkpoint was written on when it is not the scene's (no nodes when it is).
  Mesh checkpoint_mesh(const std::string& path) const {
    const auto xyz = read_restart(path, "coordinates");
    Mesh m;
    bool same = xyz.size() == 3 * sim_.mesh.x.size();
    double off = 0, size = 0;
    for (int n = 0; same && n < sim_.mesh.n_nodes(); ++n)
      for (int c = 0; c < 3; ++c) {
        off = std::max(off, std::abs(xyz[3 * n + c] - sim_.mesh.x[n][c]));
        size = std::max(size, std::abs(sim_.mesh.x[n][c]));
      }
    if (same && off <= 1e-12 * size) return m;
    const auto conn = read_restart(path, "connectivity");
    const auto block = read_restart(path, "element_block");
    const size_t nn = xyz.size() / 3, ne = block.size();
    bool valid = xyz.size() % 3 == 0 && conn.size() == 8 * ne && ne > 0;
    for (size_t i = 0; valid && i < conn.size(); ++i) valid = conn[i] >= 0 && conn[i] < nn;
    for (size_t e = 0; valid && e < ne; ++e)
      valid = block[e] >= 0 && block[e] < sim_.mesh.block_names.size();
    if (!valid)
      throw SceneError(path + ": its mesh (" + std::to_string(nn) + " nodes, " +
                       std::to_string(ne) + " elements in " +
                       std::to_string(sim_.mesh.block_names.size()) +
                       " blocks expected) cannot be read (--restart " + path + ")");
    m.block_names = sim_.mesh.block_names;
    for (size_t n = 0; n < nn; ++n) m.x.push_back({xyz[3 * n], xyz[3 * n + 1], xyz[3 * n + 2]});
    for (size_t e = 0; e < ne; ++e) {
      std::array<int, 8> c;
      for (int a = 0; a < 8; ++a) c[a] = static_cast<int>(conn[8 * e + a]);
      m.conn.push_back(c);
      m.element_block.push_back(static_cast<int>(block[e]));
    }
    return m;
  }

  // The checkpoint's state of the fields this run has, on a mesh of n nodes.
  FlowState read_flow_state(const std::string& path, int n) const {
    FlowState s;
    if (sim_.fluid) s.fluid = restart_fluid(path, n);
    if (sim_.structure) {
      s.displacement = restart_points(path, "structure_displacement", n);
      s.velocity = restart_points(path, "structure_velocity", n);
    }
    if (sim_.fsi) {
      s.mesh_displacement = restart_points(path, "fluid_mesh_displacement", n);
      s.mesh_velocity = restart_points(path, "fluid_mesh_velocity", n);
    }
    return s;
  }

  // The block indices of the fluid's and the structure's elements.
  FieldBlocks field_blocks() const {
    auto blocks_of = [&](const std::vector<int>& elements) {
      std::vector<int> b;
      for (int e : elements) b.push_back(sim_.mesh.element_block[e]);
      std::sort(b.begin(), b.end());
      b.erase(std::unique(b.begin(), b.end()), b.end());
      return b;
    };
    FieldBlocks f;
    if (sim_.fluid) f.fluid = blocks_of(sim_.fluid->elements());
    if (sim_.structure) f.structure = blocks_of(sim_.structure->elements());
    return f;
  }

  int failed(const SolveError& e, int step, double time) {
    if (tty_) std::cout << "\n";
    std::cerr << "biofsi: solve failed: field '" << e.field() << "', " << e.step() << ": "
              << e.why() << "\n";
    // The fields restored their last valid state; write it unless it is already written.
    try {
      write(step, time, {});
      std::cerr << "biofsi: wrote the last valid state to " << writer_->index_path() << " (step "
                << step << ")\n";
    } catch (const std::exception& w) {
      std::cerr << "biofsi: could not write the last valid state: " << w.what() << "\n";
    }
    return kExitSolveFailed;
  }

  int finish() {
    write_flux_tables(sim_, out_);
    const std::string summary = summarise(sim_, totals_, seconds());
    std::cout << summary;
    write_text_file((out_ / "summary.txt").string(), summary);
    std::cout << "results: " << writer_->index_path() << " (open in ParaView)\n";
    return kExitSuccess;
  }

  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

  const Scene& scene_;
  std::filesystem::path out_;
  Simulation sim_;
  Series series_;
  std::unique_ptr<MeshMotion> motion_;  // growth runs
  std::optional<XdmfWriter> writer_;    // opened once the inputs are checked
  Clock::time_point start_;
  bool tty_ = isatty(STDOUT_FILENO);
  int first_growth_step_ = 0;
  int first_flow_step_ = 0;  // a restarted flow run's

  RunTotals totals_;
};

// The run itself; every error it cannot handle leaves as an exception for run_scene's handler.
int run_checked(const RunOptions& options) {
  const Scene scene = load_scene(options.scene_path, options.overrides);
  if (options.out_dir && options.out_dir->empty())
    throw SceneError(
        "--out '': an empty directory name; expected the directory to write the "
        "results to (or no --out: the scene's output.directory)");
  const std::filesystem::path out_dir = options.out_dir ? *options.out_dir : scene.output.directory;
  std::cout << "biofsi: scene " << scene.file << ", output " << out_dir.string() << "\n";
  std::cout << describe_fidelity(scene.fidelity);
  print_active_fields(scene);
  if (!scene.scalar.enabled && !scene.fluid.enabled && !scene.structure.enabled) {
    std::cout << "nothing to solve: every field is off\n";
    return kExitSuccess;
  }
  Driver driver(scene, options, out_dir);
  if (scene.growth.enabled) return driver.run_growth();
  if (!scene.scalar.enabled) return driver.run_flow();
  return driver.run_transport();
}

}  // namespace

int report_error(const std::string& scene_path) {
  // Messages of these errors begin with the file they are about; others get the scene's.
  auto line = [&](const std::exception& e, bool names_its_file) {
    std::cerr << "biofsi: " << (names_its_file ? "" : scene_path + ": ") << e.what() << "\n";
  };
  try {
    throw;
  } catch (const OutputError& e) {
    line(e, true);
    return kExitOutputFailed;
  } catch (const SceneError& e) {
    line(e, true);
    return kExitBadInput;
  } catch (const MeshFileError& e) {
    line(e, true);
    return kExitBadInput;
  } catch (const SolveError& e) {
    line(e, false);
    return kExitSolveFailed;
  } catch (const std::bad_alloc& e) {
    std::cerr << "biofsi: " << scene_path << ": out of memory (" << e.what() << ")\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    line(e, false);
    return kExitBadInput;
  } catch (...) {
    std::cerr << "biofsi: " << scene_path << ": an error of unknown type\n";
    return kExitBadInput;
  }
}

int run_scene(const RunOptions& options) {
  try {
    return run_checked(options);
  } catch (...) {
    return report_error(options.scene_path);
  }
}

}  // namespace biofsi
