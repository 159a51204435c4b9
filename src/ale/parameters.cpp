#include "ale/parameters.hpp"

#include <algorithm>

namespace biofsi {

using namespace scene_input;

MeshMotionSettings read_mesh_motion_section(const Checker& c, const Node& node,
                                            const MeshNames& names) {
  MapView m(c, node, "mesh_motion",
            {"stiffening", "poisson_ratio", "min_quality", "sliding_walls", "fixed_walls",
             "inflow_outflow"});
  MeshMotionSettings s;
  s.stiffening = get_number(
      m, "stiffening", [](double v) { return v >= 0; }, "a number >= 0", s.stiffening);
  s.poisson_ratio = get_number(
      m, "poisson_ratio", [](double v) { return v >= 0 && v < 0.5; }, "a number in [0, 0.5)",
      s.poisson_ratio);
  s.min_quality = get_number(
      m, "min_quality", [](double v) { return v > 0 && v < 1; },
      "a number in (0, 1) (smallest scaled Jacobian)", s.min_quality);
  if (auto n = m.get("sliding_walls"))
    s.sliding_walls = face_set_list(c, *n, m.key("sliding_walls"), names.face_sets);
  if (auto n = m.get("fixed_walls"))
    s.fixed_walls = face_set_list(c, *n, m.key("fixed_walls"), names.face_sets);
  s.inflow_outflow = get_enum(m, "inflow_outflow",
                              {{"fixed", InflowOutflow::Fixed}, {"walls", InflowOutflow::Walls}},
                              std::optional<InflowOutflow>(s.inflow_outflow));
  return s;
}

void hold_inflow_outflow(MeshMotionSettings& settings,
                         const std::vector<std::string>& inflow_outflow_sets) {
  if (settings.inflow_outflow != InflowOutflow::Fixed) return;
  auto& fixed = settings.fixed_walls;
  for (const auto& set : inflow_outflow_sets)
    if (std::find(fixed.begin(), fixed.end(), set) == fixed.end()) fixed.push_back(set);
}

}  // namespace biofsi
