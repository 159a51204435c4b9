// The smallest scene text the tests build on: a 2 x 2 x 1 box of one block with scalar
// diffusion's material; a scene adds its fields and time sections.
#pragma once

#include <string>

namespace biofsi {
namespace test {

inline const std::string kTinyBoxScene = R"yaml(mesh:
  type: box
  x: [0, 1]
  z: [0, 0.1]
  nx: 2
  nz: 1
  blocks:
    - {name: fluid, y: [0, 1], ny: 2}
materials:
  fluid: {diffusivity: 1.0e-3}
)yaml";

}  // namespace test
}  // namespace biofsi
