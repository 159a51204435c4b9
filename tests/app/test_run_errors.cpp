// Hostile inputs and faults through the driver (run_scene) and the binary: each ends in one line
// "biofsi: <file>: <what>" on stderr and its documented exit code (1 bad input, 4 output failed);
// non-finite expressions name their key; nothing of an earlier run is removed before the new run's
// inputs are checked, and --overwrite leaves none of its files behind. Tiny scenes: seconds.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "app/run.hpp"
#include "scratch_dir.hpp"
#include "tiny_scene.hpp"

using namespace biofsi;
namespace fs = std::filesystem;

namespace {

const std::string source_dir = BIOFSI_SOURCE_DIR;

// Scalar transport on a 2 x 2 x 1 box: a run takes a fraction of a second.
const std::string kScene = test::kTinyBoxScene + R"yaml(fields:
  scalar:
    initial: "0"
    boundary_conditions:
      - {boundary: left, type: dirichlet, value: "1"}
time: {dt: 1.0, steps: 2}
)yaml";

class RunErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratch_dir("run_errors");
    fs::create_directories(dir_);
    scene_ = write("scene.yaml", kScene);
    out_ = dir_ / "out";
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) const {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }

  struct Result {
    int rc;
    std::string out, err;
  };

  // run_scene with its streams captured; `err` also holds what was written to descriptor 2
  // directly (HDF5 prints there), which must be nothing.
  Result run(std::vector<std::string> set = {}, bool overwrite = false,
             const std::string& restart = "", std::optional<std::string> scene = std::nullopt,
             std::optional<std::string> out = std::nullopt) const {
    RunOptions o;
    o.scene_path = scene ? *scene : scene_;
    o.out_dir = out ? *out : out_.string();
    o.overrides = std::move(set);
    o.overwrite = overwrite;
    o.restart = restart;
    std::ostringstream text, errors;
    auto* old_out = std::cout.rdbuf(text.rdbuf());
    auto* old_err = std::cerr.rdbuf(errors.rdbuf());
    const std::string raw = (dir_ / "fd2.txt").string();
    std::fflush(stderr);
    const int saved = dup(2);
    FILE* sink = std::fopen(raw.c_str(), "w");
    dup2(fileno(sink), 2);
    const int rc = run_scene(o);
    std::fflush(stderr);
    dup2(saved, 2);
    close(saved);
    std::fclose(sink);
    std::cout.rdbuf(old_out);
    std::cerr.rdbuf(old_err);
    std::ifstream in(raw);
    const std::string direct((std::istreambuf_iterator<char>(in)), {});
    fs::remove(raw);
    return {rc, text.str(), errors.str() + direct};
  }

  // Every file of a directory with its contents.
  static std::map<std::string, std::string> contents(const fs::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& e : fs::directory_iterator(dir)) {
      std::ifstream in(e.path());
      files[e.path().filename().string()] = std::string(std::istreambuf_iterator<char>(in), {});
    }
    return files;
  }

  fs::path dir_, out_;
  std::string scene_;
};

// One line on stderr that starts with "biofsi: <file>: " and holds `part`.
void expect_line(const std::string& err, const std::string& file, const std::string& part) {
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_EQ(err.rfind("biofsi: " + file + ": ", 0), 0u) << err;
  EXPECT_NE(err.find(part), std::string::npos) << err;
}

std::string msh_with_a_missing_node() {
  return "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"fluid\"\n"
         "$EndPhysicalNames\n$Entities\n0 0 0 1\n1 0 0 0 1 1 1 1 1 0\n$EndEntities\n"
         "$Nodes\n1 8 1 8\n3 1 0 8\n1\n2\n3\n4\n5\n6\n7\n8\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
         "0 0 1\n1 0 1\n1 1 1\n0 1 1\n$EndNodes\n$Elements\n1 1 1 1\n3 1 5 1\n"
         "1 1 2 3 4 5 6 7 99\n$EndElements\n";
}

}  // namespace

// Inputs that once crashed the program or read until memory ran out: each is bad input (exit 1)
// with one line naming the file, before the output directory is made.
TEST_F(RunErrors, CrashInputsAreBadInputWithOneLine) {
  Result r = run({}, false, "", "/dev/zero");
  EXPECT_EQ(r.rc, kExitBadInput);
  expect_line(r.err, "/dev/zero", "not a regular file");

  const std::string big = write("big.yaml", kScene + std::string(17 << 20, '#'));
  r = run({}, false, "", big);
  EXPECT_EQ(r.rc, kExitBadInput);
  expect_line(r.err, big, "larger than 16777216 bytes");

  r = run({"mesh.nx=20000", "mesh.nz=20000"});
  EXPECT_EQ(r.rc, kExitBadInput);
  expect_line(r.err, scene_ + ":2",
              "mesh: the mesh does not fit in memory: 1200120003 nodes need at least 2400.2 GB "
              "(2000 bytes per node)");

  write("bad.msh", msh_with_a_missing_node());
  const std::string gmsh_scene =
      write("gmsh.yaml",
            "mesh: {type: gmsh, file: bad.msh}\nmaterials:\n  fluid: {diffusivity: 1}\n"
            "time: {dt: 1, steps: 1}\n");
  r = run({}, false, "", gmsh_scene);
  EXPECT_EQ(r.rc, kExitBadInput);
  expect_line(r.err, gmsh_scene + ":1", "element 1 uses node 99, which $Nodes does not define");

  r = run({}, false, "", std::nullopt, std::string());
  EXPECT_EQ(r.rc, kExitBadInput);
  expect_line(r.err, "--out ''", "an empty directory name");

  r =
      run({"fields.scalar.boundary_conditions=[{boundary: left, type: dirichlet, value: 1}, "
           "{boundary: left, type: dirichlet, value: 0}]"});
  EXPECT_EQ(r.rc, kExitBadInput);
  expect_line(r.err, scene_ + ":15", "a second scalar boundary condition on 'left'");
  EXPECT_FALSE(fs::exists(out_));
}

// Each non-finite expression stops the run before anything is written, naming its key, the
// expression, the point and the time; one that becomes infinite later (1/(t-2)) stops it then.
TEST_F(RunErrors, NonFiniteExpressionsNameTheirKey) {
  for (const char* initial : {"sqrt(-1)", "1/(x-x)", "1/0", "10^400"}) {
    const Result r = run({std::string("fields.scalar.initial=\"") + initial + "\""});
    EXPECT_EQ(r.rc, kExitBadInput) << initial;
    expect_line(r.err, scene_, std::string("fields.scalar.initial: '") + initial + "' is ");
    EXPECT_NE(r.err.find("at (x, y, z) = (0, 0, 0), t = 0"), std::string::npos) << r.err;
  }
  Result r = run({"fields.scalar.velocity=[\"0/0\", 0, 0]"});
  EXPECT_EQ(r.rc, kExitBadInput);
  expect_line(r.err, scene_, "fields.scalar.velocity[0]: '0/0' is NaN at");
  r = run({"fields.scalar.boundary_conditions[0].value=\"1/0\""});
  EXPECT_EQ(r.rc, kExitBadInput);
  expect_line(r.err, scene_,
              "fields.scalar.boundary_conditions[0].value (line 15): '1/0' is infinite at");
  EXPECT_FALSE(fs::exists(out_));

  // Finite at the times checked before the run (0, 0.5 and 3), infinite at t = 2 (step 4).
  r = run(
      {"fields.scalar.boundary_conditions[0].value=\"1/(t-2)\"", "time.dt=0.5", "time.steps=6"});
  EXPECT_EQ(r.rc, kExitBadInput);
  expect_line(r.err, scene_,
              "fields.scalar.boundary_conditions[0].value (line 15): '1/(t-2)' is infinite at");
  EXPECT_NE(r.err.find("t = 2;"), std::string::npos) << r.err;
}

// A --restart that cannot be read (mistyped) is bad input and leaves the earlier run's files as
// they were: nothing removed, no index emptied.
TEST_F(RunErrors, AFailedRestartLeavesThePreviousRunUntouched) {
  fs::create_directories(out_);
  for (const char* name :
       {"scalar.xdmf", "scalar_000000.h5", "checkpoint_000002.h5", "summary.txt", "notes.txt"})
    std::ofstream(out_ / name) << "earlier run: " << name;
  const auto before = contents(out_);
  const std::string missing = (dir_ / "checkpoint_00002.h5").string();
  const std::vector<std::string> small = {"mesh.nx=4", "mesh.blocks.0.ny=1", "mesh.blocks.1.ny=2"};
  const std::string growth = source_dir + "/cases/coroneo2013/b_cosine.yaml";
  Result r = run(small, true, missing, growth);
  EXPECT_EQ(r.rc, kExitBadInput);
  expect_line(r.err, missing, "no such file (--restart " + missing + ")");
  EXPECT_EQ(contents(out_), before);

  // Nor does it leave an empty index where there was none.
  const fs::path fresh = dir_ / "fresh";
  r = run(small, false, missing, growth, fresh.string());
  EXPECT_EQ(r.rc, kExitBadInput);
  EXPECT_FALSE(fs::exists(fresh / "scalar.xdmf"));
}

// Without --overwrite an earlier run is refused and kept; with it, every file an earlier run
// wrote is replaced or removed (a later checkpoint, step files, temporary files of a killed run)
// and files of the user's stay.
TEST_F(RunErrors, OverwriteLeavesNoFileOfThePreviousRun) {
  fs::create_directories(out_);
  for (const char* name :
       {"scalar.xdmf", "scalar_000009.h5", "checkpoint_000009.h5", "scalar_000003.h5.tmp",
        "flux_top.csv", "series.csv", "summary.txt", "notes.txt"})
    std::ofstream(out_ / name) << "earlier run";
  const auto before = contents(out_);
  Result r = run();
  EXPECT_EQ(r.rc, kExitBadInput);
  expect_line(r.err, (out_ / "scalar.xdmf").string(), "pass --overwrite");
  EXPECT_EQ(contents(out_), before);

  r = run({}, true);
  ASSERT_EQ(r.rc, kExitSuccess) << r.err;
  std::vector<std::string> names;
  for (const auto& [name, text] : contents(out_)) names.push_back(name);
  EXPECT_EQ(names,
            (std::vector<std::string>{"notes.txt", "scalar.xdmf", "scalar_000000.h5",
                                      "scalar_000001.h5", "scalar_000002.h5", "summary.txt"}));
  EXPECT_EQ(r.err, "");
}

// A full disk (a file of the run that is a link to /dev/full): exit 4 with one line naming the
// file and the system's reason, HDF5's diagnostics folded into it.
TEST_F(RunErrors, AFullDiskIsAnOutputFailure) {
  for (const char* file : {"summary.txt", "scalar_000001.h5", "scalar.xdmf"}) {
    fs::remove_all(out_);
    fs::create_directories(out_);
    const std::string path = (out_ / file).string();
    fs::create_symlink("/dev/full", path + ".tmp");
    const Result r = run();
    EXPECT_EQ(r.rc, kExitOutputFailed) << file << ": " << r.err;
    expect_line(r.err, path, "No space left on device");
  }
}

// The binary ends every error in main's one handler with the documented exit code.
TEST_F(RunErrors, TheProgramExitsWithTheDocumentedCode) {
  auto exit_code = [&](const std::string& args) {
    const std::string log = (dir_ / "log.txt").string();
    const int status =
        std::system((std::string(BIOFSI_BINARY) + " " + args + " > " + log + " 2>&1").c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  EXPECT_EQ(exit_code("run /dev/zero"), kExitBadInput);
  EXPECT_EQ(exit_code("run " + scene_ + " --out ''"), kExitBadInput);
  EXPECT_EQ(exit_code("run " + scene_ + " --frobnicate"), kExitBadCommandLine);
  fs::create_directories(out_);
  fs::create_symlink("/dev/full", out_ / "summary.txt.tmp");
  EXPECT_EQ(exit_code("run " + scene_ + " --out " + out_.string()), kExitOutputFailed);
  std::ifstream log(dir_ / "log.txt");
  const std::string text((std::istreambuf_iterator<char>(log)), {});
  EXPECT_NE(text.find("biofsi: " + (out_ / "summary.txt").string() +
                      ": cannot write: No space left on device\n"),
            std::string::npos)
      << text;
}
