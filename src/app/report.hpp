// src/app/report.hpp: what a run tells its user — the active fields, progress, the summary, the
// flux tables and the series of forces and probe values of a flow run.
#pragma once

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "app/simulation.hpp"

namespace biofsi {

using Clock = std::chrono::steady_clock;

// Terminal: one updating line. Otherwise: a plain log line at most every few seconds.
class Progress {
 public:
  explicit Progress(int total);
  void update(int step, double time, double change);
  void done();
  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  int total_;
  bool tty_;
  Clock::time_point start_;
  double last_log_ = -1e300;
};

// Prints which fields the scene turns on and why.
void print_active_fields(const Scene& scene);

// Per block "name [min, max]" of a mesh-quality range.
std::string format_range(const std::vector<QualityRange>& q, const Mesh& mesh);

// The block a set's flux is reported into: the one block that owns its faces; for an interface
// whose faces are listed once per side (Gmsh), the block its name begins with (`biofilm_fluid`:
// biofilm), else the first of the two; otherwise the whole domain (-1).
int flux_block(const Mesh& mesh, const std::string& set);

// What a run adds up besides the fields' own statistics.
struct RunTotals {
  int steps = 0, inner_steps = 0, stationary_loops = 0, mesh_krylov_iterations = 0,
      mesh_amg_setups = 0;
  double seconds_growth = 0;
  double min_quality = 1, max_quality = -1;
  // The growth interface's motion [mm]: the largest of one growth step, and the largest distance
  // an interface node moved over the run.
  double largest_interface_step = 0, interface_moved = 0;
};

// The end-of-run summary: iterations and time per field and phase, mesh quality, the requested
// fluxes and forces.
std::string summarise(const Simulation& sim, const RunTotals& totals, double seconds);

// flux_<set>.csv for each output.flux_boundaries set: the consistent flux per node.
void write_flux_tables(const Simulation& sim, const std::filesystem::path& out);

// series.csv of a flow run: a row per step with the fluid's force on each force boundary and
// each probe's value (the mean over its nodes), written row by row so that a run's history
// survives it being stopped. Inactive without force boundaries and probes. The constructor finds
// the probes' nodes (a probe point that is not a mesh node throws SceneError naming the key);
// open() creates the file. A failed write throws OutputError.
class Series {
 public:
  explicit Series(const Simulation& sim);
  void open(const std::filesystem::path& out);
  void record(int step, double time);

 private:
  std::vector<int> probe_nodes(const ProbeSpec& p, size_t index) const;
  const Simulation& sim_;
  std::vector<std::vector<int>> probes_;  // the nodes of each output probe
  TextLog file_;
};

}  // namespace biofsi
