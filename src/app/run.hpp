// The driver: reads a scene, decides which fields it needs, runs them, writes results and a
// summary. Every error ends in one handler (report_error): one line on stderr, "biofsi: <file>:
// <what>", and the exit code of its kind.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace biofsi {

// The exit codes of `biofsi` (README.md lists them for users).
enum ExitCode {
  kExitSuccess = 0,
  kExitBadInput = 1,        // scene, mesh, expression, restart file, --out or --set value
  kExitBadCommandLine = 2,  // an unknown option, a missing value
  kExitSolveFailed = 3,     // after writing the last valid state
  kExitOutputFailed = 4,    // a result file could not be written (full disk, no permission)
};

struct RunOptions {
  std::string scene_path;
  std::optional<std::string> out_dir;  // absent: the scene's output.directory; empty: an error
  std::vector<std::string> overrides;  // --set key=value
  bool overwrite = false;
  std::string restart;  // checkpoint file to continue from (growth and transient flow scenes)
};

// Runs a scene; returns the exit code. Nothing in the output directory is written or removed
// before every input (scene, mesh, expressions at t = 0, restart file) has been read and checked.
int run_scene(const RunOptions& options);

// The handler of the exception in flight (call it in a catch block): prints one line on stderr,
// "biofsi: <file>: <what>" (the scene's path when the error does not name its own file), and
// returns the ExitCode of its kind: OutputError 4, SolveError 3, every other error 1.
int report_error(const std::string& scene_path);

}  // namespace biofsi
