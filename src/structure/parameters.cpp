#include "structure/parameters.hpp"

#include "io/expression.hpp"

namespace biofsi {

using namespace scene_input;

namespace {

StructureBcSpec read_boundary_condition(const MapView& typed, int line,
                                        const std::string& boundary) {
  const Checker& c = typed.checker();
  StructureBcSpec bc;
  bc.line = line;
  bc.boundary = boundary;
  bc.fixed =
      get_enum(typed, "type", {{"fixed", true}, {"displacement", false}}, std::optional<bool>());
  const std::string expected =
      "a list of 3 expressions (displacement components; \"free\" leaves one free)";
  if (auto v = typed.get("value")) {
    if (bc.fixed)
      c.fail(*v, typed.key("value"), "a fixed condition takes no value", render(*v),
             "no value key");
    if (!v->IsSequence() || v->size() != 3) c.wrong_type(*v, typed.key("value"), expected);
    for (size_t d = 0; d < 3; ++d) {
      const Node comp = (*v)[d];
      bc.value[d] = comp.IsScalar() && comp.Scalar() == "free"
                        ? "free"
                        : expression(c, comp, index_key(typed.key("value"), d));
    }
  } else if (!bc.fixed) {
    typed.missing("value", expected);
  }
  return bc;
}

// Elastic constants of every block in block order; blocks without them get an unused default.
std::vector<StructureMaterial> block_materials(const std::vector<std::string>& blocks,
                                               const Materials& materials) {
  std::vector<StructureMaterial> out;
  for (const auto& name : blocks) {
    const MaterialSpec& m = materials.at(name);
    out.push_back(m.elastic
                      ? StructureMaterial::from_young(m.neo_hooke ? NeoHooke : SaintVenantKirchhoff,
                                                      m.youngs_modulus, m.poisson_ratio, m.density)
                      : StructureMaterial{});
  }
  return out;
}

}  // namespace

StructureSection read_structure_section(const MapView& fields, const MeshNames& names,
                                        const Materials& materials,
                                        const std::vector<std::string>& fluid_blocks) {
  StructureSection section;
  StructureSettings& s = section.settings;
  s.materials = block_materials(names.blocks, materials);
  auto node = fields.get("structure");
  if (!node) return section;
  const Checker& c = fields.checker();
  MapView m(c, *node, fields.key("structure"),
            {"enabled", "blocks", "mode", "plane_strain", "volumetric_integration", "body_force",
             "boundary_conditions"});
  section.enabled = get_bool(m, "enabled", true);
  s.blocks = block_list(m, "blocks", names.blocks, "the elastic blocks");
  for (size_t i = 0; i < s.blocks.size(); ++i) {
    const std::string& b = s.blocks[i];
    const Node at = (*m.get("blocks"))[i];
    const std::string key = index_key(m.key("blocks"), i);
    if (std::find(fluid_blocks.begin(), fluid_blocks.end(), b) != fluid_blocks.end())
      c.fail(at, key, "block '" + b + "' already holds the fluid", b,
             "blocks that are not fields.fluid.blocks");
    if (section.enabled && !materials.at(b).elastic)
      c.fail(at, key, "block '" + b + "' has no elastic constants", b,
             "materials." + b + " with youngs_modulus, poisson_ratio and density");
  }
  s.quasi_static = get_enum(m, "mode", {{"dynamic", false}, {"quasi_static", true}},
                            std::optional<bool>(s.quasi_static));
  s.plane_strain = get_bool(m, "plane_strain", s.plane_strain);
  s.volumetric_integration =
      get_enum(m, "volumetric_integration",
               {{"full", VolumetricIntegration::Full}, {"reduced", VolumetricIntegration::Reduced}},
               std::optional<VolumetricIntegration>(s.volumetric_integration));
  section.body_force = get_expression_vector(
      m, "body_force", "a list of 3 expressions in x, y, z, t [force per volume]");
  section.boundary_conditions =
      read_boundary_conditions(m, "structure", names.face_sets, read_boundary_condition);
  return section;
}

std::array<SpaceTimeFunction, 3> structure_body_force(const StructureSection& section) {
  return space_time_functions(*section.body_force, "fields.structure.body_force");
}

std::vector<StructureDirichlet> structure_boundary_conditions(const StructureSection& section) {
  std::vector<StructureDirichlet> out;
  for (size_t i = 0; i < section.boundary_conditions.size(); ++i) {
    const StructureBcSpec& bc = section.boundary_conditions[i];
    StructureDirichlet d;
    d.set = bc.boundary;
    const std::string value =
        child_key(index_key("fields.structure.boundary_conditions", i), "value");
    for (int c = 0; c < 3; ++c)
      if (bc.fixed)
        d.value[c] = [](const Point&, double) { return 0.0; };
      else if (bc.value[c] != "free")
        d.value[c] = space_time_function(
            bc.value[c], index_key(value, c) + " (line " + std::to_string(bc.line) + ")");
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace biofsi
