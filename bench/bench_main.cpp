// The shared main of the bench programs (bench_main.hpp).
#include "bench/bench_main.hpp"

#include <HYPRE_config.h>
#include <benchmark/benchmark.h>
#include <mpi.h>

#include <Kokkos_Core.hpp>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "biofsi_version.hpp"
#include "kernels/core/simd.hpp"

namespace biofsi {
namespace bench {
namespace {

double parse_positive(const std::string& name, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !(v > 0))
    throw std::invalid_argument("--" + name + "=" + text + ": not a positive number");
  return v;
}

void add_context() {
  benchmark::AddCustomContext("kokkos_concurrency",
                              std::to_string(Kokkos::DefaultExecutionSpace().concurrency()));
  benchmark::AddCustomContext("kokkos_execution_space", Kokkos::DefaultExecutionSpace::name());
  benchmark::AddCustomContext("simd_width", std::to_string(simd_width));
  benchmark::AddCustomContext("hypre_version", HYPRE_RELEASE_VERSION);
  benchmark::AddCustomContext("hypre_location", BIOFSI_HYPRE_LOCATION);
  benchmark::AddCustomContext("hypre_openmp", BIOFSI_HYPRE_OPENMP ? "yes" : "no");
}

// Registers and runs the benchmarks; 2 on a bad command line.
int run(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);  // takes Google Benchmark's flags off argv
  Options options;
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto eq = arg.find('=');
    if (i > 0 && arg.rfind("--", 0) == 0 && eq != std::string::npos)
      options.set(arg.substr(2, eq - 2), arg.substr(eq + 1));
    else
      rest.push_back(argv[i]);
  }
  int n_rest = static_cast<int>(rest.size());
  if (benchmark::ReportUnrecognizedArguments(n_rest, rest.data())) return 2;
  try {
    register_benchmarks(options);
  } catch (const std::invalid_argument& e) {
    std::cerr << argv[0] << ": " << e.what() << "\n";
    return 2;
  }
  for (const auto& name : options.unknown()) {
    std::cerr << argv[0] << ": unknown option --" << name << "\n";
    return 2;
  }
  add_context();
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}

}  // namespace

double Options::positive(const std::string& name, double fallback) {
  read_.insert(name);
  const auto it = values_.find(name);
  return it == values_.end() ? fallback : parse_positive(name, it->second);
}

std::vector<int> Options::positive_list(const std::string& name, const std::vector<int>& fallback) {
  read_.insert(name);
  const auto it = values_.find(name);
  if (it == values_.end()) return fallback;
  std::vector<int> out;
  std::stringstream in(it->second);
  std::string item;
  while (std::getline(in, item, ',')) {
    const double v = parse_positive(name, item);
    if (v != static_cast<int>(v))
      throw std::invalid_argument("--" + name + "=" + it->second + ": not a list of integers");
    out.push_back(static_cast<int>(v));
  }
  if (out.empty()) throw std::invalid_argument("--" + name + "= needs at least one value");
  return out;
}

std::vector<std::string> Options::unknown() const {
  std::vector<std::string> out;
  for (const auto& [name, value] : values_)
    if (!read_.count(name)) out.push_back(name);
  return out;
}

}  // namespace bench
}  // namespace biofsi

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  Kokkos::initialize(argc, argv);
  const int rc = biofsi::bench::run(argc, argv);
  benchmark::Shutdown();
  biofsi::bench::release_benchmarks();
  Kokkos::finalize();
  MPI_Finalize();
  return rc;
}
