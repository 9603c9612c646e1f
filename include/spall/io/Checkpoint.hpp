#pragma once
// Checkpoint files: everything a run needs to continue, in one HDF5 file written collectively by
// all ranks. Physics-free: the particle part is every store column flagged kCheckpoint, written
// generically, so a field a later module registers is checkpointed without touching this code;
// the run's bookkeeping travels as named arrays (CheckpointState) the caller fills.
//
// Layout: root attributes `format` ("spall-checkpoint"), `format_version`, `spall_version`,
// `dimension`, `time`, `step`, `particles`, `ranks`; `/rank_counts` (rows written per rank, in
// rank order); `/state/<name>` one dataset per bookkeeping entry; `/particles/<field>` one
// dataset per checkpointed column, first dimension = particle count. Every dataset carries a
// `checksum` attribute (a sum over rows of a hash of the row's bytes and its global index), so
// a flipped byte is found whatever the rank count that reads it.
#include "spall/core/Error.hpp"
#include "spall/core/ParticleStore.hpp"

#include <mpi.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace spall::io {

inline constexpr int kCheckpointFormatVersion = 1;

// A checkpoint that cannot be used (missing, truncated, corrupt, another format, another
// deck): a usage error, exit 2, raised on every rank alike.
class CheckpointError : public UsageError {
public:
  using UsageError::UsageError;
};

// The run's bookkeeping: named 1-D arrays and texts, identical on every rank.
struct CheckpointState {
  std::map<std::string, std::vector<double>> reals;
  std::map<std::string, std::vector<std::int64_t>> integers;
  std::map<std::string, std::vector<std::uint64_t>> unsignedIntegers;
  std::map<std::string, std::string> texts;

  // Lookups that throw CheckpointError naming `path` and the entry when it is missing.
  const std::vector<double>& realArray(const std::string& name) const;
  const std::vector<std::int64_t>& integerArray(const std::string& name) const;
  const std::vector<std::uint64_t>& unsignedArray(const std::string& name) const;
  const std::string& text(const std::string& name) const;
  double real(const std::string& name) const;
  std::int64_t integer(const std::string& name) const;
  std::string path; // for messages
};

struct CheckpointHeader {
  std::string path;
  int formatVersion = 0;
  std::string version; // spall version that wrote it
  int dimension = 0;
  double time = 0.0;
  std::int64_t step = 0;
  std::uint64_t particles = 0;
  std::vector<std::uint64_t> rankCounts; // rows per writing rank
  std::vector<FieldInfo> fields;         // /particles datasets (flags unused)
  CheckpointState state;
};

struct CheckpointWrite {
  std::uint64_t bytes = 0; // file size
  double seconds = 0.0;    // slowest rank, from open to the published rename
};

// Collective. Writes PATH.tmp, flushes it to disk, renames it to PATH and syncs the directory: a
// file named PATH is always complete. Throws RunError (naming the file and the call) on failure.
CheckpointWrite writeCheckpoint(MPI_Comm comm, const std::string& path, const ParticleStore& s,
                                double time, std::int64_t step, int dimension,
                                const std::string& version, const CheckpointState& state);

// Collective: every rank reads the header and the bookkeeping of PATH independently. Throws
// CheckpointError on every rank if any rank cannot (the lowest such rank's reason).
CheckpointHeader readCheckpointHeader(MPI_Comm comm, const std::string& path);

// Collective: replaces the store's owned particles by this rank's share of the checkpoint. With
// `sameLayout` (as many ranks as wrote it) rank r takes the rows rank r wrote, in their order;
// otherwise an even slice by row, for the caller to redistribute. The store's kCheckpoint
// columns must match the file's datasets one for one (name, type, shape). Checksums are
// verified. Throws CheckpointError on every rank alike; the store is then left empty.
// Returns the bytes this rank read.
std::uint64_t readCheckpointParticles(MPI_Comm comm, const CheckpointHeader& header,
                                      ParticleStore& s, bool sameLayout);

// The order-independent checksum: sum over rows of hash(row bytes, global row index).
std::uint64_t rowChecksum(const void* rows, std::size_t bytesPerRow, std::size_t count,
                          std::uint64_t firstRow);

} // namespace spall::io
