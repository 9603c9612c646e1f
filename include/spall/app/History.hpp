#pragma once
// `spall history OUTDIR --particle ID`: a particle's deformation history as an F-table (io/
// FTable.hpp): every step, if the run recorded it ([output] record_particles), else at every
// snapshot that holds `deformation_gradient`.
#include <cstdint>
#include <string>

namespace spall::app {

struct HistoryOptions {
  std::string outputDir;
  std::uint64_t particle = 0;
  std::string output; // the F-table written ("-": standard output)
  bool overwrite = false;
};

// Throws UsageError (exit 2) when the particle has no history in the directory.
void writeHistory(const HistoryOptions& options);

} // namespace spall::app
