#include "coupling/parameters.hpp"

namespace biofsi {

using namespace scene_input;

FsiSettings read_fsi_section(const Checker& c, const Node& node, const MeshNames& names,
                             bool coupled, const FluidSection& fluid,
                             const std::string& growth_interface,
                             const MeshMotionSettings& mesh_motion) {
  FsiSettings f;
  f.mesh_motion = mesh_motion;
  if (!coupled) {
    if (node.IsDefined() && !node.IsNull())
      c.fail(node, "fsi", "a coupling section without a structure and a fluid", render(node),
             "fields.structure and fields.fluid, or no fsi section");
    return f;
  }
  MapView m(c, node, "fsi",
            {"interface", "shape_derivatives", "fixed_walls", "sliding_walls", "rel_tol",
             "max_iterations", "inner_tolerance"});
  if (auto n = m.get("interface"))
    f.interface = boundary_name(c, *n, m.key("interface"), names.face_sets);
  else if (!growth_interface.empty())
    f.interface = growth_interface;
  else
    m.missing("interface", "the face set of the fluid-structure interface");
  f.shape_derivatives = get_enum(
      m, "shape_derivatives",
      {{"finite_difference", ShapeDerivatives::FiniteDifference}, {"none", ShapeDerivatives::None}},
      std::optional<ShapeDerivatives>(f.shape_derivatives));
  // Walls given here replace both of mesh_motion's lists (one given alone: the other is empty).
  const auto fixed = m.get("fixed_walls"), sliding = m.get("sliding_walls");
  if (fixed || sliding) {
    f.mesh_motion.fixed_walls.clear();
    f.mesh_motion.sliding_walls.clear();
  }
  if (fixed)
    f.mesh_motion.fixed_walls = face_set_list(c, *fixed, m.key("fixed_walls"), names.face_sets);
  if (sliding)
    f.mesh_motion.sliding_walls =
        face_set_list(c, *sliding, m.key("sliding_walls"), names.face_sets);
  f.rel_tol = get_number(
      m, "rel_tol", [](double v) { return v > 0 && v < 1; }, "a number in (0, 1)", f.rel_tol);
  f.max_iterations = get_int(m, "max_iterations", 1, f.max_iterations);
  f.inner_tolerance = get_number(
      m, "inner_tolerance", [](double v) { return v >= 0 && v < 1; },
      "a number in [0, 1) (relative tolerance of each preconditioner block's inner solve; 0: one "
      "application of the field's preconditioner)",
      f.inner_tolerance);
  // The fluid's velocity on Γ is the structure's: the fluid must hold it (no_slip or velocity).
  bool held = false;
  for (const auto& bc : fluid.boundary_conditions)
    held = held || (bc.boundary == f.interface &&
                    (bc.type == FluidBcType::NoSlip || bc.type == FluidBcType::Velocity));
  if (!held)
    c.fail(m.get("interface").value_or(node), m.key("interface"),
           "the fluid has no no_slip condition on the interface", f.interface,
           "a fields.fluid boundary condition {boundary: " + f.interface +
               ", type: no_slip} (its velocity is then the structure's)");
  return f;
}

}  // namespace biofsi
