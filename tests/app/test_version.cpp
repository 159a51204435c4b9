// `biofsi --version`'s report, and that the hypre it names behaves as it claims: a hypre built
// with OpenMP runs on as many threads as omp_set_num_threads asks, one without on one.
#include <HYPRE_config.h>
#include <_hypre_utilities.h>
#include <gtest/gtest.h>
#include <omp.h>

#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "app/version.hpp"
#include "biofsi_version.hpp"

namespace {

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::string line_starting(const std::string& text, const std::string& prefix) {
  for (const auto& line : lines(text))
    if (line.rfind(prefix, 0) == 0) return line;
  return {};
}

}  // namespace

TEST(VersionReport, NamesEveryDependency) {
  const std::string report = biofsi::version_report();
  EXPECT_EQ(line_starting(report, "biofsi "), std::string("biofsi ") + BIOFSI_VERSION);
  for (const char* prefix : {"  Kokkos ", "  hypre ", "  MPI: ", "  HDF5 "})
    EXPECT_FALSE(line_starting(report, prefix).empty()) << "no '" << prefix << "' line in\n"
                                                        << report;
}

TEST(VersionReport, HypreLineSaysVersionThreadingAndOrigin) {
  const std::string hypre = line_starting(biofsi::version_report(), "  hypre ");
  EXPECT_TRUE(std::regex_match(
      hypre, std::regex(R"(  hypre \d+\.\d+\.\d+ \((OpenMP|no OpenMP: BoomerAMG on one thread), )"
                        R"((CUDA|no CUDA)\) from .+)")))
      << hypre;
  EXPECT_NE(hypre.find(std::string("hypre ") + HYPRE_RELEASE_VERSION + " ("), std::string::npos);
  EXPECT_NE(hypre.find(std::string(" from ") + BIOFSI_HYPRE_LOCATION), std::string::npos);
}

// hypre_NumThreads() is compiled into the library, so this checks the library linked, not only
// the header the report reads.
TEST(VersionReport, HypreThreadsAreWhatTheReportClaims) {
  const int previous = omp_get_max_threads();
  for (int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);
    EXPECT_EQ(hypre_NumThreads(), BIOFSI_HYPRE_OPENMP ? threads : 1) << threads << " threads";
  }
  omp_set_num_threads(previous);
  const std::string hypre = line_starting(biofsi::version_report(), "  hypre ");
  EXPECT_EQ(hypre.find("no OpenMP") == std::string::npos, BIOFSI_HYPRE_OPENMP == 1) << hypre;
}
