#pragma once
// MPI for the unit tests that call it (test_mpi_environment.cpp says why it is not always on).

namespace spall::fixtures {

// Starts MPI unless it runs already; finalised after the last test.
void requireMpi();

} // namespace spall::fixtures
