// Running a scene of cases/ through the driver (run_scene) from a test, with its output captured,
// and reading the series.csv it writes. Header-only; any test linked with biofsi_core may use it
// (the scene paths need BIOFSI_SOURCE_DIR, which tests/CMakeLists.txt defines for every test).
#pragma once

#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/run.hpp"
#include "scratch_dir.hpp"

namespace biofsi {
namespace test {

struct RunOutput {
  int rc;
  std::string out, err;
};

// run_scene with std::cout and std::cerr captured.
inline RunOutput run_quietly(const RunOptions& o) {
  std::ostringstream text, errors;
  auto* old_out = std::cout.rdbuf(text.rdbuf());
  auto* old_err = std::cerr.rdbuf(errors.rdbuf());
  const int rc = run_scene(o);
  std::cout.rdbuf(old_out);
  std::cerr.rdbuf(old_err);
  return {rc, text.str(), errors.str()};
}

// A scene of cases/, e.g. "turek_hron/csm3.yaml", run into `out` (emptied first).
inline RunOptions case_run(const std::string& scene, const std::filesystem::path& out,
                           std::vector<std::string> overrides = {}) {
  std::filesystem::remove_all(out);
  RunOptions o;
  o.scene_path = std::string(BIOFSI_SOURCE_DIR) + "/cases/" + scene;
  o.out_dir = out.string();
  o.overrides = std::move(overrides);
  return o;
}

inline std::vector<std::vector<std::string>> read_csv(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> row;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) row.push_back(cell);
    rows.push_back(row);
  }
  return rows;
}

// series.csv by column name.
inline std::map<std::string, std::vector<double>> read_series(const std::filesystem::path& path) {
  const auto rows = read_csv(path);
  if (rows.empty()) throw std::runtime_error(path.string() + ": no header");
  std::map<std::string, std::vector<double>> out;
  for (size_t r = 1; r < rows.size(); ++r)
    for (size_t c = 0; c < rows[0].size() && c < rows[r].size(); ++c)
      out[rows[0][c]].push_back(std::stod(rows[r][c]));
  return out;
}

}  // namespace test
}  // namespace biofsi
