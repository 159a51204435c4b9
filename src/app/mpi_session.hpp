// MPI_Init and MPI_Finalize for the biofsi binary and the test programs (tests/main.cpp), with
// LeakSanitizer paused for these two calls only. Open MPI, hwloc and the MPI modules they load
// keep about 120 kB allocated inside MPI_Init that they never free; the report's stacks end in
// modules unloaded before it is printed, so no suppression can name them. Paused here, leak
// detection stays on for every other allocation (the asan preset). Part of src/app: includes MPI
// and the sanitizer interface only.
#pragma once

#include <mpi.h>

#if defined(__SANITIZE_ADDRESS__)
#define BIOFSI_LEAK_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define BIOFSI_LEAK_SANITIZER 1
#endif
#endif
#ifdef BIOFSI_LEAK_SANITIZER
#include <sanitizer/lsan_interface.h>
#endif

namespace biofsi {

inline void mpi_init(int* argc, char*** argv) {
#ifdef BIOFSI_LEAK_SANITIZER
  __lsan_disable();
#endif
  MPI_Init(argc, argv);
#ifdef BIOFSI_LEAK_SANITIZER
  __lsan_enable();
#endif
}

inline void mpi_finalize() {
#ifdef BIOFSI_LEAK_SANITIZER
  __lsan_disable();
#endif
  MPI_Finalize();
#ifdef BIOFSI_LEAK_SANITIZER
  __lsan_enable();
#endif
}

}  // namespace biofsi
