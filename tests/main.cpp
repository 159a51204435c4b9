// GoogleTest entry for host-code tests: MPI (hypre needs it) and Kokkos live around all tests.
#include <gtest/gtest.h>
#include <mpi.h>

#include <Kokkos_Core.hpp>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  MPI_Init(&argc, &argv);
  Kokkos::initialize(argc, argv);
  int rc = 0;
  { rc = RUN_ALL_TESTS(); }
  Kokkos::finalize();
  MPI_Finalize();
  return rc;
}
