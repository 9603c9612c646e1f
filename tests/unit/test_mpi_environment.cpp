// Unit tests link gtest_main, which knows nothing of MPI. Tests that call MPI (collective HDF5
// writes, reductions) share this environment: MPI is initialised once before the first test and
// finalised after the last, on however many ranks the binary was started (usually one).
#include <gtest/gtest.h>
#include <mpi.h>

#include "spall/parallel/Mpi.hpp"

#include <memory>

namespace {

class MpiEnvironment : public ::testing::Environment {
public:
  void SetUp() override {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) session_ = std::make_unique<spall::parallel::MpiSession>();
  }
  void TearDown() override { session_.reset(); }

private:
  std::unique_ptr<spall::parallel::MpiSession> session_; // when this environment started MPI
};

// gtest takes ownership; registration before main() is allowed.
[[maybe_unused]] ::testing::Environment* const kMpiEnvironment =
    ::testing::AddGlobalTestEnvironment(new MpiEnvironment);

} // namespace
