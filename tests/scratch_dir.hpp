// Scratch directories for a test's files under the temporary directory ($TMPDIR), named after the
// test, so that the tests of one build tree never share one; give each build tree its own TMPDIR
// to run two trees' tests at once.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

namespace biofsi {
namespace test {

// <tmp>/biofsi_<name>_<test name>, removed (not created): what the previous run left goes first.
inline std::filesystem::path scratch_dir(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string test = info ? std::string("_") + info->name() : std::string();
  std::replace(test.begin(), test.end(), '/', '_');
  const auto dir = std::filesystem::temp_directory_path() / ("biofsi_" + name + test);
  std::filesystem::remove_all(dir);
  return dir;
}

}  // namespace test
}  // namespace biofsi
