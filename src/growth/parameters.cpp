#include "growth/parameters.hpp"

#include <sstream>

namespace biofsi {

using namespace scene_input;

namespace {

// growth.inner_loop against time.steady_tolerance: the stationarity stop needs a tolerance, and a
// fixed count must not have one (it would stop the loop early).
InnerLoop read_inner_loop(const MapView& m, double steady_tolerance) {
  const InnerLoop implied =
      steady_tolerance > 0 ? InnerLoop::UntilStationary : InnerLoop::FixedSteps;
  const InnerLoop loop = get_enum(
      m, "inner_loop",
      {{"fixed_steps", InnerLoop::FixedSteps}, {"until_stationary", InnerLoop::UntilStationary}},
      std::optional<InnerLoop>(implied));
  std::ostringstream tolerance;
  tolerance << steady_tolerance;
  if (loop == InnerLoop::FixedSteps && steady_tolerance > 0)
    m.checker().fail(*m.get("inner_loop"), m.key("inner_loop"),
                     "a fixed step count with time.steady_tolerance " + tolerance.str() +
                         ", which would end it early",
                     "fixed_steps",
                     "no time.steady_tolerance (or 0): the inner loop then runs exactly "
                     "time.steps steps; or inner_loop: until_stationary");
  if (loop == InnerLoop::UntilStationary && !(steady_tolerance > 0))
    m.checker().fail(*m.get("inner_loop"), m.key("inner_loop"),
                     "the stationarity stop without time.steady_tolerance", "until_stationary",
                     "time.steady_tolerance > 0 (the relative change that ends the inner loop); "
                     "or inner_loop: fixed_steps");
  return loop;
}

}  // namespace

GrowthSection read_growth_section(const Checker& c, const Node& node, const MeshNames& names,
                                  const std::vector<std::string>& stacked_blocks,
                                  const MeshMotionSettings& mesh_motion, int inner_steps,
                                  double steady_tolerance) {
  GrowthSection g;
  GrowthSettings& s = g.settings;
  s.mesh_motion = mesh_motion;
  if (!node.IsDefined() || node.IsNull()) return g;
  MapView m(c, node, "growth",
            {"enabled", "interface", "biofilm_block", "k1", "k2", "dt_bio", "steps", "averaging",
             "window", "inner_loop", "reference_update", "output_every", "checkpoint"});
  g.enabled = get_bool(m, "enabled", true);
  s.interface_set =
      boundary_name(c, m.require("interface", "the face set of the biofilm-fluid interface"),
                    m.key("interface"), names.face_sets);
  g.biofilm_block = get_choice(m, "biofilm_block", names.blocks, std::nullopt);
  // The interface's faces belong to the block below it; that block is the one that grows.
  const auto& bs = stacked_blocks;
  for (size_t i = 0; i + 1 < bs.size(); ++i)
    if (s.interface_set == bs[i] + "_" + bs[i + 1] && g.biofilm_block != bs[i])
      c.fail(*m.get("biofilm_block"), m.key("biofilm_block"),
             "the interface's faces belong to block '" + bs[i] + "'", g.biofilm_block,
             "'" + bs[i] + "'");
  auto nonnegative = [](double v) { return v >= 0; };
  s.k1 = get_number(m, "k1", nonnegative,
                    "a number >= 0 [mm per ms per unit flux density] (growth by substrate flux)",
                    std::nullopt);
  s.k2 = get_number(m, "k2", nonnegative, "a number >= 0 (erosion by shear stress)", 0.0);
  s.dt_bio = get_number(
      m, "dt_bio", [](double v) { return v > 0; }, "a finite number > 0 [ms]", std::nullopt);
  g.steps = get_int(m, "steps", 1, std::nullopt);
  g.averaging =
      get_enum(m, "averaging",
               {{"stationary", GrowthAveraging::Stationary}, {"window", GrowthAveraging::Window}},
               std::optional<GrowthAveraging>(g.averaging));
  g.window = get_int(m, "window", 1, g.window);
  if (g.averaging == GrowthAveraging::Window && g.window > inner_steps)
    c.fail(*m.get("window"), m.key("window"), "a window longer than the inner loop",
           std::to_string(g.window),
           "at most time.steps (" + std::to_string(inner_steps) + ") inner steps");
  g.inner_loop = read_inner_loop(m, steady_tolerance);
  g.reference_update = get_enum(
      m, "reference_update", {{"reset", ReferenceUpdate::Reset}, {"keep", ReferenceUpdate::Keep}},
      std::optional<ReferenceUpdate>(g.reference_update));
  g.output_every = get_int(m, "output_every", 1, g.output_every);
  g.checkpoint = get_bool(m, "checkpoint", g.checkpoint);
  return g;
}

}  // namespace biofsi
