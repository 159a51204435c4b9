// The driver: reads a scene, decides which fields it needs, runs them, writes results and a
// summary. Exit codes: 0 success, 1 bad input, 3 failed solve (after writing the last valid state).
#pragma once

#include <string>
#include <vector>

namespace biofsi {

struct RunOptions {
  std::string scene_path;
  std::string out_dir;                 // empty: the scene's output.directory
  std::vector<std::string> overrides;  // --set key=value
  bool overwrite = false;
  std::string restart;  // checkpoint file to continue from (growth scenes)
};

int run_scene(const RunOptions& options);

}  // namespace biofsi
