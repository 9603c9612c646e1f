#pragma once
// The MPI context and the global reductions the run loop needs. Physics-free.
#include <mpi.h>

#include <cstdint>
#include <span>
#include <vector>

namespace spall::parallel {

class MpiContext {
public:
  explicit MpiContext(MPI_Comm comm = MPI_COMM_WORLD);
  MPI_Comm comm() const { return comm_; }
  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }

  double min(double v) const;
  double max(double v) const;
  double sum(double v) const;
  std::uint64_t sum(std::uint64_t v) const;
  // Element-wise sum in place. Every rank adds in rank order, so the result does not depend on
  // the reduction tree (MPI_Allreduce may sum in any order).
  void sumInRankOrder(std::span<double> values) const;

private:
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
};

// RAII MPI_Init_thread / MPI_Finalize for the executable.
class MpiSession {
public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
};

} // namespace spall::parallel
