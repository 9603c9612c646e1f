// Unit tests link gtest_main, which knows nothing of MPI. Most tests never call it, and starting
// it costs a process ~0.25 s (ctest runs every test in a process of its own: a minute of the
// suite). A test that calls MPI (collective HDF5 writes, reductions) starts it first with
// fixtures::requireMpi(); it is finalised after the last test, on however many ranks the binary
// was started (usually one). A test that forgets fails at once: Open MPI aborts a call made
// before MPI_Init, naming the call.
#include "unit/MpiForTests.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include "spall/parallel/Mpi.hpp"

#include <memory>

namespace {

std::unique_ptr<spall::parallel::MpiSession>& lazySession() {
  static std::unique_ptr<spall::parallel::MpiSession> s; // when a test started MPI
  return s;
}

class MpiEnvironment : public ::testing::Environment {
public:
  void TearDown() override { lazySession().reset(); }
};

// gtest takes ownership; registration before main() is allowed.
[[maybe_unused]] ::testing::Environment* const kMpiEnvironment =
    ::testing::AddGlobalTestEnvironment(new MpiEnvironment);

} // namespace

namespace spall::fixtures {

void requireMpi() {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) lazySession() = std::make_unique<parallel::MpiSession>();
}

} // namespace spall::fixtures
