// Unit tests link gtest_main, which knows nothing of MPI. Tests that call MPI (collective HDF5
// writes, reductions) share this environment: MPI is initialised once before the first test and
// finalised after the last, on however many ranks the binary was started (usually one).
#include <gtest/gtest.h>
#include <mpi.h>

#include "spall/parallel/Mpi.hpp"

#include <string>

namespace {

class MpiEnvironment : public ::testing::Environment {
public:
  void SetUp() override {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) {
      sessionBase_ = spall::parallel::preparePrivateSingleton();
      int provided = 0;
      MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
      spall::parallel::singletonStarted(sessionBase_);
      owner_ = true;
    }
  }
  void TearDown() override {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (owner_ && !finalized) MPI_Finalize();
    if (owner_) spall::parallel::removeSessionBase(sessionBase_);
  }

private:
  bool owner_ = false;
  std::string sessionBase_;
};

// gtest takes ownership; registration before main() is allowed.
[[maybe_unused]] ::testing::Environment* const kMpiEnvironment =
    ::testing::AddGlobalTestEnvironment(new MpiEnvironment);

} // namespace
