// The published steady benchmarks on Gmsh meshes (cases/meshes/*.geo, made at build time into
// BIOFSI_MESH_DIR): DFG / Schaefer-Turek 2D-1 and Turek-Hron CFD1, pseudo-2-D (one hex layer,
// w = 0), forces from the consistent residual (reaction) per unit depth. Reference values:
// ../shared/reference/benchmarks.md.
#pragma once

#include <algorithm>
#include <chrono>
#include <functional>
#include <string>
#include <vector>

#include "fluid/fluid_test_support.hpp"
#include "mesh/gmsh.hpp"

namespace biofsi {
namespace test {

struct BenchmarkResult {
  double drag = 0, lift = 0, dp = 0;  // per unit depth; dp only for DFG
  int nodes = 0, newton = 0, krylov = 0;
  double seconds = 0;
};

// Depth of the extruded layer: any value works (forces are divided by it); 0.05 keeps the
// elements near the cylinder roughly isotropic at the finer refinements.
constexpr double benchmark_thickness = 0.05;

// A mesh the build made (its name), or a .msh file given by its path (mesh studies).
inline std::string mesh_file(const std::string& name) {
  const std::string suffix = ".msh";
  if (name.size() > suffix.size() &&
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
    return name;
  return std::string(BIOFSI_MESH_DIR) + "/" + name + ".msh";
}

// Channel flow past the body with the parabolic inflow of mean velocity u_mean; the benchmarks'
// do-nothing outflow is the one of the grad-u form (symmetric_viscous = false).
inline BenchmarkResult run_channel_benchmark(Mesh mesh, const std::vector<std::string>& body_sets,
                                             double density, double viscosity, double u_mean,
                                             FluidPreconditioner pc, bool with_dp,
                                             const std::function<void(FluidSettings&)>& tweak) {
  add_union_set(mesh, body_sets, "body");

  FluidSettings s = tight_fluid_settings(density, viscosity);
  s.symmetric_viscous = false;
  s.preconditioner = pc;
  s.newton_options.rel_tol = 1e-10;
  if (tweak) tweak(s);
  const double h = 0.41, u_max = 1.5 * u_mean;
  const FluidFunction inflow = [h, u_max](const Point& x, double) {
    return 4 * u_max * x[1] * (h - x[1]) / (h * h);
  };
  std::vector<FluidBoundaryCondition> bcs = {
      fluid_no_slip("walls"), fluid_no_slip("body"),
      fluid_velocity("inflow", inflow, constant(0.0), constant(0.0)), fluid_do_nothing("outflow")};
  FluidField field(mesh, s, bcs);
  field.set_initial(nullptr, nullptr, 0.0);
  BenchmarkResult r;
  const auto start = std::chrono::steady_clock::now();
  const NewtonResult nr = field.solve_steady("benchmark");
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(nr.converged);
  r.newton = field.stats().newton_iterations;
  r.krylov = field.stats().krylov_iterations;
  r.nodes = mesh.n_nodes();
  const Point f = field.force("body");
  r.drag = f[0] / benchmark_thickness;
  r.lift = f[1] / benchmark_thickness;
  if (with_dp) {
    const double z = 0.5 * benchmark_thickness;
    r.dp = field.probe({0.15, 0.2, z})[3] - field.probe({0.25, 0.2, z})[3];
  }
  return r;
}

// DFG 2D-1: rho = 1, nu = 1e-3, U_mean = 0.2, D = 0.1; c = 2 F / (rho U_mean^2 D).
struct DfgReference {
  static constexpr double c_d = 5.57953523384, c_l = 0.010618948146, dp = 0.11752016697;
};

inline BenchmarkResult run_dfg(int refine, FluidPreconditioner pc = FluidPreconditioner::Simple,
                               const std::function<void(FluidSettings&)>& tweak = {}) {
  Mesh mesh = read_gmsh(mesh_file("dfg_2d1_r" + std::to_string(refine)), benchmark_thickness);
  BenchmarkResult r = run_channel_benchmark(mesh, {"cylinder"}, 1.0, 1e-3, 0.2, pc, true, tweak);
  const double scale = 2 / (1.0 * 0.2 * 0.2 * 0.1);
  r.drag *= scale;  // now c_D
  r.lift *= scale;  // now c_L
  return r;
}

// Turek-Hron CFD1: rho = 1000, nu = 1e-3 (mu = 1), U_mean = 0.2, rigid cylinder + flag; the
// fluid block of the FSI mesh family. Forces in N/m.
struct Cfd1Reference {
  static constexpr double drag = 14.2929, lift = 1.11905;
};

inline BenchmarkResult run_cfd1(int refine, FluidPreconditioner pc = FluidPreconditioner::Simple,
                                const std::function<void(FluidSettings&)>& tweak = {}) {
  const Mesh full =
      read_gmsh(mesh_file("turek_hron_r" + std::to_string(refine)), benchmark_thickness);
  return run_channel_benchmark(submesh(full, {"fluid"}), {"cylinder", "fsi"}, 1000.0, 1.0, 0.2, pc,
                               false, tweak);
}

inline void print_benchmark(const char* name, int refine, const BenchmarkResult& r, double ref_d,
                            double ref_l) {
  std::printf("[ measured ] %s refine %d (%d nodes): drag %.5f (%+.2f%%), lift %.5f (%+.2f%%)",
              name, refine, r.nodes, r.drag, 100 * (r.drag - ref_d) / ref_d, r.lift,
              100 * (r.lift - ref_l) / ref_l);
  if (r.dp != 0)
    std::printf(", dp %.5f (%+.2f%%)", r.dp, 100 * (r.dp - DfgReference::dp) / DfgReference::dp);
  std::printf("; %d Newton, %d Krylov, %.1f s\n", r.newton, r.krylov, r.seconds);
}

}  // namespace test
}  // namespace biofsi
