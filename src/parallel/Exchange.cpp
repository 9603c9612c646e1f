#include "spall/parallel/Exchange.hpp"

#include "spall/core/Error.hpp"

#include <limits>
#include <string>

namespace spall::parallel {

namespace {

int checkedInt(std::size_t n, const char* what) {
  // MPI counts are int: a block over 2 GiB needs another scheme (derived types); say so rather
  // than wrap around.
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw RunError(std::string("MPI exchange: ") + what + " exceeds 2 GiB on one rank pair");
  return static_cast<int>(n);
}

} // namespace

std::vector<std::size_t> exchangeCounts(MPI_Comm comm, const std::vector<std::size_t>& countTo) {
  std::vector<std::uint64_t> out(countTo.begin(), countTo.end()), in(countTo.size());
  MPI_Alltoall(out.data(), 1, MPI_UINT64_T, in.data(), 1, MPI_UINT64_T, comm);
  return {in.begin(), in.end()};
}

ExchangeResult exchangeBytes(MPI_Comm comm, const std::vector<std::byte>& send,
                             const std::vector<std::size_t>& countTo) {
  const std::size_t ranks = countTo.size();
  ExchangeResult r;
  r.countFrom = exchangeCounts(comm, countTo);
  r.offsetFrom.assign(ranks, 0);
  std::vector<int> sc(ranks), sd(ranks), rc(ranks), rd(ranks);
  std::size_t so = 0, ro = 0;
  for (std::size_t k = 0; k < ranks; ++k) {
    sc[k] = checkedInt(countTo[k], "send block");
    sd[k] = checkedInt(so, "send buffer");
    rc[k] = checkedInt(r.countFrom[k], "receive block");
    rd[k] = checkedInt(ro, "receive buffer");
    r.offsetFrom[k] = ro;
    so += countTo[k];
    ro += r.countFrom[k];
  }
  r.data.resize(ro);
  MPI_Alltoallv(send.data(), sc.data(), sd.data(), MPI_BYTE, r.data.data(), rc.data(), rd.data(),
                MPI_BYTE, comm);
  return r;
}

} // namespace spall::parallel
