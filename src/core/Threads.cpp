#include "spall/core/Threads.hpp"

#include <cstdlib>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace spall {

void configureThreads() {
#ifdef _OPENMP
  const char* env = std::getenv("OMP_NUM_THREADS");
  if (env == nullptr || *env == '\0') omp_set_num_threads(1);
#endif
  if (const char* rows = std::getenv("SPALL_THREADED_ROWS")) {
    char* end = nullptr;
    const unsigned long long value = std::strtoull(rows, &end, 10);
    if (end != rows && *end == '\0') setThreadedRows(static_cast<std::size_t>(value));
  }
}

void setThreadedRows(std::size_t rows) {
  detail::threadedRows = rows;
}

int threadCount() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

void setThreadCount([[maybe_unused]] int threads) {
#ifdef _OPENMP
  omp_set_num_threads(threads);
#endif
}

} // namespace spall
