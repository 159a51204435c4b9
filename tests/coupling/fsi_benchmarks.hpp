// The Turek & Hron (2006) FSI benchmarks (../shared/reference/benchmarks.md) on the Gmsh mesh
// family of cases/meshes/turek_hron.geo, pseudo-2-D (one hex layer, w = 0, plane strain): the
// elastic flag (St. Venant-Kirchhoff) clamped to the rigid cylinder, a parabolic inflow, no-slip
// walls, do-nothing outflow. Forces on cylinder + flag per unit depth from the fluid's consistent
// reaction; displacements of point A = (0.6, 0.2) at the flag's tip.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>

#include "coupling/fsi.hpp"
#include "fluid/fluid_benchmarks.hpp"

namespace biofsi {
namespace test {

struct FsiCase {
  double solid_density = 1000, solid_shear_modulus = 0.5e6, solid_poisson = 0.4;
  double fluid_density = 1000, kinematic_viscosity = 1e-3, u_mean = 0.2;
};

struct FsiBenchmarkResult {
  double ux = 0, uy = 0, drag = 0, lift = 0;
  int nodes = 0, newton = 0, krylov = 0;
  std::vector<int> krylov_per_newton;
  double seconds = 0;
  FsiStats stats;
};

struct TurekHronFsi {
  Mesh mesh;
  std::unique_ptr<FluidField> fluid;
  std::unique_ptr<StructureField> structure;
  std::unique_ptr<FsiProblem> fsi;
  std::vector<int> tip;  // the nodes at A through the thickness
  // The inflow is scaled by ramp(t) (1 for steady runs).
  std::function<double(double)> ramp = [](double) { return 1.0; };

  double tip_displacement(int c) const {
    const auto d = fsi->displacement();
    double s = 0;
    for (int n : tip) s += d[n][c] / tip.size();
    return s;
  }
  // The fluid's force per unit depth on the rigid cylinder and on the flag. The nodes both sets
  // share (the flag's root corners) count for the cylinder, so the two parts add up to force().
  // Only the total is independent of the pressure level (which the do-nothing outflow fixes):
  // the flag's surface is open at its root, so a constant p0 added to the pressure takes
  // p0 * 0.02 m (the flag's thickness) from the flag's drag and gives it to the cylinder's. A
  // drag oscillation that sits on one part may therefore be the pressure level at the body
  // oscillating; the lift's split has no such term (the flag's two long sides cancel).
  struct ForceParts {
    Point cylinder, flag;
    Point total() const { return {cylinder[0] + flag[0], cylinder[1] + flag[1], 0.0}; }
  };
  ForceParts force_parts() const {
    const BoundaryTraction cyl = fluid->boundary_traction("cylinder");
    const BoundaryTraction flag = fluid->boundary_traction("fsi");
    const auto& cylinder_nodes = mesh.node_sets.at("cylinder");
    ForceParts p{{0, 0, 0}, {0, 0, 0}};
    for (int c = 0; c < 2; ++c) p.cylinder[c] = cyl.total[c] / benchmark_thickness;
    for (size_t i = 0; i < flag.nodes.size(); ++i)
      if (!std::binary_search(cylinder_nodes.begin(), cylinder_nodes.end(), flag.nodes[i]))
        for (int c = 0; c < 2; ++c) p.flag[c] += flag.force[i][c] / benchmark_thickness;
    return p;
  }
  Point force() const { return force_parts().total(); }
};

inline std::unique_ptr<TurekHronFsi> make_turek_hron(
    const std::string& mesh_name, const FsiCase& c, bool steady, double theta = 0.5,
    ShapeDerivatives shape = ShapeDerivatives::FiniteDifference,
    const std::function<void(FsiSettings&)>& tweak = nullptr,
    const std::function<void(FluidSettings&)>& fluid_tweak = nullptr) {
  auto th = std::make_unique<TurekHronFsi>();
  th->mesh = read_gmsh(mesh_file(mesh_name), benchmark_thickness);
  const Mesh& mesh = th->mesh;
  for (int n = 0; n < mesh.n_nodes(); ++n)
    if (std::abs(mesh.x[n][0] - 0.6) < 1e-9 && std::abs(mesh.x[n][1] - 0.2) < 1e-9)
      th->tip.push_back(n);

  FluidSettings fs = tight_fluid_settings(c.fluid_density, c.fluid_density * c.kinematic_viscosity);
  fs.blocks = {"fluid"};
  fs.symmetric_viscous = false;  // the benchmarks' do-nothing outflow (see fluid_benchmarks.hpp)
  fs.theta = theta;
  if (fluid_tweak) fluid_tweak(fs);
  const double h = 0.41, u_max = 1.5 * c.u_mean;
  TurekHronFsi* self = th.get();
  const FluidFunction inflow = [h, u_max, self](const Point& x, double t) {
    return self->ramp(t) * 4 * u_max * x[1] * (h - x[1]) / (h * h);
  };
  th->fluid = std::make_unique<FluidField>(
      mesh, fs,
      std::vector<FluidBoundaryCondition>{
          fluid_no_slip("walls"), fluid_no_slip("cylinder"), fluid_no_slip("fsi"),
          fluid_velocity("inflow", inflow, constant(0.0), constant(0.0)),
          fluid_do_nothing("outflow")});

  StructureSettings ss;
  const double mu = c.solid_shear_modulus, nu = c.solid_poisson;
  const StructureMaterial flag =
      StructureMaterial::from_young(SaintVenantKirchhoff, 2 * mu * (1 + nu), nu, c.solid_density);
  ss.materials.assign(mesh.block_names.size(), flag);
  ss.blocks = {"solid"};
  ss.quasi_static = steady;
  ss.theta = theta;
  ss.plane_strain = true;
  const SpaceTimeFunction zero = constant(0.0);
  th->structure = std::make_unique<StructureField>(
      mesh, ss, std::vector<StructureDirichlet>{{"solid_clamp", {zero, zero, zero}}});

  FsiSettings fsi;
  fsi.interface = "fsi";
  fsi.mesh_motion.fixed_walls = {"walls", "inflow", "outflow", "cylinder"};
  fsi.mesh_motion.sliding_walls = {"front", "back"};
  fsi.shape_derivatives = shape;
  fsi.rel_tol = 1e-8;
  // Tighter block solves than the default: 52 instead of 313 outer iterations on FSI1 refine 2
  // (FsiSettings::inner_tolerance).
  fsi.inner_tolerance = 3e-4;
  if (tweak) tweak(fsi);
  th->fsi = std::make_unique<FsiProblem>(mesh, *th->fluid, *th->structure, fsi);
  th->fluid->set_initial(nullptr, nullptr, 0.0);
  return th;
}

// FSI1: steady, Re 20 (Turek & Hron 2006, Table "FSI1").
struct Fsi1Reference {
  static constexpr double ux = 2.27e-5, uy = 8.209e-4, drag = 14.295, lift = 0.7638;
};

// mesh_name: a mesh of cases/meshes/turek_hron.geo made by tests/CMakeLists.txt
// (turek_hron_r<refine>).
inline FsiBenchmarkResult run_fsi1(const std::string& mesh_name,
                                   ShapeDerivatives shape = ShapeDerivatives::FiniteDifference) {
  FsiCase fc;
  // The fluid block by a sparse LU of its Jacobian (fields.fluid.preconditioner: direct): on
  // refine 2, 2 threads, in one sitting, 40.3 s against SIMPLE's 140.7 s with the same 7 Newton
  // steps and results (the fluid block's 3442 inner SIMPLE iterations took 108.7 s, its 34 LU
  // solves 1.9 s); with the LU, inner tolerance 1e-2 took 52.3 s and 3e-3 stalled.
  auto th = make_turek_hron(mesh_name, fc, true, 1.0, shape, nullptr, [](FluidSettings& f) {
    f.preconditioner = FluidPreconditioner::Direct;
  });
  FsiBenchmarkResult r;
  const auto start = std::chrono::steady_clock::now();
  const NewtonResult nr = th->fsi->solve_steady("FSI1");
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.newton = nr.iterations;
  r.krylov = nr.krylov_iterations;
  r.krylov_per_newton = th->fsi->stats().last_krylov;
  r.nodes = th->mesh.n_nodes();
  r.ux = th->tip_displacement(0);
  r.uy = th->tip_displacement(1);
  const Point f = th->force();
  r.stats = th->fsi->stats();
  r.drag = f[0];
  r.lift = f[1];
  return r;
}

inline void print_fsi1(const std::string& mesh_name, const FsiBenchmarkResult& r) {
  const char* refine = mesh_name.c_str();
  using R = Fsi1Reference;
  std::printf(
      "[ measured ] FSI1 %s (%d nodes): u_x(A) %.4e (%+.2f%%), u_y(A) %.4e (%+.2f%%), drag "
      "%.4f (%+.2f%%), lift %.4f (%+.2f%%); %d Newton, %d Krylov (",
      refine, r.nodes, r.ux, 100 * (r.ux - R::ux) / R::ux, r.uy, 100 * (r.uy - R::uy) / R::uy,
      r.drag, 100 * (r.drag - R::drag) / R::drag, r.lift, 100 * (r.lift - R::lift) / R::lift,
      r.newton, r.krylov);
  for (size_t i = 0; i < r.krylov_per_newton.size(); ++i)
    std::printf("%s%d", i ? " " : "", r.krylov_per_newton[i]);
  std::printf(" per Newton iteration), %.1f s\n", r.seconds);
  const FsiStats& s = r.stats;
  std::printf(
      "[ measured ] FSI1 %s time [s]: residual %.1f, Jacobian action %.1f (shape "
      "derivatives %.1f), assembly %.1f, preconditioner set-up %.1f, preconditioner %.1f (block "
      "Krylov: "
      "structure %d its %.1f s, fluid %d its %.1f s, fluid mesh %d its %.1f s)\n",
      refine, s.seconds_residual, s.seconds_tangent, s.seconds_shape, s.seconds_assembly,
      s.seconds_preconditioner_setup, s.seconds_preconditioner, s.inner_iterations[0],
      s.seconds_inner[0], s.inner_iterations[1], s.seconds_inner[1], s.inner_iterations[2],
      s.seconds_inner[2]);
}

}  // namespace test
}  // namespace biofsi
