// GoogleTest entry for host-code tests: MPI (hypre needs it) and Kokkos live around all tests.
#include <gtest/gtest.h>

#include <Kokkos_Core.hpp>

#include "app/mpi_session.hpp"

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  biofsi::mpi_init(&argc, &argv);
  Kokkos::initialize(argc, argv);
  int rc = 0;
  { rc = RUN_ALL_TESTS(); }
  Kokkos::finalize();
  biofsi::mpi_finalize();
  return rc;
}
