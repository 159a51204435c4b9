// src/app: the command-line program — argument parsing, version report, and the driver that
// turns a scene into solved fields and output. It may depend on every other src/ folder; nothing
// depends on it.
#pragma once

#include <string>

namespace biofsi {

// Multi-line report: biofsi, Kokkos (version and enabled backends), hypre (version, OpenMP and
// CUDA or not, install prefix or "Debian libhypre-dev"), MPI library, HDF5.
std::string version_report();

}  // namespace biofsi
