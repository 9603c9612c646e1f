#pragma once
// Threads inside a rank (OpenMP). A threaded loop writes row i from row i's inputs only (the
// neighbor sums gather into i in the row's canonical order) and reductions combine in a fixed
// order, so a run is the same bit for bit on any thread count, as on any rank count.
#include <cstddef>

namespace spall {

// The threads each rank runs its loops with: OMP_NUM_THREADS, or 1 when it is not set (an
// `mpirun -np <cores>` job must not start cores x cores threads); SPALL_THREADED_ROWS.
void configureThreads();
int threadCount();
// Sets the count for the loops that follow (tests; a run takes it from OMP_NUM_THREADS).
void setThreadCount(int threads);

// Whether a loop over n rows runs in threads (`#pragma omp ... if (threaded(n))`): below ~4k rows
// (SPALL_THREADED_ROWS, default 4096) a parallel region's start and barrier (microseconds; far
// more when the cores are shared, as the waiting threads spin) cost more than the rows. Either
// way the results are the same; tests set it to 1 to run small decks in threads.
namespace detail {
inline std::size_t threadedRows = 4096;
}
inline bool threaded(std::size_t n) {
  return n >= detail::threadedRows;
}
void setThreadedRows(std::size_t rows);

// [begin, end) of chunk c of `chunks` equal parts of [0, n): a static split of a loop into
// pieces whose results are concatenated in chunk order.
inline std::size_t chunkBegin(std::size_t n, std::size_t chunks, std::size_t c) {
  return n / chunks * c + (c < n % chunks ? c : n % chunks);
}

} // namespace spall
