// biofsi command line: `biofsi --version`, `biofsi run SCENE.yaml [--out DIR] [--set key=value]...
// [--overwrite] [--restart CHECKPOINT]`. Exit codes: biofsi::ExitCode (app/run.hpp).
#include <Kokkos_Core.hpp>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "app/mpi_session.hpp"
#include "app/run.hpp"
#include "app/version.hpp"

namespace {

const char* usage =
    "usage: biofsi --version\n"
    "       biofsi run SCENE.yaml [--out DIR] [--set key=value]... [--overwrite]\n"
    "                             [--restart CHECKPOINT]\n"
    "  --out DIR        write results to DIR instead of the scene's output.directory\n"
    "  --set key=value  override a scene value, e.g. --set time.dt=0.5 --set mesh.nx=80\n"
    "  --overwrite      replace results already in the output directory\n"
    "  --restart FILE   continue a growth run from its checkpoint_NNNNNN.h5\n";

// Returns the exit code; fills options when the command is `run`.
int parse(int argc, char** argv, bool& version, biofsi::RunOptions& options) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty()) {
    std::cerr << usage;
    return biofsi::kExitBadCommandLine;
  }
  if (args[0] == "--version" || args[0] == "version") {
    version = true;
    return 0;
  }
  if (args[0] == "--help" || args[0] == "-h") {
    std::cout << usage;
    return -1;
  }
  if (args[0] != "run") {
    std::cerr << "biofsi: unknown command '" << args[0] << "'\n" << usage;
    return biofsi::kExitBadCommandLine;
  }
  for (size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&](const char* flag) -> const std::string* {
      if (i + 1 >= args.size()) {
        std::cerr << "biofsi: " << flag << " needs a value\n" << usage;
        return nullptr;
      }
      return &args[++i];
    };
    if (a == "--out") {
      const std::string* v = value("--out");
      if (!v) return biofsi::kExitBadCommandLine;
      options.out_dir = *v;
    } else if (a == "--set") {
      const std::string* v = value("--set");
      if (!v) return biofsi::kExitBadCommandLine;
      options.overrides.push_back(*v);
    } else if (a == "--restart") {
      const std::string* v = value("--restart");
      if (!v) return biofsi::kExitBadCommandLine;
      options.restart = *v;
    } else if (a == "--overwrite") {
      options.overwrite = true;
    } else if (a.rfind("--kokkos", 0) == 0) {
      continue;  // Kokkos' own options (--kokkos-num-threads=N, ...), read by Kokkos::initialize
    } else if (!a.empty() && a[0] == '-') {
      std::cerr << "biofsi: unknown option '" << a << "'\n" << usage;
      return biofsi::kExitBadCommandLine;
    } else if (options.scene_path.empty()) {
      options.scene_path = a;
    } else {
      std::cerr << "biofsi: more than one scene given ('" << options.scene_path << "', '" << a
                << "')\n";
      return biofsi::kExitBadCommandLine;
    }
  }
  if (options.scene_path.empty()) {
    std::cerr << "biofsi: run needs a scene file\n" << usage;
    return biofsi::kExitBadCommandLine;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  bool version = false;
  biofsi::RunOptions options;
  const int parsed = parse(argc, argv, version, options);
  if (parsed != 0) return parsed < 0 ? 0 : parsed;
  biofsi::mpi_init(&argc, &argv);
  int rc = 0;
  Kokkos::initialize(argc, argv);
  try {
    if (version)
      std::cout << biofsi::version_report();
    else
      rc = biofsi::run_scene(options);
  } catch (...) {
    rc = biofsi::report_error(options.scene_path);
  }
  Kokkos::finalize();
  biofsi::mpi_finalize();
  return rc;
}
