// What the libFuzzer targets share: a private scratch folder for the input written as a file, and
// the checks a mesh the readers accept must pass. Part of tests/fuzz: includes src/mesh only.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

#include "mesh/mesh.hpp"

namespace biofsi::fuzz {

// <temporary directory>/biofsi_fuzz_<what>_<pid>, created once; the input files live there, so
// that relative paths inside an input (a scene's mesh file) resolve to nothing the fuzzer made.
inline std::string scratch_dir(const std::string& what) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("biofsi_fuzz_" + what + "_" + std::to_string(getpid()));
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    std::fprintf(stderr, "%s: %s\n", dir.c_str(), ec.message().c_str());
    std::abort();
  }
  return dir.string();
}

inline void write_input(const std::string& path, const uint8_t* data, size_t size) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f || (size > 0 && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) {
    std::perror(path.c_str());
    std::abort();
  }
}

[[noreturn]] inline void invalid_mesh_accepted(const std::string& why) {
  std::fprintf(stderr, "biofsi fuzz: a mesh was accepted with %s\n", why.c_str());
  std::abort();
}

// A mesh a reader returns: indices in range and every element valid (check_element).
inline void check_mesh(const Mesh& m) {
  const int n = m.n_nodes();
  if (m.element_block.size() != m.conn.size()) invalid_mesh_accepted("element_block's size wrong");
  if (m.global_node_id.size() != m.x.size()) invalid_mesh_accepted("global_node_id's size wrong");
  for (int e = 0; e < m.n_elements(); ++e) {
    for (int v : m.conn[e])
      if (v < 0 || v >= n) invalid_mesh_accepted("a node out of range");
    const int b = m.element_block[e];
    if (b < 0 || b >= static_cast<int>(m.block_names.size()))
      invalid_mesh_accepted("a block out of range");
    if (check_element(m, m.conn[e]).shape != ElementShape::Valid)
      invalid_mesh_accepted("an element that is not valid");
  }
  for (const auto& [name, faces] : m.face_sets)
    for (const auto& f : faces)
      if (f.element < 0 || f.element >= m.n_elements() || f.local_face < 0 || f.local_face >= 6)
        invalid_mesh_accepted("a face of set '" + name + "' out of range");
  for (const auto& [name, nodes] : m.node_sets)
    for (int v : nodes)
      if (v < 0 || v >= n) invalid_mesh_accepted("a node of set '" + name + "' out of range");
}

}  // namespace biofsi::fuzz
