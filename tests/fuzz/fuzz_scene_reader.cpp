// libFuzzer target for the scene reader (load_scene: the YAML scene file, each field's section
// reader, expressions, the box mesh's sets and the --set overrides). The input is written to a
// scene file in an empty folder (so a Gmsh mesh it names resolves to nothing the fuzzer made) and
// loaded. Its leading lines of the form "#set key=value" are also passed as overrides, as
// `biofsi --set key=value` would; to YAML they are comments. SceneError is the reader's documented
// answer to a bad scene; any other exception, a sanitizer report, a crash, a hang or running out
// of memory is a finding.
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "io/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = biofsi::fuzz::scratch_dir("scene") + "/scene.yaml";
  biofsi::fuzz::write_input(path, data, size);
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> overrides;
  const std::string prefix = "#set ";
  for (size_t pos = 0; text.compare(pos, prefix.size(), prefix) == 0;) {
    const size_t end = std::min(text.find('\n', pos), text.size());
    overrides.push_back(text.substr(pos + prefix.size(), end - pos - prefix.size()));
    pos = end + 1;
    if (pos >= text.size()) break;
  }
  try {
    biofsi::load_scene(path, overrides);
  } catch (const biofsi::SceneError&) {
  }
  return 0;
}
