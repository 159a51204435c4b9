#include "scalar/parameters.hpp"

#include "io/expression.hpp"

namespace biofsi {

using namespace scene_input;

namespace {

TransportCoefficients block_coefficients(const std::vector<std::string>& blocks,
                                         const Materials& materials,
                                         const std::vector<std::string>& deforming_blocks) {
  TransportCoefficients k;
  for (size_t b = 0; b < blocks.size(); ++b) {
    const MaterialSpec& m = materials.at(blocks[b]);
    k.diffusivity[b] = m.diffusivity;
    k.monod_rate[b] = m.monod_rate;
    k.monod_half_saturation[b] = m.monod_half_saturation;
    if (std::find(deforming_blocks.begin(), deforming_blocks.end(), blocks[b]) !=
        deforming_blocks.end())
      k.material_motion[b] = 1;  // the deforming biofilm: Phi div u_S (eq. 9)
  }
  return k;
}

ScalarBcSpec read_boundary_condition(const Checker& c, const Node& item, const std::string& ikey,
                                     const std::set<std::string>& face_sets) {
  const std::string map_expected = "a map {boundary, type, ...}";
  if (!item.IsMap()) c.wrong_type(item, ikey, map_expected);
  // The type decides which other keys are allowed, so read it before checking the keys.
  MapView typed(c, item, ikey, {"boundary", "type", "value", "flux", "coefficient", "ambient"});
  ScalarBcSpec bc;
  bc.line = line_of(item, 0);
  bc.kind = get_enum(typed, "type",
                     {{"dirichlet", ScalarBcKind::Dirichlet},
                      {"neumann", ScalarBcKind::Flux},
                      {"robin", ScalarBcKind::Robin}},
                     std::optional<ScalarBcKind>());
  if (bc.kind == ScalarBcKind::Dirichlet) {
    MapView m(c, item, ikey, {"boundary", "type", "value"});
    bc.value = get_expression(m, "value", std::nullopt);
  } else if (bc.kind == ScalarBcKind::Flux) {
    MapView m(c, item, ikey, {"boundary", "type", "flux"});
    bc.value = get_expression(m, "flux", std::nullopt);
  } else {
    MapView m(c, item, ikey, {"boundary", "type", "coefficient", "ambient"});
    bc.coefficient = get_number(
        m, "coefficient", [](double v) { return v >= 0; }, "a number >= 0 [mm/ms]", std::nullopt);
    bc.value = get_expression(m, "ambient", std::nullopt);
  }
  std::vector<std::string> names(face_sets.begin(), face_sets.end());
  const Node b = typed.require("boundary", "a face set of the mesh: " + join_list(names));
  bc.boundary = boundary_name(c, b, typed.key("boundary"), face_sets);
  return bc;
}

}  // namespace

ScalarSection read_scalar_section(const MapView& fields, const MeshNames& names,
                                  const Materials& materials,
                                  const std::vector<std::string>& deforming_blocks,
                                  bool fluid_enabled) {
  ScalarSection section;
  section.settings.coefficients = block_coefficients(names.blocks, materials, deforming_blocks);
  auto node = fields.get("scalar");
  if (!node) return section;
  const Checker& c = fields.checker();
  MapView s(c, *node, fields.key("scalar"),
            {"enabled", "initial", "velocity", "supg", "preconditioner", "boundary_conditions"});
  section.enabled = get_bool(s, "enabled", section.enabled);
  section.initial = get_expression(s, "initial", section.initial);
  if (auto v = s.get("velocity")) {
    if (fluid_enabled)
      c.fail(*v, s.key("velocity"), "a prescribed velocity while the fluid field is on", render(*v),
             "no velocity key: the scalar is convected by the fluid's velocity");
    section.velocity =
        *get_expression_vector(s, "velocity", "a list of 3 expressions (velocity components)");
  }
  section.settings.supg = get_bool(s, "supg", section.settings.supg);
  section.settings.preconditioner =
      get_enum(s, "preconditioner",
               {{"amg", ScalarPreconditioner::Amg}, {"direct", ScalarPreconditioner::Direct}},
               std::optional<ScalarPreconditioner>(section.settings.preconditioner));
  auto bcs = s.get("boundary_conditions");
  if (!bcs || bcs->IsNull()) return section;
  const std::string key = s.key("boundary_conditions");
  if (!bcs->IsSequence()) c.wrong_type(*bcs, key, "a list of boundary conditions");
  OneConditionPerBoundary once("scalar");
  for (size_t i = 0; i < bcs->size(); ++i) {
    const std::string ikey = index_key(key, i);
    const Node item = (*bcs)[i];
    section.boundary_conditions.push_back(read_boundary_condition(c, item, ikey, names.face_sets));
    once.claim(c, item["boundary"], child_key(ikey, "boundary"),
               section.boundary_conditions.back().boundary);
  }
  return section;
}

std::vector<ScalarBoundaryCondition> scalar_boundary_conditions(const ScalarSection& section) {
  std::vector<ScalarBoundaryCondition> out;
  for (size_t i = 0; i < section.boundary_conditions.size(); ++i) {
    const ScalarBcSpec& bc = section.boundary_conditions[i];
    const char* name = bc.kind == ScalarBcKind::Dirichlet ? "value"
                       : bc.kind == ScalarBcKind::Flux    ? "flux"
                                                          : "ambient";
    ScalarBoundaryCondition c;
    c.set = bc.boundary;
    c.kind = bc.kind;
    c.value = space_time_function(
        bc.value, child_key(index_key("fields.scalar.boundary_conditions", i), name) + " (line " +
                      std::to_string(bc.line) + ")");
    c.coefficient = bc.coefficient;
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace biofsi
