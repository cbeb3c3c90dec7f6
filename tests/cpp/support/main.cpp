// GoogleTest runner for tests that need MPI and dolfinx (as dolfinx's own
// cpp/test/main.cpp): MPI must outlive every dolfinx object.
#include <dolfinx/common/log.h>
#include <gtest/gtest.h>
#include <mpi.h>

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  dolfinx::init_logging(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  const int status = RUN_ALL_TESTS();
  MPI_Finalize();
  return status;
}
