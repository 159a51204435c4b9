# Finds biofsi's dependencies. Kokkos: Kokkos_ROOT (variable or environment) wins; otherwise the
# cache that scripts/setup fills. A Serial-only Kokkos is refused: it would run on one thread.
# hypre likewise: HYPRE_ROOT, else the cache's OpenMP build, else Debian's libhypre-dev.
if(DEFINED ENV{BIOFSI_CACHE})
  set(_biofsi_cache "$ENV{BIOFSI_CACHE}")
else()
  set(_biofsi_cache "$ENV{HOME}/.cache/biofsi")
endif()
if(NOT DEFINED Kokkos_ROOT AND NOT DEFINED ENV{Kokkos_ROOT})
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
  # UMFPACK (SuiteSparse, Debian's libsuitesparse-dev) for the sparse direct preconditioner.
  find_path(UMFPACK_INCLUDE_DIR umfpack.h PATH_SUFFIXES suitesparse REQUIRED)
  find_library(UMFPACK_LIBRARY umfpack REQUIRED)
  add_library(biofsi::umfpack INTERFACE IMPORTED)
  set_target_properties(biofsi::umfpack PROPERTIES INTERFACE_INCLUDE_DIRECTORIES
                        "${UMFPACK_INCLUDE_DIR}" INTERFACE_LINK_LIBRARIES "${UMFPACK_LIBRARY}")
  set(HDF5_PREFER_PARALLEL TRUE)
  find_package(HDF5 REQUIRED COMPONENTS C)
  if(NOT HDF5_IS_PARALLEL)
    message(WARNING "biofsi: HDF5 at ${HDF5_INCLUDE_DIRS} is not the MPI build (libhdf5-openmpi-dev)")
  endif()
  # hypre for BoomerAMG, as the target biofsi::hypre. HYPRE_ROOT (variable or environment) wins;
  # otherwise, with BIOFSI_HYPRE_FLAVOUR openmp or cuda, that build in the cache scripts/setup
  # fills; otherwise Debian's libhypre-dev, which has no OpenMP. Sets BIOFSI_HYPRE_VERSION,
  # BIOFSI_HYPRE_LOCATION (a path, or "Debian libhypre-dev"), BIOFSI_HYPRE_OPENMP and
  # BIOFSI_HYPRE_CUDA (0 or 1) from the HYPRE_config.h found, for the version report.
  # Debian's is the default: on 2 threads the OpenMP build's BoomerAMG made one of the test
  # suite's fluid tests 18x slower (docs/performance.md).
  set(BIOFSI_HYPRE_FLAVOUR "debian" CACHE STRING
      "debian (Debian's libhypre-dev), openmp (scripts/setup --hypre-openmp) or cuda")
  if(NOT DEFINED HYPRE_ROOT AND DEFINED ENV{HYPRE_ROOT})
    set(HYPRE_ROOT "$ENV{HYPRE_ROOT}")
  endif()
  if(NOT DEFINED HYPRE_ROOT AND NOT BIOFSI_HYPRE_FLAVOUR STREQUAL "debian")
    set(_hypre_cached "${_biofsi_cache}/hypre-2.26.0-${BIOFSI_HYPRE_FLAVOUR}")
    if(EXISTS "${_hypre_cached}/include/HYPRE_config.h")
      set(HYPRE_ROOT "${_hypre_cached}")
    else()
      message(FATAL_ERROR "biofsi: BIOFSI_HYPRE_FLAVOUR=${BIOFSI_HYPRE_FLAVOUR} but ${_hypre_cached} "
        "holds no hypre; build it with scripts/setup --hypre-${BIOFSI_HYPRE_FLAVOUR}, or configure "
        "with -DBIOFSI_HYPRE_FLAVOUR=debian")
    endif()
  endif()

  if(DEFINED HYPRE_ROOT)
    # hypre's own CMake package carries what its static library needs (MPI, OpenMP, CUDA libraries).
    # HYPRE_DIR is forgotten so that a changed HYPRE_ROOT or flavour is honoured on reconfiguring.
    unset(HYPRE_DIR CACHE)
    find_package(HYPRE CONFIG REQUIRED PATHS "${HYPRE_ROOT}" NO_DEFAULT_PATH)
    set(_hypre_config "${HYPRE_ROOT}/include/HYPRE_config.h")
    add_library(biofsi::hypre INTERFACE IMPORTED)
    set_target_properties(biofsi::hypre PROPERTIES INTERFACE_LINK_LIBRARIES HYPRE::HYPRE)
    set(BIOFSI_HYPRE_LOCATION "${HYPRE_ROOT}")
  else()
    find_path(HYPRE_INCLUDE_DIR HYPRE.h PATH_SUFFIXES hypre REQUIRED)
    find_library(HYPRE_LIBRARY NAMES HYPRE REQUIRED)
    set(_hypre_config "${HYPRE_INCLUDE_DIR}/HYPRE_config.h")
    add_library(biofsi::hypre INTERFACE IMPORTED)
    set_target_properties(biofsi::hypre PROPERTIES
      INTERFACE_INCLUDE_DIRECTORIES "${HYPRE_INCLUDE_DIR}"
      INTERFACE_LINK_LIBRARIES "${HYPRE_LIBRARY};MPI::MPI_C")
    set(BIOFSI_HYPRE_LOCATION "Debian libhypre-dev")
  endif()

  file(STRINGS "${_hypre_config}" _hypre_version REGEX "^#define HYPRE_RELEASE_VERSION ")
  string(REGEX REPLACE ".*\"(.*)\".*" "\\1" BIOFSI_HYPRE_VERSION "${_hypre_version}")
  foreach(feature OPENMP CUDA)
    file(STRINGS "${_hypre_config}" _hypre_using REGEX "^#define HYPRE_USING_${feature} ")
    if(_hypre_using)
      set(BIOFSI_HYPRE_${feature} 1)
    else()
      set(BIOFSI_HYPRE_${feature} 0)
    endif()
  endforeach()

  if(BIOFSI_HYPRE_CUDA)
    # BoomerAmg (src/solvers/hypre_amg.cpp) hands hypre host vectors; a CUDA hypre keeps them in
    # device memory, so its build only serves a future GPU port of that wrapper.
    message(FATAL_ERROR
      "biofsi: hypre at '${BIOFSI_HYPRE_LOCATION}' is a CUDA build; biofsi's BoomerAMG "
      "wrapper needs a host build. Use BIOFSI_HYPRE_FLAVOUR=openmp (or debian), or a HYPRE_ROOT "
      "without CUDA.")
  endif()
  if(BIOFSI_HYPRE_OPENMP)
    message(STATUS
      "biofsi: hypre ${BIOFSI_HYPRE_VERSION} with OpenMP from ${BIOFSI_HYPRE_LOCATION}")
  else()
    message(STATUS
      "biofsi: hypre ${BIOFSI_HYPRE_VERSION} without OpenMP from ${BIOFSI_HYPRE_LOCATION}: "
      "BoomerAMG set-up and V-cycles run on one thread whatever OMP_NUM_THREADS says "
      "(hypre with OpenMP: scripts/setup --hypre-openmp, -DBIOFSI_HYPRE_FLAVOUR=openmp)")
  endif()
  if(BIOFSI_BUILD_BENCH)
    find_package(benchmark REQUIRED)
  endif()
endif()
