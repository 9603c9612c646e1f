#pragma once
// The MPI context and the global reductions the run loop needs. Physics-free.
#include <mpi.h>

#include <climits>
#include <cstdint>
#include <exception>
#include <span>
#include <string>
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

// Copies `root`'s string to every rank of comm.
void broadcast(std::string& s, int root, MPI_Comm comm);

// Collective error agreement, so that no rank is left waiting in a collective call that the
// others skipped. agreeOnFailure runs f on every rank; if any rank throws, every rank throws
// Error with the lowest failing rank's message. onRoot runs f on rank 0 alone (a decision about
// files, say) and, if it throws, every rank throws Error with rank 0's message.
template <class Error, class F> void agreeOnFailure(MPI_Comm comm, F&& f) {
  std::string message;
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  int mine = INT_MAX;
  try {
    f();
  } catch (const std::exception& e) {
    message = e.what();
    mine = rank;
  }
  int first = INT_MAX;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == INT_MAX) return;
  broadcast(message, first, comm);
  throw Error(message);
}

template <class Error, class F> void onRoot(MPI_Comm comm, F&& f) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::string message;
  int failed = 0;
  if (rank == 0) {
    try {
      f();
    } catch (const std::exception& e) {
      message = e.what();
      failed = 1;
    }
  }
  MPI_Bcast(&failed, 1, MPI_INT, 0, comm);
  if (!failed) return;
  broadcast(message, 0, comm);
  throw Error(message);
}

// RAII MPI_Init_thread / MPI_Finalize for the executable and the unit tests. In a process no
// launcher started (a singleton: `spall check`, a one-rank run, a unit test), Open MPI is first
// told the process never spawns, so it starts no support daemon for it (0.35 -> 0.24 s for
// `spall info`), and is given a session directory of its own, made under $TMPDIR and removed
// after MPI_Finalize. Isolated singletons all name their session directory alike (jf.0/1), so
// with a shared one each one's MPI_Finalize deletes the others' MPI-IO scratch files and their
// snapshot writes fail (tests/cli/test_concurrent_runs.py). It is also given the ob1
// point-to-point layer unless OMPI_MCA_pml is set (src/parallel/Mpi.cpp: 0.24 -> 0.04 s). Nothing
// is set under mpirun or srun, or where the user set OMPI_MCA_ess_singleton_isolated or
// OMPI_MCA_orte_tmpdir_base; what was set is unset again after MPI_Init, so that a process this
// one starts makes its own.
class MpiSession {
public:
  MpiSession(int& argc, char**& argv);
  MpiSession(); // without the command line (the unit tests)
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

private:
  std::string sessionBase_;
};

} // namespace spall::parallel
