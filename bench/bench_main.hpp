// The main every bench program shares (bench_main.cpp, library biofsi_bench_main): MPI (hypre
// needs it) and Kokkos around Google Benchmark. A program supplies register_benchmarks and
// release_benchmarks. Kokkos fixes its OpenMP thread count at initialisation (OMP_NUM_THREADS), so
// thread scaling is measured by one process per thread count (bench/run).
//
// The context of every run names the Kokkos execution space and concurrency, the SIMD width and
// the hypre linked. A program's own options are --name=VALUE; any other argument goes to Google
// Benchmark (and Kokkos' --kokkos-* to Kokkos), and an unknown one stops the program with status 2.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

namespace biofsi {
namespace bench {

// The program's --name=VALUE options; reading one marks it as known.
class Options {
 public:
  void set(const std::string& name, const std::string& value) { values_[name] = value; }
  // The value, or `fallback` where the option is absent; std::invalid_argument if it is no
  // positive number.
  double positive(const std::string& name, double fallback);
  // A comma-separated list of positive integers, e.g. "1,2".
  std::vector<int> positive_list(const std::string& name, const std::vector<int>& fallback);
  // Options given but never read.
  std::vector<std::string> unknown() const;

 private:
  std::map<std::string, std::string> values_;
  std::set<std::string> read_;
};

// Supplied by each program: registers its benchmarks (throws std::invalid_argument on a bad
// option) ...
void register_benchmarks(Options& options);
// ... and frees what they keep (hypre objects, Views) before MPI and Kokkos are torn down.
void release_benchmarks();

}  // namespace bench
}  // namespace biofsi
