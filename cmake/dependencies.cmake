# Finds biofsi's dependencies. Kokkos: Kokkos_ROOT (variable or environment) wins; otherwise the
# cache that scripts/setup fills. A Serial-only Kokkos is refused: it would run on one thread.
if(NOT DEFINED Kokkos_ROOT AND NOT DEFINED ENV{Kokkos_ROOT})
  if(DEFINED ENV{BIOFSI_CACHE})
    set(_biofsi_cache "$ENV{BIOFSI_CACHE}")
  else()
    set(_biofsi_cache "$ENV{HOME}/.cache/biofsi")
  endif()
  set(BIOFSI_KOKKOS_FLAVOUR "openmp" CACHE STRING "which cached Kokkos build to use (openmp or cuda)")
  set(Kokkos_ROOT "${_biofsi_cache}/kokkos-3.4.01-${BIOFSI_KOKKOS_FLAVOUR}")
endif()
find_package(Kokkos REQUIRED)
if(NOT "OPENMP" IN_LIST Kokkos_DEVICES AND NOT "CUDA" IN_LIST Kokkos_DEVICES)
  message(FATAL_ERROR
    "biofsi: the Kokkos found at '${Kokkos_DIR}' has devices '${Kokkos_DEVICES}'; biofsi needs "
    "the OpenMP (or CUDA) backend. A Serial-only Kokkos (such as Debian's libtrilinos-kokkos-dev) "
    "would silently run on one thread. Run scripts/setup, or point Kokkos_ROOT at a Kokkos built "
    "with -DKokkos_ENABLE_OPENMP=ON.")
endif()
message(STATUS "biofsi: Kokkos ${Kokkos_VERSION} with devices ${Kokkos_DEVICES}")

if(BIOFSI_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()

if(NOT BIOFSI_KERNELS_ONLY)
  find_package(MPI REQUIRED COMPONENTS C CXX)
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(MUPARSER REQUIRED IMPORTED_TARGET muparser)
  find_package(yaml-cpp REQUIRED)
  find_package(Eigen3 REQUIRED NO_MODULE)
  set(HDF5_PREFER_PARALLEL TRUE)
  find_package(HDF5 REQUIRED COMPONENTS C)
  if(NOT HDF5_IS_PARALLEL)
    message(WARNING "biofsi: HDF5 at ${HDF5_INCLUDE_DIRS} is not the MPI build (libhdf5-openmpi-dev)")
  endif()
  find_path(HYPRE_INCLUDE_DIR HYPRE.h PATH_SUFFIXES hypre REQUIRED)
  find_library(HYPRE_LIBRARY NAMES HYPRE REQUIRED)
  add_library(biofsi::hypre INTERFACE IMPORTED)
  set_target_properties(biofsi::hypre PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${HYPRE_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${HYPRE_LIBRARY};MPI::MPI_C")
  if(BIOFSI_BUILD_BENCH)
    find_package(benchmark REQUIRED)
  endif()
endif()
