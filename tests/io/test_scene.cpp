#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "io/scene.hpp"
#include "scratch_dir.hpp"
#include "tiny_scene.hpp"

namespace biofsi {
namespace {

namespace fs = std::filesystem;

const std::string kFile = "scene.yaml";

// Every key of the schema, none at its default.
const std::string kFull = R"yaml(# a full scene
mesh:
  type: box
  x: [-5, 5]
  z: [-0.1, 0.1]
  nx: 4
  nz: 1
  blocks:
    - name: biofilm
      y: [-5, -3]
      ny: 2
      grading: 1.5
    - name: fluid
      y: [-3, 5]
      ny: 4
materials:
  biofilm:
    diffusivity: 1.0e-4
    monod_rate: 2.0e-4
    monod_half_saturation: 0.1
  fluid:
    diffusivity: 2.0e-3
fields:
  scalar:
    enabled: false
    initial: "0.5 + 0.5*cos(0.2*_pi*x)"
    velocity: ["0.1*y", "0", 0]
    supg: false
    boundary_conditions:
      - {boundary: top, type: dirichlet, value: "0.5 + 0.5*cos(0.2*_pi*x)"}
      - {boundary: left, type: neumann, flux: "0"}
      - {boundary: right, type: robin, coefficient: 2.5, ambient: "0.3"}
time:
  mode: transient
  dt: 0.5
  steps: 10
  theta: 0.75
  steady_tolerance: 1.0e-8
solver:
  newton: {rel_tol: 1e-9, abs_tol: 1e-12, max_iterations: 30}
  linear: {rel_tol: 1e-7, max_iterations: 400, restart: 40}
  scatter: atomic
  reuse_preconditioner: false
output:
  directory: results
  every: 2
  flux_boundaries: [biofilm_fluid, bottom]
)yaml";

// Only the required keys.
const std::string kMinimal = test::kTinyBoxScene + R"yaml(time:
  dt: 1.0
  steps: 3
)yaml";

// `text` with the single occurrence of `from` replaced by `to`.
std::string replaced(const std::string& text, const std::string& from, const std::string& to) {
  const size_t p = text.find(from);
  EXPECT_NE(p, std::string::npos) << "'" << from << "' not in the scene";
  EXPECT_EQ(text.find(from, p + 1), std::string::npos) << "'" << from << "' is not unique";
  if (p == std::string::npos) return text;
  return text.substr(0, p) + to + text.substr(p + from.size());
}

// 1-based line of the first occurrence of `marker`.
int line_of(const std::string& text, const std::string& marker) {
  const size_t p = text.find(marker);
  EXPECT_NE(p, std::string::npos) << "'" << marker << "' not in the scene";
  return 1 +
         static_cast<int>(std::count(text.begin(), text.begin() + std::min(p, text.size()), '\n'));
}

std::string error_of(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    parse_scene(text, kFile, overrides);
  } catch (const SceneError& e) {
    return e.what();
  }
  ADD_FAILURE() << "the scene was accepted";
  return "";
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

// The message names file and line, the dotted key, the offending value and the expectation.
void expect_error(const std::string& text, int line, const std::string& key,
                  const std::string& value, const std::string& expected,
                  const std::vector<std::string>& overrides = {}) {
  const std::string m = error_of(text, overrides);
  EXPECT_EQ(m.rfind(kFile + ":" + std::to_string(line) + ": ", 0), 0u) << m;
  EXPECT_TRUE(contains(m, ": " + key + ": ")) << m;
  if (!value.empty()) {
    EXPECT_TRUE(contains(m, "got '" + value + "'")) << m;
  }
  EXPECT_TRUE(contains(m, "expected " + expected)) << m;
}

TEST(Scene, ParsesEveryValueOfAFullScene) {
  const Scene s = parse_scene(kFull, kFile);
  EXPECT_EQ(s.file, kFile);
  EXPECT_EQ(s.box.x0, -5);
  EXPECT_EQ(s.box.x1, 5);
  EXPECT_EQ(s.box.z0, -0.1);
  EXPECT_EQ(s.box.z1, 0.1);
  EXPECT_EQ(s.box.nx, 4);
  EXPECT_EQ(s.box.nz, 1);
  ASSERT_EQ(s.box.blocks.size(), 2u);
  EXPECT_EQ(s.box.blocks[0].name, "biofilm");
  EXPECT_EQ(s.box.blocks[0].y0, -5);
  EXPECT_EQ(s.box.blocks[0].y1, -3);
  EXPECT_EQ(s.box.blocks[0].ny, 2);
  EXPECT_EQ(s.box.blocks[0].grading, 1.5);
  EXPECT_EQ(s.box.blocks[1].name, "fluid");
  EXPECT_EQ(s.box.blocks[1].y0, -3);
  EXPECT_EQ(s.box.blocks[1].y1, 5);
  EXPECT_EQ(s.box.blocks[1].ny, 4);
  EXPECT_EQ(s.box.blocks[1].grading, 1.0);

  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials.at("biofilm").diffusivity, 1.0e-4);
  EXPECT_EQ(s.materials.at("biofilm").monod_rate, 2.0e-4);
  EXPECT_EQ(s.materials.at("biofilm").monod_half_saturation, 0.1);
  EXPECT_EQ(s.materials.at("fluid").diffusivity, 2.0e-3);
  EXPECT_EQ(s.materials.at("fluid").monod_rate, 0);

  EXPECT_FALSE(s.scalar.enabled);
  EXPECT_EQ(s.scalar.initial, "0.5 + 0.5*cos(0.2*_pi*x)");
  EXPECT_EQ(s.scalar.velocity, (std::array<std::string, 3>{"0.1*y", "0", "0"}));
  EXPECT_FALSE(s.scalar.settings.supg);
  const auto& bcs = s.scalar.boundary_conditions;
  ASSERT_EQ(bcs.size(), 3u);
  EXPECT_EQ(bcs[0].boundary, "top");
  EXPECT_EQ(bcs[0].kind, ScalarBcKind::Dirichlet);
  EXPECT_EQ(bcs[0].value, "0.5 + 0.5*cos(0.2*_pi*x)");
  EXPECT_EQ(bcs[0].line, line_of(kFull, "{boundary: top"));
  EXPECT_EQ(bcs[1].boundary, "left");
  EXPECT_EQ(bcs[1].kind, ScalarBcKind::Flux);
  EXPECT_EQ(bcs[1].value, "0");
  EXPECT_EQ(bcs[2].boundary, "right");
  EXPECT_EQ(bcs[2].kind, ScalarBcKind::Robin);
  EXPECT_EQ(bcs[2].coefficient, 2.5);
  EXPECT_EQ(bcs[2].value, "0.3");
  EXPECT_EQ(bcs[2].line, line_of(kFull, "{boundary: right"));

  EXPECT_EQ(s.time.mode, TimeMode::Transient);
  EXPECT_EQ(s.time.dt, 0.5);
  EXPECT_EQ(s.time.steps, 10);
  EXPECT_EQ(s.time.theta, 0.75);
  EXPECT_EQ(s.time.steady_tolerance, 1.0e-8);

  EXPECT_EQ(s.solver.newton_rel_tol, 1e-9);
  EXPECT_EQ(s.solver.newton_abs_tol, 1e-12);
  EXPECT_EQ(s.solver.newton_max_iterations, 30);
  EXPECT_EQ(s.solver.linear_rel_tol, 1e-7);
  EXPECT_EQ(s.solver.linear_max_iterations, 400);
  EXPECT_EQ(s.solver.linear_restart, 40);
  EXPECT_EQ(s.solver.scatter, Scatter::Atomic);
  EXPECT_FALSE(s.solver.reuse_preconditioner);
  // One key for every field's Newton and the coupling's.
  EXPECT_FALSE(s.scalar.settings.newton.reuse_preconditioner);

  EXPECT_EQ(s.output.directory, "results");
  EXPECT_EQ(s.output.every, 2);
  EXPECT_EQ(s.output.flux_boundaries, (std::vector<std::string>{"biofilm_fluid", "bottom"}));
}

TEST(Scene, AppliesDefaultsWhenOptionalKeysAreAbsent) {
  const Scene s = parse_scene(kMinimal, kFile);
  const Scene d;
  ASSERT_EQ(s.box.blocks.size(), 1u);
  EXPECT_EQ(s.box.blocks[0].grading, 1.0);
  EXPECT_EQ(s.materials.at("fluid").monod_rate, 0);
  EXPECT_EQ(s.scalar.enabled, d.scalar.enabled);
  EXPECT_EQ(s.scalar.initial, "0");
  EXPECT_EQ(s.scalar.velocity, d.scalar.velocity);
  EXPECT_EQ(s.scalar.settings.supg, d.scalar.settings.supg);
  EXPECT_TRUE(s.scalar.boundary_conditions.empty());
  EXPECT_EQ(s.time.mode, TimeMode::Transient);
  EXPECT_EQ(s.time.theta, d.time.theta);
  EXPECT_EQ(s.time.steady_tolerance, d.time.steady_tolerance);
  EXPECT_EQ(s.solver.newton_rel_tol, d.solver.newton_rel_tol);
  EXPECT_EQ(s.solver.newton_abs_tol, d.solver.newton_abs_tol);
  EXPECT_EQ(s.solver.newton_max_iterations, d.solver.newton_max_iterations);
  EXPECT_EQ(s.solver.linear_rel_tol, d.solver.linear_rel_tol);
  EXPECT_EQ(s.solver.linear_max_iterations, d.solver.linear_max_iterations);
  EXPECT_EQ(s.solver.linear_restart, d.solver.linear_restart);
  EXPECT_EQ(s.solver.scatter, Scatter::Colored);
  EXPECT_TRUE(s.solver.reuse_preconditioner);
  EXPECT_TRUE(s.scalar.settings.newton.reuse_preconditioner);
  EXPECT_EQ(s.output.directory, d.output.directory);
  EXPECT_EQ(s.output.every, 1);
  EXPECT_TRUE(s.output.flux_boundaries.empty());
}

TEST(Scene, SteadyModeNeedsNoTimeStep) {
  const std::string text = replaced(kMinimal, "  dt: 1.0\n  steps: 3\n", "  mode: steady\n");
  const Scene s = parse_scene(text, kFile);
  EXPECT_EQ(s.time.mode, TimeMode::Steady);
}

TEST(Scene, RejectsAnUnknownTopLevelKey) {
  const std::string text = kFull + "colour: blue\n";
  expect_error(text, line_of(text, "colour"), "colour", "colour", "one of mesh, materials");
}

TEST(Scene, RejectsAnUnknownNestedKey) {
  const std::string text = replaced(kFull, "  steps: 10\n", "  steps: 10\n  dtt: 1\n");
  expect_error(text, line_of(text, "dtt"), "time.dtt", "dtt", "one of mode, dt, steps");
  const std::string bc = replaced(kFull, "flux: \"0\"}", "flux: \"0\", value: \"1\"}");
  expect_error(bc, line_of(bc, "{boundary: left"), "fields.scalar.boundary_conditions[1].value",
               "value", "one of boundary, type, flux");
}

TEST(Scene, RejectsAStringWhereANumberIsExpected) {
  const std::string text = replaced(kFull, "dt: 0.5", "dt: fast");
  expect_error(text, line_of(text, "dt: fast"), "time.dt", "fast", "a finite number > 0");
  // Quoting makes a string even of digits: no silent conversion.
  const std::string quoted = replaced(kFull, "dt: 0.5", "dt: \"0.5\"");
  expect_error(quoted, line_of(quoted, "dt: "), "time.dt", "0.5", "a finite number > 0");
}

TEST(Scene, RejectsAMapWhereAListIsExpected) {
  const std::string text =
      replaced(kFull, "flux_boundaries: [biofilm_fluid, bottom]", "flux_boundaries: {a: 1}");
  expect_error(text, line_of(text, "flux_boundaries"), "output.flux_boundaries", "{a: 1}",
               "a list of face set names");
  const std::string blocks =
      replaced(kMinimal, "    - {name: fluid, y: [0, 1], ny: 2}", "    name: fluid");
  expect_error(blocks, line_of(blocks, "name: fluid"), "mesh.blocks", "{name: fluid}",
               "a list of 1 to 8 blocks");
}

TEST(Scene, RejectsAFloatWhereAnIntegerIsExpected) {
  const std::string text = replaced(kFull, "nx: 4", "nx: 4.0");
  expect_error(text, line_of(text, "nx: 4.0"), "mesh.nx", "4.0", "an integer >= 1");
}

TEST(Scene, RejectsANonBooleanFlag) {
  const std::string text = replaced(kFull, "supg: false", "supg: maybe");
  expect_error(text, line_of(text, "supg"), "fields.scalar.supg", "maybe", "true or false");
}

TEST(Scene, RejectsAMissingRequiredKeyAtItsParentsLine) {
  const std::string text = replaced(kFull, "  dt: 0.5\n", "");
  const std::string m = error_of(text);
  expect_error(text, line_of(text, "mode: transient"), "time.dt", "", "a finite number > 0");
  EXPECT_TRUE(contains(m, "missing required key")) << m;
  const std::string ny = replaced(kFull, "      ny: 4\n", "");
  expect_error(ny, line_of(ny, "name: fluid"), "mesh.blocks[1].ny", "", "an integer >= 1");
  const std::string time = replaced(kMinimal, "time:\n  dt: 1.0\n  steps: 3\n", "");
  expect_error(time, 1, "time", "", "a map");
}

TEST(Scene, RejectsANegativeDiffusivity) {
  const std::string text = replaced(kFull, "diffusivity: 1.0e-4", "diffusivity: -1.0e-4");
  expect_error(text, line_of(text, "-1.0e-4"), "materials.biofilm.diffusivity", "-1.0e-4",
               "a number > 0");
}

TEST(Scene, RejectsANonPositiveTimeStep) {
  for (const std::string dt : {"0", "-0.5", ".inf"}) {
    const std::string text = replaced(kFull, "dt: 0.5", "dt: " + dt);
    expect_error(text, line_of(text, "dt: "), "time.dt", dt, "a finite number > 0");
  }
}

TEST(Scene, RejectsThetaOutsideHalfToOne) {
  for (const std::string theta : {"0.4", "1.2"}) {
    const std::string text = replaced(kFull, "theta: 0.75", "theta: " + theta);
    expect_error(text, line_of(text, "theta"), "time.theta", theta, "a number in [0.5, 1]");
  }
  EXPECT_EQ(parse_scene(replaced(kFull, "theta: 0.75", "theta: 0.5"), kFile).time.theta, 0.5);
  EXPECT_EQ(parse_scene(replaced(kFull, "theta: 0.75", "theta: 1"), kFile).time.theta, 1.0);
}

TEST(Scene, RejectsZeroSteps) {
  const std::string text = replaced(kFull, "steps: 10", "steps: 0");
  expect_error(text, line_of(text, "steps: 0"), "time.steps", "0", "an integer >= 1");
}

TEST(Scene, RejectsBlocksThatAreNotContiguous) {
  const std::string text = replaced(kFull, "y: [-3, 5]", "y: [-2.5, 5]");
  expect_error(text, line_of(text, "y: [-2.5, 5]"), "mesh.blocks[1].y", "[-2.5, 5]",
               "y0 = -3 (where block 'biofilm' ends)");
}

TEST(Scene, RejectsABlockWithoutMaterial) {
  const std::string text = replaced(kFull, "  fluid:\n    diffusivity: 2.0e-3\n", "");
  const std::string m = error_of(text);
  expect_error(text, line_of(text, "  biofilm:\n    diffusivity"), "materials.fluid", "",
               "a map with diffusivity");
  EXPECT_TRUE(contains(m, "missing required key")) << m;
}

TEST(Scene, RejectsAMaterialForAnUnknownBlock) {
  const std::string text = replaced(kFull, "    diffusivity: 2.0e-3\n",
                                    "    diffusivity: 2.0e-3\n  sludge: {diffusivity: 1}\n");
  expect_error(text, line_of(text, "sludge"), "materials.sludge", "sludge",
               "one of the blocks biofilm, fluid");
}

TEST(Scene, RejectsAnUnknownBoundaryName) {
  const std::string text = replaced(kFull, "boundary: top", "boundary: roof");
  expect_error(text, line_of(text, "roof"), "fields.scalar.boundary_conditions[0].boundary", "roof",
               "a face set of the mesh: ");
  EXPECT_TRUE(contains(error_of(text), "biofilm_fluid")) << "the message lists the names";
  const std::string flux = replaced(kFull, "[biofilm_fluid, bottom]", "[biofilm_fluid, floor]");
  expect_error(flux, line_of(flux, "floor"), "output.flux_boundaries[1]", "floor",
               "a face set of the mesh: ");
}

TEST(Scene, RejectsAnUnknownBoundaryConditionType) {
  const std::string text = replaced(kFull, "type: neumann", "type: newman");
  expect_error(text, line_of(text, "newman"), "fields.scalar.boundary_conditions[1].type", "newman",
               "one of dirichlet, neumann, robin");
}

TEST(Scene, RejectsAnExpressionWithASyntaxError) {
  const std::string text =
      replaced(kFull, "initial: \"0.5 + 0.5*cos(0.2*_pi*x)\"", "initial: \"0.5 + *x\"");
  expect_error(text, line_of(text, "initial"), "fields.scalar.initial", "0.5 + *x",
               "an expression in x, y, z, t");
  const std::string value =
      replaced(kFull, "value: \"0.5 + 0.5*cos(0.2*_pi*x)\"}", "value: \"cos(x\"}");
  expect_error(value, line_of(value, "cos(x\""), "fields.scalar.boundary_conditions[0].value",
               "cos(x", "an expression in x, y, z, t");
}

TEST(Scene, RejectsAnExpressionWithAnUnknownVariable) {
  const std::string text = replaced(kFull, "[\"0.1*y\", \"0\", 0]", "[\"0.1*w\", \"0\", 0]");
  expect_error(text, line_of(text, "velocity"), "fields.scalar.velocity[0]", "0.1*w",
               "an expression in x, y, z, t");
  EXPECT_TRUE(contains(error_of(text), "unknown variable 'w'")) << error_of(text);
}

TEST(Scene, RejectsAMonodRateWithoutHalfSaturation) {
  const std::string text = replaced(kFull, "    monod_half_saturation: 0.1\n", "");
  const std::string m = error_of(text);
  expect_error(text, line_of(text, "diffusivity: 1.0e-4"),
               "materials.biofilm.monod_half_saturation", "", "a number > 0");
  EXPECT_TRUE(contains(m, "monod_rate > 0")) << m;
}

TEST(Scene, RejectsAnUnknownScatterPolicy) {
  const std::string text = replaced(kFull, "scatter: atomic", "scatter: greedy");
  expect_error(text, line_of(text, "greedy"), "solver.scatter", "greedy", "one of colored, atomic");
  const std::string reuse =
      replaced(kFull, "reuse_preconditioner: false", "reuse_preconditioner: 1");
  expect_error(reuse, line_of(reuse, "reuse_preconditioner"), "solver.reuse_preconditioner", "1",
               "true or false");
}

TEST(Scene, RejectsDuplicateKeys) {
  const std::string text = replaced(kFull, "  steps: 10\n", "  steps: 10\n  dt: 2\n");
  expect_error(text, line_of(text, "dt: 2"), "time.dt", "dt", "each key once");
}

TEST(Scene, RejectsBlockNamesWhoseFaceSetsCollide) {
  // "a" below "left": the interface "a_left" would merge with a's left side.
  const std::string text =
      replaced(kMinimal, "    - {name: fluid, y: [0, 1], ny: 2}",
               "    - {name: a, y: [0, 1], ny: 2}\n    - {name: left, y: [1, 2], ny: 2}");
  const std::string m = error_of(text);
  EXPECT_TRUE(contains(m, "a_left")) << m;
}

TEST(Scene, ReportsAYamlSyntaxErrorWithItsLine) {
  const std::string text = replaced(kFull, "  steps: 10\n", "  steps: [10\n");
  const std::string m = error_of(text);
  EXPECT_EQ(m.rfind(kFile + ":", 0), 0u) << m;
  EXPECT_TRUE(contains(m, "YAML syntax error")) << m;
  const std::string tab = replaced(kFull, "  nz: 1\n", "  nz: 1\n nz2: x: y\n");
  const std::string t = error_of(tab);
  EXPECT_EQ(t.rfind(kFile + ":" + std::to_string(line_of(tab, "nz2")) + ":", 0), 0u) << t;
}

class SceneFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratch_dir("test_scene");
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  fs::path dir_;
};

TEST_F(SceneFile, LoadsAFileAndNamesItInMessages) {
  const std::string path = write("full.yaml", kFull);
  EXPECT_EQ(load_scene(path).file, path);
  EXPECT_EQ(load_scene(path, {"time.dt=0.125"}).time.dt, 0.125);
  const std::string bad = write("bad.yaml", replaced(kFull, "steps: 10", "steps: 0"));
  try {
    load_scene(bad);
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(bad + ":" + std::to_string(line_of(kFull, "steps")), 0),
              0u)
        << e.what();
  }
}

TEST_F(SceneFile, ReportsAMissingFile) {
  const std::string path = (dir_ / "nope.yaml").string();
  try {
    load_scene(path);
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_TRUE(contains(e.what(), path)) << e.what();
    EXPECT_TRUE(contains(e.what(), "cannot read")) << e.what();
  }
  EXPECT_THROW(load_scene(dir_.string()), SceneError);
}

// A path that is not a regular file (it could be read forever) and a file too large to be a scene
// are refused before anything is parsed, with the size they have.
TEST_F(SceneFile, RefusesDevicesAndFilesLargerThanTheLimit) {
  try {
    load_scene("/dev/zero");
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), "/dev/zero: cannot read the scene file: not a regular file");
  }
  const std::string big = write("big.yaml", kMinimal);
  std::ofstream(big, std::ios::app) << std::string(kMaxSceneBytes, '#');
  try {
    load_scene(big);
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_TRUE(contains(e.what(), big + ": the scene file is larger than 16777216 bytes (" +
                                       std::to_string(fs::file_size(big)) + ")"))
        << e.what();
  }
}

// A box larger than memory is refused when the scene is read, with the node count it asked for
// (1.2e9 nodes of at least 2 kB each: more than any machine these tests run on).
TEST(Scene, RefusesABoxMeshThatDoesNotFitInMemory) {
  const std::string m = error_of(kMinimal, {"mesh.nx=20000", "mesh.nz=20000"});
  EXPECT_TRUE(contains(m, "mesh: the mesh does not fit in memory: 1200120003 nodes need at least"))
      << m;
  EXPECT_TRUE(contains(m, "got '1200120003 nodes'")) << m;
  // The issue's nx = 1e8 (written as an integer; 1e8 itself is not one).
  EXPECT_TRUE(contains(error_of(kMinimal, {"mesh.nx=100000000"}), "got '600000006 nodes'"));
  EXPECT_TRUE(contains(error_of(kMinimal, {"mesh.nx=1e8"}), "not an integer"));
}

// A Gmsh mesh: the file is found next to the scene, read during validation, and its block and set
// names are what the rest of the scene is checked against.
TEST_F(SceneFile, ReadsAGmshMeshRelativeToTheSceneFile) {
  fs::copy_file(std::string(BIOFSI_MESH_DIR) + "/dfg_2d1_r1.msh", dir_ / "channel.msh");
  const std::string gmsh_mesh = "mesh:\n  type: gmsh\n  file: channel.msh\n  thickness: 0.01\n";
  const std::string minimal_tail = kMinimal.substr(kMinimal.find("materials:"));
  const std::string with_flux = minimal_tail + "output:\n  flux_boundaries: [cylinder]\n";
  const std::string path = write("channel.yaml", gmsh_mesh + with_flux);
  const Scene s = load_scene(path);
  EXPECT_EQ(s.mesh_type, "gmsh");
  EXPECT_EQ(s.gmsh_file, (dir_ / "channel.msh").lexically_normal().string());
  EXPECT_EQ(s.gmsh_thickness, 0.01);
  EXPECT_EQ(s.block_names, std::vector<std::string>{"fluid"});
  const Mesh mesh = make_scene_mesh(s);
  EXPECT_TRUE(mesh.face_sets.count("cylinder"));
  EXPECT_GT(mesh.n_elements(), 1000);

  auto error = [&](const std::string& text) {
    try {
      load_scene(write("bad.yaml", text));
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  // A set the mesh does not have.
  const std::string unknown =
      error(gmsh_mesh + minimal_tail + "output:\n  flux_boundaries: [top]\n");
  EXPECT_TRUE(contains(unknown, "output.flux_boundaries[0]: unknown boundary; got 'top'"))
      << unknown;
  EXPECT_TRUE(contains(unknown, "cylinder")) << unknown;
  // A 2-D mesh without a thickness: the reader's message, under the key that names the file.
  const std::string thin = error(replaced(gmsh_mesh, "  thickness: 0.01\n", "") + minimal_tail);
  EXPECT_TRUE(contains(thin, "bad.yaml:3: mesh.file: cannot use the mesh")) << thin;
  EXPECT_TRUE(contains(thin, "needs a thickness > 0")) << thin;
  // A missing file and a box key under a gmsh mesh.
  const std::string missing = error(replaced(gmsh_mesh, "channel.msh", "nope.msh") + minimal_tail);
  EXPECT_TRUE(contains(missing, "mesh.file: cannot use the mesh")) << missing;
  EXPECT_TRUE(contains(missing, "got 'nope.msh'")) << missing;
  const std::string mixed = error(gmsh_mesh + "  nx: 3\n" + minimal_tail);
  EXPECT_TRUE(contains(mixed, "mesh.nx: not a key of a gmsh mesh")) << mixed;
  // keep_blocks: only the blocks named (here the file's one block), and none it does not have.
  const Scene kept =
      load_scene(write("kept.yaml", gmsh_mesh + "  keep_blocks: [fluid]\n" + with_flux));
  EXPECT_EQ(kept.gmsh_keep_blocks, std::vector<std::string>{"fluid"});
  EXPECT_EQ(make_scene_mesh(kept).n_elements(), mesh.n_elements());
  const std::string unknown_block = error(gmsh_mesh + "  keep_blocks: [solid]\n" + minimal_tail);
  EXPECT_TRUE(contains(unknown_block, "mesh.keep_blocks[0]: unknown block; got 'solid'"))
      << unknown_block;
  // On a two-block mesh: the flag alone of Turek-Hron, its sets restricted to it.
  Scene flag;
  flag.mesh_type = "gmsh";
  flag.gmsh_file = std::string(BIOFSI_MESH_DIR) + "/turek_hron_r1.msh";
  flag.gmsh_thickness = 0.01;
  flag.gmsh_keep_blocks = {"solid"};
  const Mesh solid = make_scene_mesh(flag);
  EXPECT_EQ(solid.block_names, std::vector<std::string>{"solid"});
  EXPECT_TRUE(solid.face_sets.count("solid_clamp"));
  EXPECT_FALSE(solid.face_sets.count("inflow"));
  EXPECT_LT(solid.n_elements(), make_scene_mesh(flag, nullptr, false).n_elements());
}

// The fluid section: every key read, the scalar then convected by the fluid (no velocity key).
const std::string kFluid = R"yaml(  fluid:
    blocks: [fluid]
    density: 1.0e-3
    viscosity: 1.0e-3
    mode: transient
    initial: steady
    supg: false
    grad_div: false
    transient_tau: false
    pseudo_2d: true
    viscous_form: gradient
    preconditioner: simplec
    boundary_conditions:
      - {boundary: left, type: velocity, value: ["0.0375 + 0.0125*y", 0, 0]}
      - {boundary: biofilm_fluid, type: no_slip}
      - {boundary: top, type: slip}
      - {boundary: right, type: do_nothing}
      - {boundary: bottom, type: pressure, value: "1 + t"}
)yaml";

std::string with_fluid(const std::string& scene) {
  const std::string no_velocity = replaced(scene, "    velocity: [\"0.1*y\", \"0\", 0]\n", "");
  return replaced(no_velocity, "fields:\n", "fields:\n" + kFluid);
}

TEST(Scene, ReadsTheFluidField) {
  const Scene s = parse_scene(with_fluid(kFull), kFile);
  const FluidSettings& f = s.fluid.settings;
  EXPECT_TRUE(s.fluid.enabled);
  EXPECT_EQ(f.blocks, std::vector<std::string>{"fluid"});
  EXPECT_EQ(f.density, 1e-3);
  EXPECT_EQ(f.viscosity, 1e-3);
  EXPECT_EQ(s.fluid.mode, FlowMode::Transient);
  EXPECT_EQ(s.fluid.initial, FlowStart::Steady);
  EXPECT_FALSE(f.supg);
  EXPECT_FALSE(f.grad_div);
  EXPECT_FALSE(f.transient_tau);
  EXPECT_TRUE(f.pseudo_2d);
  EXPECT_FALSE(f.symmetric_viscous);
  EXPECT_EQ(f.preconditioner, FluidPreconditioner::SimpleC);
  const auto& fbcs = s.fluid.boundary_conditions;
  ASSERT_EQ(fbcs.size(), 5u);
  EXPECT_EQ(fbcs[0].type, FluidBcType::Velocity);
  EXPECT_EQ(fbcs[0].value[0], "0.0375 + 0.0125*y");
  EXPECT_EQ(fbcs[1].boundary, "biofilm_fluid");
  EXPECT_EQ(fbcs[1].type, FluidBcType::NoSlip);
  EXPECT_EQ(fbcs[4].value[0], "1 + t");
  EXPECT_EQ(fbcs[2].line, line_of(with_fluid(kFull), "type: slip"));
  EXPECT_FALSE(parse_scene(kFull, kFile).fluid.enabled);
  // Defaults: the symmetric viscous form of eq. 2 and SIMPLE (the measured best).
  const Scene d =
      parse_scene(replaced(replaced(with_fluid(kFull), "    viscous_form: gradient\n", ""),
                           "    preconditioner: simplec\n", ""),
                  kFile);
  EXPECT_TRUE(d.fluid.settings.symmetric_viscous);
  EXPECT_EQ(d.fluid.settings.preconditioner, FluidPreconditioner::Simple);
  EXPECT_EQ(
      parse_scene(replaced(with_fluid(kFull), "    initial: steady\n", ""), kFile).fluid.initial,
      FlowStart::Rest);
}

TEST(Scene, RejectsBadFluidInput) {
  const std::string good = with_fluid(kFull);
  expect_error(replaced(good, "blocks: [fluid]", "blocks: [water]"),
               line_of(good, "blocks: [fluid]"), "fields.fluid.blocks[0]", "water",
               "a list of the blocks that hold fluid: one or more of");
  expect_error(replaced(good, "viscosity: 1.0e-3", "viscosity: 0"), line_of(good, "viscosity:"),
               "fields.fluid.viscosity", "0", "a number > 0");
  expect_error(replaced(good, "type: no_slip}", "type: no_slip, value: 1}"),
               line_of(good, "type: no_slip"), "fields.fluid.boundary_conditions[1].value", "1",
               "no value key");
  expect_error(replaced(good, "value: \"1 + t\"", "value: \"1 + q\""), line_of(good, "1 + t"),
               "fields.fluid.boundary_conditions[4].value", "1 + q", "an expression");
  expect_error(replaced(good, "type: slip", "type: sliding"), line_of(good, "type: slip"),
               "fields.fluid.boundary_conditions[2].type", "sliding", "one of");
  expect_error(replaced(good, "initial: steady", "initial: developed"),
               line_of(good, "initial: steady"), "fields.fluid.initial", "developed", "one of");
  // A steady flow has no starting state to choose.
  expect_error(replaced(good, "mode: transient\n    initial", "mode: steady\n    initial"),
               line_of(good, "initial: steady"), "fields.fluid.initial", "steady",
               "rest, or mode: transient");
  // A prescribed scalar velocity would silently lose against the fluid's.
  const std::string both = replaced(kFull, "fields:\n", "fields:\n" + kFluid);
  expect_error(both, line_of(both, "velocity: [\"0.1"), "fields.scalar.velocity", "",
               "no velocity key: the scalar is convected by the fluid's velocity");
}

// Two conditions of one field on one boundary: refused at the second, naming the first (which of
// them held was not what the scene said).
TEST(Scene, RejectsTwoConditionsOfAFieldOnOneBoundary) {
  const std::string twice =
      replaced(kFull, "      - {boundary: left, type: neumann, flux: \"0\"}\n",
               "      - {boundary: top, type: dirichlet, value: \"1\"}\n");
  expect_error(twice, line_of(twice, "value: \"1\"}"),
               "fields.scalar.boundary_conditions[1].boundary", "top",
               "each boundary once in a field's boundary_conditions");
  EXPECT_TRUE(
      contains(error_of(twice), "(the first is fields.scalar.boundary_conditions[0].boundary)"))
      << error_of(twice);
  const std::string good = with_fluid(kFull);
  const std::string fluid_twice =
      replaced(good, "{boundary: top, type: slip}", "{boundary: left, type: no_slip}");
  expect_error(fluid_twice, line_of(fluid_twice, "{boundary: left, type: no_slip}"),
               "fields.fluid.boundary_conditions[2].boundary", "left",
               "each boundary once in a field's boundary_conditions");
}

TEST(SceneOverrides, ChangeValuesIncludingListEntries) {
  const Scene s = parse_scene(
      kFull, kFile,
      {"time.dt=0.25", "mesh.blocks.1.ny=40", "mesh.blocks[0].grading=2", "fields.scalar.supg=true",
       R"(fields.scalar.velocity=["1", 0, "t"])", "fields.scalar.boundary_conditions.0.value=0.75",
       "output.flux_boundaries.1=top", "solver.newton.max_iterations=7", "time.mode = steady"});
  EXPECT_EQ(s.time.dt, 0.25);
  EXPECT_EQ(s.box.blocks[1].ny, 40);
  EXPECT_EQ(s.box.blocks[0].grading, 2.0);
  EXPECT_TRUE(s.scalar.settings.supg);
  EXPECT_EQ(s.scalar.velocity, (std::array<std::string, 3>{"1", "0", "t"}));
  EXPECT_EQ(s.scalar.boundary_conditions[0].value, "0.75");
  EXPECT_EQ(s.output.flux_boundaries, (std::vector<std::string>{"biofilm_fluid", "top"}));
  EXPECT_EQ(s.solver.newton_max_iterations, 7);
  EXPECT_EQ(s.time.mode, TimeMode::Steady);
  EXPECT_EQ(s.time.steps, 10);  // untouched
}

TEST(SceneOverrides, LaterOverridesWin) {
  EXPECT_EQ(parse_scene(kFull, kFile, {"time.dt=0.25", "time.dt=2"}).time.dt, 2.0);
}

TEST(SceneOverrides, CreateMissingMaps) {
  const Scene s = parse_scene(
      kMinimal, kFile,
      {"solver.linear.restart=10", "fields.scalar.initial=x*y", "output.directory=elsewhere"});
  EXPECT_EQ(s.solver.linear_restart, 10);
  EXPECT_EQ(s.scalar.initial, "x*y");
  EXPECT_EQ(s.output.directory, "elsewhere");
}

TEST(SceneOverrides, AreValidatedLikeTheFileAndNamedInMessages) {
  const std::string m = error_of(kFull, {"time.dt=-1"});
  expect_error(kFull, line_of(kFull, "dt: 0.5"), "time.dt", "-1", "a finite number > 0",
               {"time.dt=-1"});
  EXPECT_TRUE(contains(m, "--set time.dt=-1")) << m;
  const std::string unknown = error_of(kFull, {"time.foo=1"});
  EXPECT_TRUE(contains(unknown, "time.foo: unknown key")) << unknown;
  EXPECT_TRUE(contains(unknown, "--set time.foo=1")) << unknown;
  const std::string created = error_of(kMinimal, {"materials.sludge.diffusivity=1"});
  EXPECT_TRUE(contains(created, "materials.sludge")) << created;
  EXPECT_TRUE(contains(created, "--set materials.sludge.diffusivity=1")) << created;
}

TEST(SceneOverrides, RejectMalformedOverridesNamingThem) {
  for (const std::string bad :
       {"time.dt", "=1", " =1", "time..dt=1", "mesh.blocks.5.ny=3", "mesh.blocks[2].ny=3",
        "time.dt.x=1", "mesh.blocks.first.ny=1", "time[0]=1", "time.dt=[1", "mesh.nx[0]=1"}) {
    const std::string m = error_of(kFull, {bad});
    EXPECT_EQ(m.rfind("--set " + bad + ": ", 0), 0u) << m;
  }
  EXPECT_TRUE(contains(error_of(kFull, {"mesh.blocks.5.ny=3"}), "out of range"));
  EXPECT_TRUE(contains(error_of(kFull, {"time.dt"}), "missing '='"));
}

// An index too large for any integer type is out of range like any other (std::stoul threw
// std::out_of_range through parse_scene: found with tests/fuzz/fuzz_scene_reader).
TEST(SceneOverrides, RejectAnIndexBeyondEveryIntegerAsOutOfRange) {
  for (const std::string bad :
       {"mesh.blocks[99999999999999999999].ny=3", "mesh.blocks.18446744073709551616.ny=3"}) {
    const std::string m = error_of(kFull, {bad});
    EXPECT_EQ(m.rfind("--set " + bad + ": ", 0), 0u) << m;
    EXPECT_TRUE(contains(m, "out of range: 'mesh.blocks' has 2 entries")) << m;
  }
}

// The structure field and the coupling: elastic constants per block, the structure section and
// the fsi section, every key read; then the checks that keep a coupled scene consistent.
const std::string kStructure = R"yaml(  structure:
    blocks: [biofilm]
    mode: dynamic
    plane_strain: true
    boundary_conditions:
      - {boundary: bottom, type: fixed}
      - {boundary: left, type: displacement, value: ["0.01*t", free, 0]}
)yaml";
const std::string kElastic = R"yaml(    model: neo_hooke
    youngs_modulus: 1.0e-6
    poisson_ratio: 0.3
    density: 1.0e-3
)yaml";
const std::string kFsi = R"yaml(fsi:
  interface: biofilm_fluid
  shape_derivatives: none
  fixed_walls: [bottom, top]
  sliding_walls: [left, right]
  rel_tol: 1.0e-7
  max_iterations: 12
)yaml";

std::string with_structure(const std::string& scene) {
  std::string s = replaced(with_fluid(scene), "fields:\n", "fields:\n" + kStructure);
  s = replaced(s, "    monod_half_saturation: 0.1\n",
               "    monod_half_saturation: 0.1\n" + kElastic);
  return replaced(s, "time:\n", kFsi + "time:\n");
}

TEST(Scene, ReadsTheStructureFieldAndTheCoupling) {
  const Scene s = parse_scene(with_structure(kFull), kFile);
  EXPECT_TRUE(s.structure.enabled);
  EXPECT_EQ(s.structure.settings.blocks, std::vector<std::string>{"biofilm"});
  EXPECT_FALSE(s.structure.settings.quasi_static);
  EXPECT_TRUE(s.structure.settings.plane_strain);
  EXPECT_EQ(s.structure.settings.volumetric_integration, VolumetricIntegration::Full);
  EXPECT_EQ(
      parse_scene(with_structure(kFull), kFile, {"fields.structure.volumetric_integration=reduced"})
          .structure.settings.volumetric_integration,
      VolumetricIntegration::Reduced);
  const std::string bad =
      error_of(with_structure(kFull), {"fields.structure.volumetric_integration=fbar"});
  EXPECT_TRUE(contains(bad, "fields.structure.volumetric_integration")) << bad;
  EXPECT_TRUE(contains(bad, "fbar")) << bad;
  EXPECT_TRUE(contains(bad, "full")) << bad;
  ASSERT_EQ(s.structure.boundary_conditions.size(), 2u);
  EXPECT_TRUE(s.structure.boundary_conditions[0].fixed);
  EXPECT_FALSE(s.structure.boundary_conditions[1].fixed);
  EXPECT_EQ(s.structure.boundary_conditions[1].value[0], "0.01*t");
  EXPECT_EQ(s.structure.boundary_conditions[1].value[1], "free");
  const MaterialSpec& m = s.materials.at("biofilm");
  EXPECT_TRUE(m.elastic);
  EXPECT_TRUE(m.neo_hooke);
  EXPECT_EQ(m.youngs_modulus, 1e-6);
  EXPECT_EQ(m.poisson_ratio, 0.3);
  EXPECT_EQ(m.density, 1e-3);
  EXPECT_EQ(s.fsi.interface, "biofilm_fluid");
  EXPECT_EQ(s.fsi.shape_derivatives, ShapeDerivatives::None);
  // solver.reuse_preconditioner (kFull: false) reaches every field and the coupling.
  EXPECT_FALSE(s.fsi.reuse_preconditioner);
  EXPECT_FALSE(s.structure.settings.newton.reuse_preconditioner);
  EXPECT_FALSE(s.fluid.settings.newton_options.reuse_preconditioner);
  // The fluid's inflow (left) and outflow (right, and bottom's pressure) join the fixed walls.
  EXPECT_EQ(s.fsi.mesh_motion.fixed_walls,
            (std::vector<std::string>{"bottom", "top", "left", "right"}));
  EXPECT_EQ(s.fsi.mesh_motion.sliding_walls, (std::vector<std::string>{"left", "right"}));
  EXPECT_EQ(s.fsi.rel_tol, 1e-7);
  EXPECT_EQ(s.fsi.max_iterations, 12);
  EXPECT_FALSE(parse_scene(kFull, kFile).structure.enabled);
}

TEST(Scene, RejectsInconsistentCoupledScenes) {
  const std::string good = with_structure(kFull);
  // A structure block needs its elastic constants.
  const std::string no_modulus = replaced(good, "    youngs_modulus: 1.0e-6\n", "");
  EXPECT_TRUE(contains(error_of(no_modulus), "youngs_modulus")) << error_of(no_modulus);
  expect_error(replaced(good, "poisson_ratio: 0.3", "poisson_ratio: 0.5"),
               line_of(good, "poisson_ratio: 0.3"), "materials.biofilm.poisson_ratio", "0.5",
               "a number in (-1, 0.5)");
  expect_error(replaced(good, "model: neo_hooke", "model: mooney"), line_of(good, "model:"),
               "materials.biofilm.model", "mooney", "one of");
  // The fluid's block cannot also be the structure's.
  expect_error(replaced(good, "    blocks: [biofilm]\n", "    blocks: [fluid]\n"),
               line_of(good, "    blocks: [biofilm]"), "fields.structure.blocks[0]", "fluid",
               "blocks that are not fields.fluid.blocks");
  // A fixed condition takes no value; a displacement needs one.
  expect_error(replaced(good, "{boundary: bottom, type: fixed}",
                        "{boundary: bottom, type: fixed, value: [0, 0, 0]}"),
               line_of(good, "type: fixed"), "fields.structure.boundary_conditions[0].value", "",
               "no value key");
  // A dynamic structure in a steady flow has no steady coupled problem.
  const std::string steady =
      replaced(good, "    mode: transient\n    initial: steady\n", "    mode: steady\n");
  expect_error(steady, line_of(steady, "mode: dynamic"), "fields.structure.mode", "dynamic",
               "quasi_static");
  // The interface must carry the fluid's no-slip condition (its velocity becomes the structure's).
  const std::string slip_interface = replaced(good, "{boundary: biofilm_fluid, type: no_slip}",
                                              "{boundary: biofilm_fluid, type: slip}");
  expect_error(slip_interface, line_of(slip_interface, "interface: biofilm_fluid"), "fsi.interface",
               "biofilm_fluid", "a fields.fluid boundary condition");
  expect_error(replaced(good, "shape_derivatives: none", "shape_derivatives: exact"),
               line_of(good, "shape_derivatives"), "fsi.shape_derivatives", "exact", "one of");
  expect_error(replaced(good, "rel_tol: 1.0e-7", "rel_tol: 2"), line_of(good, "rel_tol: 1.0e-7"),
               "fsi.rel_tol", "2", "a number in (0, 1)");
  // A coupling section without the fields it couples.
  const std::string lonely = replaced(kFull, "time:\n", kFsi + "time:\n");
  expect_error(lonely, line_of(lonely, "interface: biofilm_fluid"), "fsi", "",
               "fields.structure and fields.fluid, or no fsi section");
}

TEST(Scene, ReadsTimeStagesOfAFlowRun) {
  // kFull's scalar field is off: a flow run, whose steps may come in stages.
  const std::vector<std::string> staged = {
      "time.dt=null", "time.steps=null", "time.stages=[{dt: 0.5, steps: 2}, {dt: 0.25, steps: 3}]"};
  const Scene s = parse_scene(kFull, kFile, staged);
  ASSERT_EQ(s.time.stages.size(), 2u);
  EXPECT_EQ(s.time.stages[1].dt, 0.25);
  EXPECT_EQ(s.time.stages[1].steps, 3);
  EXPECT_EQ(s.time.dt, 0.5);
  EXPECT_EQ(s.time.steps, 5);
  const Scene plain = parse_scene(kFull, kFile);
  ASSERT_EQ(plain.time.stages.size(), 1u);
  EXPECT_EQ(plain.time.stages[0].dt, plain.time.dt);
  EXPECT_EQ(plain.time.stages[0].steps, plain.time.steps);
  // Either dt and steps or stages; stages only where no inner loop of the scalar needs one dt.
  EXPECT_TRUE(contains(error_of(kFull, {staged[2]}), "time.dt: dt and steps beside stages"));
  std::vector<std::string> with_scalar = staged;
  with_scalar.push_back("fields.scalar.enabled=true");
  EXPECT_TRUE(contains(error_of(kFull, with_scalar),
                       "time.stages: stages in a scene with the scalar field"));
  EXPECT_TRUE(contains(
      error_of(kFull, {"time.dt=null", "time.steps=null", "time.stages=[{dt: 0.5, steps: 0}]"}),
      "time.stages[0].steps: out of range"));
}

// A stage's theta defaults to time.theta and may differ per stage (a damped start-up).
TEST(Scene, ReadsAThetaPerTimeStage) {
  const Scene s =
      parse_scene(kFull, kFile,
                  {"time.dt=null", "time.steps=null",
                   "time.stages=[{dt: 0.5, steps: 2, theta: 1}, {dt: 0.25, steps: 3}]"});
  ASSERT_EQ(s.time.stages.size(), 2u);
  EXPECT_EQ(s.time.stages[0].theta, 1.0);
  EXPECT_EQ(s.time.stages[1].theta, 0.75);  // kFull's time.theta
  EXPECT_EQ(parse_scene(kFull, kFile).time.stages[0].theta, 0.75);
  EXPECT_TRUE(contains(error_of(kFull, {"time.dt=null", "time.steps=null",
                                        "time.stages=[{dt: 0.5, steps: 2, theta: 0.4}]"}),
                       "time.stages[0].theta: out of range"))
      << error_of(kFull, {"time.dt=null", "time.steps=null",
                          "time.stages=[{dt: 0.5, steps: 2, theta: 0.4}]"});
}

// Each stage's steps fit an int, their sum need not: it is refused instead of overflowing (signed
// overflow, undefined behaviour: found with tests/fuzz/fuzz_scene_reader under UBSan).
TEST(Scene, RefusesStagesWhoseStepsTogetherOverflowAnInt) {
  auto staged = [](const std::string& first, const std::string& second) {
    return replaced(
        kFull, "  dt: 0.5\n  steps: 10\n",
        "  stages:\n    - {dt: 1, steps: " + first + "}\n    - {dt: 1, steps: " + second + "}\n");
  };
  const std::string over = staged("2147483647", "2147483647");
  expect_error(over, line_of(over, "    - {dt: 1"), "time.stages", "4294967294 steps",
               "at most 2147483647 steps in all stages together");
  // At the limit exactly, it is read.
  EXPECT_EQ(parse_scene(staged("2147483646", "1"), kFile).time.steps, 2147483647);
  EXPECT_TRUE(contains(error_of(staged("2147483646", "2")), "2147483648 steps"));
}

// Body forces per volume: the structure's as given, the fluid's per unit mass (its density).
TEST(Scene, ReadsBodyForces) {
  const std::string with_forces =
      replaced(replaced(with_structure(kFull), "    plane_strain: true\n",
                        "    plane_strain: true\n    body_force: [0, \"-2*t\", 0]\n"),
               "    preconditioner: simplec\n",
               "    preconditioner: simplec\n    body_force: [\"3e-3*x\", 0, 0]\n");
  const Scene s = parse_scene(with_forces, kFile);
  ASSERT_TRUE(s.structure.body_force.has_value());
  EXPECT_EQ((*s.structure.body_force)[1], "-2*t");
  EXPECT_EQ(structure_body_force(s.structure)[1](Point{0, 0, 0}, 3.0), -6.0);
  ASSERT_TRUE(s.fluid.body_force.has_value());
  // 3e-3 x per volume over density 1e-3: 3 x per unit mass.
  EXPECT_NEAR(fluid_body_force(s.fluid)(Point{2, 0, 0}, 0.0)[0], 6.0, 1e-12);
  EXPECT_FALSE(parse_scene(with_structure(kFull), kFile).structure.body_force.has_value());
  const std::string two = replaced(with_forces, "[0, \"-2*t\", 0]", "[0, 1]");
  EXPECT_TRUE(contains(error_of(two), "fields.structure.body_force: wrong type")) << error_of(two);
}

// A structure alone: no fluid, no scalar, no growth (a structural run); beside the scalar it needs
// the flow that loads it.
TEST(Scene, AcceptsAStructureAloneOnlyWithoutScalarAndGrowth) {
  const std::string alone = replaced(
      replaced(replaced(kFull, "fields:\n", "fields:\n" + kStructure),
               "    monod_half_saturation: 0.1\n", "    monod_half_saturation: 0.1\n" + kElastic),
      "    velocity: [\"0.1*y\", \"0\", 0]\n", "");
  const Scene s = parse_scene(alone, kFile);
  EXPECT_TRUE(s.structure.enabled);
  EXPECT_FALSE(s.fluid.enabled);
  const std::string m = error_of(alone, {"fields.scalar.enabled=true"});
  EXPECT_TRUE(contains(m, "fields.structure: a structure without a fluid field beside the scalar"))
      << m;
}

// mesh.unions: new face sets from the mesh's own, usable wherever a face set is.
TEST(Scene, ReadsUnionsOfFaceSets) {
  const Scene s = parse_scene(
      kFull, kFile, {"mesh.unions={walls: [left, right]}", "output.flux_boundaries=[walls]"});
  ASSERT_EQ(s.mesh_unions.size(), 1u);
  EXPECT_EQ(s.mesh_unions[0].first, "walls");
  const Mesh mesh = make_scene_mesh(s);
  ASSERT_TRUE(mesh.face_sets.count("walls"));
  EXPECT_EQ(mesh.face_sets.at("walls").size(),
            mesh.face_sets.at("left").size() + mesh.face_sets.at("right").size());
  EXPECT_EQ(mesh.node_sets.at("walls").size(),
            mesh.node_sets.at("left").size() + mesh.node_sets.at("right").size());
  EXPECT_TRUE(contains(error_of(kFull, {"mesh.unions={left: [right]}"}),
                       "mesh.unions.left: not a new set name"));
  EXPECT_TRUE(contains(error_of(kFull, {"mesh.unions={walls: [left, nowhere]}"}),
                       "mesh.unions.walls[1]: unknown boundary"));
}

TEST(Scene, ReadsProbesAndChecksTheirField) {
  const std::string probes =
      "output.probes=[{name: tip, point: [0.5, 1], quantity: velocity}, "
      "{name: p0, point: [0, 0, 0], quantity: pressure}]";
  const Scene s = parse_scene(with_fluid(kFull), kFile, {probes});
  ASSERT_EQ(s.output.probes.size(), 2u);
  EXPECT_EQ(s.output.probes[0].name, "tip");
  EXPECT_EQ(s.output.probes[0].point, (std::vector<double>{0.5, 1}));
  EXPECT_EQ(s.output.probes[0].quantity, ProbeSpec::Quantity::Velocity);
  EXPECT_EQ(s.output.probes[1].quantity, ProbeSpec::Quantity::Pressure);
  EXPECT_TRUE(
      contains(error_of(with_fluid(kFull),
                        {"output.probes=[{name: d, point: [0, 0], quantity: displacement}]"}),
               "output.probes[0].quantity: a displacement without a structure field"));
  EXPECT_TRUE(contains(error_of(kFull, {"output.probes=[{name: v, point: [0, 0], quantity: "
                                        "velocity}]"}),
                       "a flow value without a fluid field"));
  EXPECT_TRUE(contains(error_of(with_fluid(kFull), {"output.probes=[{name: v, point: [0], "
                                                    "quantity: velocity}]"}),
                       "output.probes[0].point: wrong type"));
  EXPECT_TRUE(contains(
      error_of(with_fluid(kFull), {"output.probes=[{name: a, point: [0, 0], quantity: pressure}, "
                                   "{name: a, point: [1, 0], quantity: pressure}]"}),
      "duplicate probe name"));
}

const std::string kGrowth =
    "growth={interface: biofilm_fluid, biofilm_block: biofilm, k1: 1.0e-3, dt_bio: 10, steps: 2}";

TEST(Scene, ReadsTheInnerLoopAndTheReferenceUpdateOfTheGrowthLoop) {
  const Scene s = parse_scene(kFull, kFile, {kGrowth});
  EXPECT_TRUE(s.growth.enabled);
  // kFull has time.steady_tolerance 1e-8: the stationarity stop is the default.
  EXPECT_EQ(s.growth.inner_loop, InnerLoop::UntilStationary);
  EXPECT_EQ(s.growth.reference_update, ReferenceUpdate::Reset);
  EXPECT_EQ(parse_scene(kFull, kFile, {kGrowth, "time.steady_tolerance=0"}).growth.inner_loop,
            InnerLoop::FixedSteps);
  const Scene fixed =
      parse_scene(kFull, kFile,
                  {kGrowth, "time.steady_tolerance=0", "growth.inner_loop=fixed_steps",
                   "growth.reference_update=keep"});
  EXPECT_EQ(fixed.growth.inner_loop, InnerLoop::FixedSteps);
  EXPECT_EQ(fixed.growth.reference_update, ReferenceUpdate::Keep);
}

TEST(Scene, RefusesAGrowthLoopThatContradictsTheTimeSection) {
  const std::string fixed = error_of(kFull, {kGrowth, "growth.inner_loop=fixed_steps"});
  EXPECT_TRUE(contains(fixed,
                       "growth.inner_loop: a fixed step count with "
                       "time.steady_tolerance 1e-08"))
      << fixed;
  EXPECT_TRUE(contains(fixed, "got 'fixed_steps'")) << fixed;
  EXPECT_TRUE(contains(fixed, "expected no time.steady_tolerance (or 0)")) << fixed;
  const std::string stationary =
      error_of(kFull, {kGrowth, "time.steady_tolerance=0", "growth.inner_loop=until_stationary"});
  EXPECT_TRUE(contains(stationary,
                       "growth.inner_loop: the stationarity stop without "
                       "time.steady_tolerance"))
      << stationary;
  EXPECT_TRUE(contains(stationary, "expected time.steady_tolerance > 0")) << stationary;
  // A window longer than the inner loop (kFull: time.steps 10) could never be filled.
  const std::string window =
      error_of(kFull, {kGrowth, "growth.averaging=window", "growth.window=11"});
  EXPECT_TRUE(contains(window, "growth.window: a window longer than the inner loop")) << window;
  EXPECT_TRUE(contains(window, "expected at most time.steps (10) inner steps")) << window;
  const std::string unknown = error_of(kFull, {kGrowth, "growth.reference_update=relax"});
  EXPECT_TRUE(contains(unknown, "growth.reference_update: unknown value")) << unknown;
  EXPECT_TRUE(contains(unknown, "expected one of reset, keep")) << unknown;
}

TEST(Scene, HoldsTheFlowsInflowAndOutflowFixedInTheCoupledSolveUnlessTheWallsDecide) {
  // kFluid: velocity on left, do_nothing on right, pressure on bottom; no_slip on the interface.
  // with_structure's fsi section: fixed_walls [bottom, top], sliding_walls [left, right].
  const std::vector<std::string> walls_only = {"bottom", "top"};
  const std::vector<std::string> open_fixed = {"bottom", "top", "left", "right"};
  const Scene fixed = parse_scene(with_structure(kFull), kFile, {kGrowth});
  EXPECT_EQ(fixed.fsi.mesh_motion.inflow_outflow, InflowOutflow::Fixed);
  EXPECT_EQ(fixed.fsi.mesh_motion.fixed_walls, open_fixed);
  EXPECT_EQ(fixed.fsi.mesh_motion.sliding_walls, (std::vector<std::string>{"left", "right"}));
  // A growth step's mesh motion keeps its wall lists: the interface's end nodes rise along them.
  EXPECT_EQ(fixed.growth.settings.mesh_motion.fixed_walls, walls_only);
  const Scene walls =
      parse_scene(with_structure(kFull), kFile, {kGrowth, "mesh_motion.inflow_outflow=walls"});
  EXPECT_EQ(walls.fsi.mesh_motion.inflow_outflow, InflowOutflow::Walls);
  EXPECT_EQ(walls.fsi.mesh_motion.fixed_walls, walls_only);
  // A velocity condition on the FSI interface is its motion, not an inflow.
  const Scene moving =
      parse_scene(replaced(with_structure(kFull), "{boundary: biofilm_fluid, type: no_slip}",
                           "{boundary: biofilm_fluid, type: velocity, value: [0, 0, 0]}"),
                  kFile);
  EXPECT_EQ(moving.fsi.mesh_motion.fixed_walls, open_fixed);
  const std::string bad = error_of(kFull, {"mesh_motion.inflow_outflow=sliding"});
  EXPECT_TRUE(contains(bad, "mesh_motion.inflow_outflow: unknown value")) << bad;
  EXPECT_TRUE(contains(bad, "expected one of fixed, walls")) << bad;
}

// fidelity: draft | standard | fine scales the mesh's division counts (after --set) and reports
// what it changed; a pseudo-2-D mesh stays one element thick; a Gmsh mesh's refine parameter
// scales; a bad value stops with the file, key, value and the allowed ones.
TEST(Scene, FidelityPresetScalesTheMeshResolution) {
  const Scene standard = parse_scene(kFull, kFile);
  EXPECT_TRUE(standard.fidelity.level.empty());
  EXPECT_EQ(standard.box.nx, 4);
  const Scene draft = parse_scene(kFull, kFile, {"fidelity=draft"});
  EXPECT_EQ(draft.fidelity.level, "draft");
  EXPECT_EQ(draft.box.nx, 2);
  EXPECT_EQ(draft.box.nz, 1);
  ASSERT_EQ(draft.box.blocks.size(), 2u);
  EXPECT_EQ(draft.box.blocks[0].ny, 1);
  EXPECT_EQ(draft.box.blocks[1].ny, 2);
  EXPECT_EQ(draft.fidelity.changes.size(), 3u);
  EXPECT_TRUE(contains(draft.fidelity.expected, "no error band is known for scene.yaml"))
      << draft.fidelity.expected;
  const Scene fine = parse_scene(kFull, kFile, {"fidelity=fine", "mesh.nz=3"});
  EXPECT_EQ(fine.box.nx, 8);
  EXPECT_EQ(fine.box.nz, 6);  // the --set value is scaled too: the preset comes after overrides
  EXPECT_EQ(fine.box.blocks[0].ny, 4);
  EXPECT_EQ(fine.box.blocks[1].ny, 8);
  const Scene same = parse_scene(kFull, kFile, {"fidelity=standard"});
  EXPECT_EQ(same.box.nx, 4);
  EXPECT_TRUE(same.fidelity.changes.empty());

  YAML::Node gmsh = YAML::Load(
      "mesh: {type: gmsh, file: m.geo, parameters: {refine: 3}}\n"
      "fidelity: draft\n");
  const scene_input::Checker checker(kFile, {});
  const FidelityReport r = apply_fidelity(gmsh, checker);
  EXPECT_EQ(gmsh["mesh"]["parameters"]["refine"].as<double>(), 1.5);
  ASSERT_EQ(r.changes.size(), 1u);
  EXPECT_EQ(r.changes[0], "mesh.parameters.refine: 3 -> 1.5");

  // An inner loop that runs until stationary (growth, no transient flow): draft takes 4x longer
  // steps (as many fewer, rounded up) to a 100x looser tolerance, fine a 100x tighter one; a
  // transient flow or a fixed inner loop keeps its steps.
  const std::string growth_scene =
      "mesh: {type: box, nx: 40}\n"
      "time: {dt: 1.0, steps: 10, steady_tolerance: 1.0e-6}\n"
      "growth: {interface: biofilm_fluid}\n";
  const scene_input::Checker c_scene("cases/coroneo2013/c_shear_quasi_steady.yaml", {});
  YAML::Node draft_growth = YAML::Load(growth_scene + "fidelity: draft\n");
  const FidelityReport d = apply_fidelity(draft_growth, c_scene);
  EXPECT_EQ(draft_growth["time"]["dt"].as<double>(), 4.0);
  EXPECT_EQ(draft_growth["time"]["steps"].as<int>(), 3);
  EXPECT_DOUBLE_EQ(draft_growth["time"]["steady_tolerance"].as<double>(), 1e-4);
  EXPECT_TRUE(contains(d.expected, "3.4%")) << d.expected;
  YAML::Node fine_growth = YAML::Load(growth_scene + "fidelity: fine\n");
  apply_fidelity(fine_growth, c_scene);
  EXPECT_EQ(fine_growth["time"]["dt"].as<double>(), 1.0);
  EXPECT_DOUBLE_EQ(fine_growth["time"]["steady_tolerance"].as<double>(), 1e-8);
  const std::string time = "time: {dt: 1.0, steps: 10, steady_tolerance: 1.0e-6}\n";
  for (const std::string& kept :
       {time + "growth: {interface: biofilm_fluid}\nfields: {fluid: {mode: transient}}\n",
        time + "growth: {interface: biofilm_fluid, inner_loop: fixed_steps}\n", time}) {
    YAML::Node n = YAML::Load("mesh: {type: box, nx: 40}\n" + kept + "fidelity: draft\n");
    apply_fidelity(n, checker);
    EXPECT_EQ(n["time"]["dt"].as<double>(), 1.0) << kept;
    EXPECT_EQ(n["time"]["steps"].as<int>(), 10) << kept;
    EXPECT_EQ(n["mesh"]["nx"].as<int>(), 20) << kept;
  }

  const std::string bad = error_of(kFull, {"fidelity=coarse"});
  EXPECT_TRUE(contains(bad,
                       "fidelity: unknown value; got 'coarse', expected one of draft, "
                       "standard, fine"))
      << bad;
}

}  // namespace
}  // namespace biofsi
