#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>

#include "io/output.hpp"
#include "mesh/mesh.hpp"
#include "scratch_dir.hpp"

namespace biofsi {
namespace {

namespace fs = std::filesystem;

class XdmfOutput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratch_dir("test_io");
    mesh_ =
        make_box_mesh({-1, 1, 0, 0.5, 3, 2, {{"biofilm", 0, 1, 1, 1.0}, {"fluid", 1, 2, 2, 2.0}}});
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A nodal scalar and a cell vector whose values differ per step and per entry.
  std::vector<OutputField> fields(int step) const {
    OutputField phi{"phi", 1, false, {}};
    for (const auto& p : mesh_.x) phi.values.push_back(step + p[0] * 0.1 + p[1] / 3.0 + p[2]);
    OutputField flux{"flux", 3, true, {}};
    for (int e = 0; e < mesh_.n_elements(); ++e)
      for (int c = 0; c < 3; ++c) flux.values.push_back(1.0 / (1 + e + 7 * c) - step);
    return {phi, flux};
  }

  std::string h5(int step) const {
    char name[32];
    std::snprintf(name, sizeof name, "run_%06d.h5", step);
    return (dir_ / name).string();
  }

  static std::string read_text(const std::string& path) {
    std::ifstream in(path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }

  static int count(const std::string& text, const std::string& what) {
    int n = 0;
    for (size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
    return n;
  }

  // Returns what was written for each step.
  std::map<int, std::vector<OutputField>> write_two_steps() {
    XdmfWriter w(dir_.string(), "run", false);
    std::map<int, std::vector<OutputField>> written;
    written[0] = fields(0);
    w.write(0, 0.0, mesh_, written[0]);
    // The mesh moves between steps in later work; each step must keep its own coordinates.
    distort(mesh_, [](const Point& p) { return Point{p[0], p[1] + 0.01 * p[0], p[2]}; });
    written[5] = fields(5);
    w.write(5, 2.5, mesh_, written[5]);
    return written;
  }

  fs::path dir_;
  Mesh mesh_;
};

TEST_F(XdmfOutput, StepsReadBackExactly) {
  const Mesh before = mesh_;
  const auto written = write_two_steps();
  const Mesh& after = mesh_;
  for (int step : {0, 5}) {
    const Mesh& m = step == 0 ? before : after;
    std::vector<double> xyz, conn, block;
    for (const auto& p : m.x) xyz.insert(xyz.end(), p.begin(), p.end());
    for (const auto& c : m.conn) conn.insert(conn.end(), c.begin(), c.end());
    block.assign(m.element_block.begin(), m.element_block.end());
    EXPECT_EQ(read_h5_dataset(h5(step), "coordinates"), xyz) << step;
    EXPECT_EQ(read_h5_dataset(h5(step), "/connectivity"), conn) << step;
    EXPECT_EQ(read_h5_dataset(h5(step), "block"), block) << step;
    const auto& f = written.at(step);
    EXPECT_EQ(read_h5_dataset(h5(step), "phi"), f[0].values) << step;
    EXPECT_EQ(read_h5_dataset(h5(step), "flux"), f[1].values) << step;
  }
  EXPECT_THROW(read_h5_dataset(h5(0), "no_such_field"), std::runtime_error);
  EXPECT_THROW(read_h5_dataset(h5(1), "phi"), std::runtime_error);
}

TEST_F(XdmfOutput, IndexListsEveryStepWithTimeFileAndTopology) {
  write_two_steps();
  const std::string x = read_text((dir_ / "run.xdmf").string());
  EXPECT_EQ(x.rfind("<?xml", 0), 0u);
  EXPECT_NE(x.find("<Xdmf Version=\"3.0\""), std::string::npos);
  EXPECT_NE(x.find("CollectionType=\"Temporal\""), std::string::npos);
  EXPECT_EQ(count(x, "GridType=\"Uniform\""), 2);
  EXPECT_EQ(count(x, "<Grid"), 3);  // the collection and one grid per step
  EXPECT_EQ(count(x, "</Grid>"), 3);
  EXPECT_NE(x.find("<Time Value=\"0\"/>"), std::string::npos);
  EXPECT_NE(x.find("<Time Value=\"2.5\"/>"), std::string::npos);
  EXPECT_LT(x.find("<Time Value=\"0\"/>"), x.find("<Time Value=\"2.5\"/>"));
  EXPECT_EQ(count(x, "TopologyType=\"Hexahedron\""), 2);
  EXPECT_EQ(count(x, "GeometryType=\"XYZ\""), 2);
  EXPECT_EQ(count(x, "run_000000.h5:/coordinates"), 1);
  EXPECT_EQ(count(x, "run_000005.h5:/coordinates"), 1);
  EXPECT_NE(x.find("NumberOfElements=\"" + std::to_string(mesh_.n_elements()) + "\""),
            std::string::npos);
  EXPECT_EQ(count(x, "Name=\"phi\" AttributeType=\"Scalar\" Center=\"Node\""), 2);
  EXPECT_EQ(count(x, "Name=\"flux\" AttributeType=\"Vector\" Center=\"Cell\""), 2);
  EXPECT_EQ(count(x, "Name=\"block\" AttributeType=\"Scalar\" Center=\"Cell\""), 2);
  EXPECT_NE(x.find("Dimensions=\"" + std::to_string(mesh_.n_nodes()) + " 1\""), std::string::npos);
}

TEST_F(XdmfOutput, LeavesNoTemporaryFiles) {
  write_two_steps();
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir_)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"run.xdmf", "run_000000.h5", "run_000005.h5"}));
}

TEST_F(XdmfOutput, RefusesToOverwriteAnExistingIndexUnlessAsked) {
  write_two_steps();
  try {
    XdmfWriter again(dir_.string(), "run", false);
    FAIL() << "a second writer replaced an existing index";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find((dir_ / "run.xdmf").string()), std::string::npos) << m;
    EXPECT_NE(m.find("--overwrite"), std::string::npos) << m;
  }
  EXPECT_EQ(count(read_text((dir_ / "run.xdmf").string()), "GridType=\"Uniform\""), 2);

  XdmfWriter fresh(dir_.string(), "run", true);
  fresh.write(0, 1.0, mesh_, fields(0));
  const std::string x = read_text(fresh.index_path());
  EXPECT_EQ(count(x, "GridType=\"Uniform\""), 1);
  EXPECT_NE(x.find("<Time Value=\"1\"/>"), std::string::npos);
}

TEST_F(XdmfOutput, OverwritingRemovesTheEarlierSeriesStepFiles) {
  write_two_steps();
  const fs::path other = dir_ / "other_000001.h5", keep = dir_ / "run_notes.h5";
  std::ofstream(other) << "x";
  std::ofstream(keep) << "x";
  XdmfWriter fresh(dir_.string(), "run", true);
  int steps = 0;
  for (const auto& e : fs::directory_iterator(dir_))
    if (e.path().filename().string().rfind("run_0", 0) == 0) ++steps;
  EXPECT_EQ(steps, 0);             // no stale step file beside the new, empty index
  EXPECT_TRUE(fs::exists(other));  // another series' and unrelated files stay
  EXPECT_TRUE(fs::exists(keep));
}

TEST_F(XdmfOutput, CreatesMissingDirectories) {
  const fs::path nested = dir_ / "a" / "b";
  XdmfWriter w(nested.string(), "run", false);
  w.write(0, 0.0, mesh_, {});
  EXPECT_TRUE(fs::exists(nested / "run_000000.h5"));
  EXPECT_TRUE(fs::exists(nested / "run.xdmf"));
}

TEST_F(XdmfOutput, RejectsFieldsOfTheWrongSize) {
  XdmfWriter w(dir_.string(), "run", false);
  auto f = fields(0);
  f[0].values.pop_back();
  EXPECT_THROW(w.write(0, 0.0, mesh_, f), std::invalid_argument);
  EXPECT_FALSE(fs::exists(h5(0)));
}

// What `body` writes to file descriptor 2 (HDF5 prints there, past std::cerr).
template <class Body>
std::string stderr_of(const Body& body) {
  const std::string path = testing::TempDir() + "stderr_" + std::to_string(getpid());
  std::fflush(stderr);
  const int saved = dup(2);
  FILE* sink = std::fopen(path.c_str(), "w");
  dup2(fileno(sink), 2);
  body();
  std::fflush(stderr);
  dup2(saved, 2);
  close(saved);
  std::fclose(sink);
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The expected message of a write into /dev/full: the file, what failed, the system's reason.
void expect_full_disk(const std::function<void()>& write, const std::string& file) {
  const std::string printed = stderr_of([&] {
    try {
      write();
      ADD_FAILURE() << "the write to /dev/full succeeded";
    } catch (const OutputError& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind(file + ": ", 0), 0u) << m;
      EXPECT_NE(m.find("No space left on device"), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;  // one line
    }
  });
  EXPECT_EQ(printed, "");  // HDF5's own error printing is off
}

// A full disk (a temporary file that is a link to /dev/full) stops every kind of write with
// OutputError naming the file and the system's reason, and leaves no temporary file.
TEST_F(XdmfOutput, AFullDiskStopsEachWriteNamingTheFileAndTheReason) {
  fs::create_directories(dir_);
  XdmfWriter w(dir_.string(), "run", false);
  fs::create_symlink("/dev/full", h5(0) + ".tmp");
  expect_full_disk([&] { w.write(0, 0.0, mesh_, fields(0)); }, h5(0));
  EXPECT_FALSE(fs::exists(h5(0)));
  EXPECT_FALSE(fs::is_symlink(h5(0) + ".tmp"));

  fs::create_symlink("/dev/full", (dir_ / "run.xdmf.tmp").string());
  expect_full_disk([&] { w.write(1, 0.0, mesh_, fields(1)); }, (dir_ / "run.xdmf").string());

  const std::string checkpoint = (dir_ / "checkpoint_000001.h5").string();
  fs::create_symlink("/dev/full", checkpoint + ".tmp");
  expect_full_disk([&] { write_h5_datasets(checkpoint, {{"phi", {1.0, 2.0}}}); }, checkpoint);

  const std::string summary = (dir_ / "summary.txt").string();
  fs::create_symlink("/dev/full", summary + ".tmp");
  expect_full_disk([&] { write_text_file(summary, "summary\n"); }, summary);
  EXPECT_FALSE(fs::exists(summary));

  expect_full_disk([&] { TextLog("/dev/full").append("step,time\n"); }, "/dev/full");
}

TEST_F(XdmfOutput, AnOutputDirectoryThatCannotBeMadeIsAnOutputError) {
  try {
    XdmfWriter w("/dev/full/results", "run", false);
    FAIL() << "created";
  } catch (const OutputError& e) {
    EXPECT_EQ(
        std::string(e.what()).rfind("/dev/full/results: cannot create the output directory: ", 0),
        0u)
        << e.what();
  }
}

}  // namespace
}  // namespace biofsi
