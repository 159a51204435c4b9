#include "fluid/parameters.hpp"

#include "io/expression.hpp"

namespace biofsi {

using namespace scene_input;

namespace {

const std::vector<std::pair<std::string, FluidBcType>> kBcTypes = {
    {"velocity", FluidBcType::Velocity},
    {"no_slip", FluidBcType::NoSlip},
    {"slip", FluidBcType::Slip},
    {"pressure", FluidBcType::Pressure},
    {"do_nothing", FluidBcType::DoNothing}};

std::string bc_type_name(FluidBcType t) {
  for (const auto& [name, type] : kBcTypes)
    if (type == t) return name;
  return "?";
}

FluidBcSpec read_boundary_condition(const MapView& typed, int line, const std::string& boundary) {
  const Checker& c = typed.checker();
  FluidBcSpec bc;
  bc.line = line;
  bc.boundary = boundary;
  bc.type = get_enum(typed, "type", kBcTypes, {});
  const bool has_value = bc.type == FluidBcType::Velocity || bc.type == FluidBcType::Pressure;
  if (auto v = typed.get("value")) {
    if (!has_value)
      c.fail(*v, typed.key("value"), "a " + bc_type_name(bc.type) + " condition takes no value",
             render(*v), "no value key");
    if (bc.type == FluidBcType::Velocity) {
      bc.value =
          *get_expression_vector(typed, "value", "a list of 3 expressions (velocity components)");
    } else {
      bc.value[0] = expression(c, *v, typed.key("value"));
    }
  } else if (has_value) {
    typed.missing("value",
                  bc.type == FluidBcType::Velocity ? "a list of 3 expressions" : "an expression",
                  "");
  }
  return bc;
}

}  // namespace

FluidSection read_fluid_section(const MapView& fields, const MeshNames& names) {
  FluidSection section;
  auto node = fields.get("fluid");
  if (!node) return section;
  MapView m(fields.checker(), *node, fields.key("fluid"),
            {"enabled", "blocks", "density", "viscosity", "mode", "initial", "supg", "grad_div",
             "transient_tau", "pseudo_2d", "viscous_form", "preconditioner", "body_force",
             "boundary_conditions"});
  FluidSettings& s = section.settings;
  section.enabled = get_bool(m, "enabled", true);
  s.blocks = block_list(m, "blocks", names.blocks, "the blocks that hold fluid");
  auto positive = [](double v) { return v > 0; };
  s.density = get_number(m, "density", positive, "a number > 0 [mass/mm^3]", std::nullopt);
  s.viscosity =
      get_number(m, "viscosity", positive, "a number > 0 (dynamic) [mass/(mm ms)]", std::nullopt);
  section.mode =
      get_enum(m, "mode", {{"steady", FlowMode::Steady}, {"transient", FlowMode::Transient}},
               std::optional<FlowMode>(section.mode));
  section.initial =
      get_enum(m, "initial", {{"rest", FlowStart::Rest}, {"steady", FlowStart::Steady}},
               std::optional<FlowStart>(section.initial));
  if (section.initial == FlowStart::Steady && section.mode == FlowMode::Steady)
    m.checker().fail(*m.get("initial"), m.key("initial"), "a starting state for a steady flow",
                     "steady",
                     "rest, or mode: transient (the flow then starts from its steady state)");
  s.supg = get_bool(m, "supg", s.supg);
  s.grad_div = get_bool(m, "grad_div", s.grad_div);
  s.transient_tau = get_bool(m, "transient_tau", s.transient_tau);
  s.pseudo_2d = get_bool(m, "pseudo_2d", s.pseudo_2d);
  s.symmetric_viscous = get_enum(m, "viscous_form", {{"symmetric", true}, {"gradient", false}},
                                 std::optional<bool>(s.symmetric_viscous));
  s.preconditioner = get_enum(m, "preconditioner",
                              {{"simple", FluidPreconditioner::Simple},
                               {"simplec", FluidPreconditioner::SimpleC},
                               {"monolithic_amg", FluidPreconditioner::MonolithicAmg},
                               {"direct", FluidPreconditioner::Direct}},
                              std::optional<FluidPreconditioner>(s.preconditioner));
  section.body_force = get_expression_vector(
      m, "body_force", "a list of 3 expressions in x, y, z, t [force per volume]");
  section.boundary_conditions =
      read_boundary_conditions(m, "fluid", names.face_sets, read_boundary_condition);
  return section;
}

FluidVectorFunction fluid_body_force(const FluidSection& section) {
  const auto f = space_time_functions(*section.body_force, "fields.fluid.body_force");
  // The field takes force per unit mass (kernels/fluid/pointwise.hpp).
  const double per_mass = 1 / section.settings.density;
  return [f, per_mass](const Point& x, double t) {
    return Point{per_mass * f[0](x, t), per_mass * f[1](x, t), per_mass * f[2](x, t)};
  };
}

std::vector<std::string> inflow_outflow_boundaries(const FluidSection& section,
                                                   const std::string& interface) {
  std::vector<std::string> out;
  if (!section.enabled) return out;
  for (const FluidBcSpec& bc : section.boundary_conditions) {
    const bool open = bc.type == FluidBcType::Velocity || bc.type == FluidBcType::Pressure ||
                      bc.type == FluidBcType::DoNothing;
    if (open && bc.boundary != interface) out.push_back(bc.boundary);
  }
  return out;
}

std::vector<FluidBoundaryCondition> fluid_boundary_conditions(const FluidSection& section) {
  std::vector<FluidBoundaryCondition> out;
  for (size_t i = 0; i < section.boundary_conditions.size(); ++i) {
    const FluidBcSpec& bc = section.boundary_conditions[i];
    // The scene key of a value, for a message about where it is not finite.
    auto key = [&](int d) {
      const std::string value =
          child_key(index_key("fields.fluid.boundary_conditions", i), "value");
      return (bc.type == FluidBcType::Velocity ? index_key(value, d) : value) + " (line " +
             std::to_string(bc.line) + ")";
    };
    switch (bc.type) {
      case FluidBcType::Velocity:
        out.push_back(fluid_velocity(bc.boundary, space_time_function(bc.value[0], key(0)),
                                     space_time_function(bc.value[1], key(1)),
                                     space_time_function(bc.value[2], key(2))));
        break;
      case FluidBcType::NoSlip:
        out.push_back(fluid_no_slip(bc.boundary));
        break;
      case FluidBcType::Slip:
        out.push_back(fluid_slip(bc.boundary));
        break;
      case FluidBcType::Pressure:
        out.push_back(fluid_pressure(bc.boundary, space_time_function(bc.value[0], key(0))));
        break;
      case FluidBcType::DoNothing:
        out.push_back(fluid_do_nothing(bc.boundary));
        break;
    }
  }
  return out;
}

}  // namespace biofsi
