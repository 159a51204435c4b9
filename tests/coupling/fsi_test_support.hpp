// Shared set-up for the FSI tests (src/coupling): a two-block channel (an elastic layer under a
// shear flow, the box form of the biofilm cases), the fields on it and the coupling.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "coupling/fsi.hpp"
#include "fluid/fluid_test_support.hpp"

namespace biofsi {
namespace test {

// [0, 1] x ([0, 0.25] solid, [0.25, 1] fluid) x [0, 0.1], nx elements along x.
inline Mesh layer_channel(int nx, int ny_solid, int ny_fluid) {
  return make_box_mesh(
      {0,
       1,
       0,
       0.1,
       nx,
       1,
       {{"solid", 0.0, 0.25, ny_solid, 1.0}, {"fluid", 0.25, 1.0, ny_fluid, 1.0}}});
}

struct LayerProblem {
  Mesh mesh;
  std::unique_ptr<FluidField> fluid;
  std::unique_ptr<StructureField> structure;
  std::unique_ptr<FsiProblem> fsi;
};

struct LayerParameters {
  double fluid_density = 1, viscosity = 0.05, inflow = 1;  // shear inflow u = inflow (y - 0.25)
  double solid_density = 1, youngs_modulus = 50, poisson_ratio = 0.3;
  StructureModel model = SaintVenantKirchhoff;
  bool quasi_static = false;
  double theta = 0.66;
  ShapeDerivatives shape = ShapeDerivatives::FiniteDifference;
  int nx = 6, ny_solid = 2, ny_fluid = 4;
  int max_iterations = 25, max_step_cuts = 4;
};

// The layer clamped at its bottom and sides, a linear shear inflow on the left, do-nothing on the
// right, slip at the top; the fluid mesh fixed at top and bottom, sliding on the sides and the z
// planes; pseudo-2-D throughout.
inline LayerProblem make_layer_problem(const LayerParameters& p) {
  LayerProblem lp;
  lp.mesh = layer_channel(p.nx, p.ny_solid, p.ny_fluid);
  FluidSettings fs = tight_fluid_settings(p.fluid_density, p.viscosity);
  fs.blocks = {"fluid"};
  fs.theta = p.theta;
  const double u0 = p.inflow;
  const FluidFunction shear = [u0](const Point& x, double) { return u0 * (x[1] - 0.25) / 0.75; };
  lp.fluid = std::make_unique<FluidField>(
      lp.mesh, fs,
      std::vector<FluidBoundaryCondition>{
          fluid_velocity("fluid_left", shear, constant(0), constant(0)),
          fluid_no_slip("solid_fluid"), fluid_slip("top"), fluid_do_nothing("fluid_right")});
  StructureSettings ss;
  const StructureMaterial solid =
      StructureMaterial::from_young(p.model, p.youngs_modulus, p.poisson_ratio, p.solid_density);
  ss.materials = {solid, solid};  // the fluid block's entry is not used
  ss.blocks = {"solid"};
  ss.quasi_static = p.quasi_static;
  ss.theta = p.theta;
  ss.plane_strain = true;
  const SpaceTimeFunction zero = constant(0);
  lp.structure = std::make_unique<StructureField>(
      lp.mesh, ss,
      std::vector<StructureDirichlet>{{"bottom", {zero, zero, zero}},
                                      {"solid_left", {zero, zero, zero}},
                                      {"solid_right", {zero, zero, zero}}});
  FsiSettings fsi;
  fsi.interface = "solid_fluid";
  fsi.mesh_motion.fixed_walls = {"bottom", "top"};
  fsi.mesh_motion.sliding_walls = {"left", "right", "front", "back"};
  fsi.shape_derivatives = p.shape;
  fsi.rel_tol = 1e-10;
  fsi.max_iterations = p.max_iterations;
  fsi.max_step_cuts = p.max_step_cuts;
  lp.fsi = std::make_unique<FsiProblem>(lp.mesh, *lp.fluid, *lp.structure, fsi);
  return lp;
}

}  // namespace test
}  // namespace biofsi
