#include "app/version.hpp"

#include <HYPRE_config.h>
#include <hdf5.h>
#include <mpi.h>

#include <Kokkos_Core.hpp>
#include <sstream>

#include "biofsi_version.hpp"

namespace biofsi {

namespace {

std::string kokkos_version() {
  const int v = KOKKOS_VERSION;  // e.g. 30401
  std::ostringstream s;
  s << v / 10000 << '.' << (v / 100) % 100 << '.';
  if (v % 100 < 10) s << '0';
  s << v % 100;
  return s.str();
}

std::string kokkos_backends() {
  std::string b;
  auto add = [&b](const char* name) { b += (b.empty() ? "" : ", ") + std::string(name); };
#ifdef KOKKOS_ENABLE_CUDA
  add("CUDA");
#endif
#ifdef KOKKOS_ENABLE_OPENMP
  add("OpenMP");
#endif
#ifdef KOKKOS_ENABLE_THREADS
  add("Threads");
#endif
#ifdef KOKKOS_ENABLE_SERIAL
  add("Serial");
#endif
  return b + "; default execution space " + Kokkos::DefaultExecutionSpace::name();
}

// CMake read these from the HYPRE_config.h next to the library it links; a different one on the
// include path would mean that the code is compiled against another hypre than it runs.
#if defined(HYPRE_USING_OPENMP) != BIOFSI_HYPRE_OPENMP || \
    defined(HYPRE_USING_CUDA) != BIOFSI_HYPRE_CUDA
#error "HYPRE_config.h on the include path is not the one of the hypre that CMake chose"
#endif

std::string hypre_build() {
  std::string s = HYPRE_RELEASE_VERSION;
  s += BIOFSI_HYPRE_OPENMP ? " (OpenMP" : " (no OpenMP: BoomerAMG on one thread";
  s += BIOFSI_HYPRE_CUDA ? ", CUDA" : ", no CUDA";
  return s + ") from " + BIOFSI_HYPRE_LOCATION;
}

std::string mpi_library() {
  char text[MPI_MAX_LIBRARY_VERSION_STRING];
  int length = 0;
  MPI_Get_library_version(text, &length);
  std::string s(text, length);
  const auto cut = s.find_first_of(",\n");
  return cut == std::string::npos ? s : s.substr(0, cut);
}

}  // namespace

std::string version_report() {
  unsigned major = 0, minor = 0, release = 0;
  H5get_libversion(&major, &minor, &release);
  std::ostringstream s;
  s << "biofsi " << BIOFSI_VERSION << "\n"
    << "  Kokkos " << kokkos_version() << " (" << kokkos_backends() << ")\n"
    << "  hypre " << hypre_build() << "\n"
    << "  MPI: " << mpi_library() << "\n"
    << "  HDF5 " << major << '.' << minor << '.' << release << "\n";
  return s.str();
}

}  // namespace biofsi
