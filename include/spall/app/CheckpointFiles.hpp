#pragma once
// The files of a restart chain in an output directory (docs/reference.md, output layout):
// checkpoints/ckpt_NNNNNN.h5 (NNNNNN = step), checkpoints/latest naming the newest complete one,
// and the logs and snapshots a restart continues. Rank 0 only; no MPI here.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace spall::app {

std::string checkpointFileName(std::int64_t step);

// Points checkpoints/latest at `fileName` atomically: a killed writer leaves the old pointer.
void publishLatest(const std::filesystem::path& checkpointDir, const std::string& fileName);

// Deletes all but the newest `keep` checkpoints (by step); never the one `latest` names.
void pruneCheckpoints(const std::filesystem::path& checkpointDir, int keep);

// Deletes the *.tmp a killed writer left (at a restart, when no writer can be running).
void removeStaleTemporaries(const std::filesystem::path& checkpointDir);

// The checkpoints `--restart` may use, in the order to try them. "latest": the file `latest`
// names, then every other complete checkpoint, newest first (`fallback` true, and `problem`
// says what is wrong with `latest` if anything). A path: that file only.
struct RestartCandidates {
  std::vector<std::filesystem::path> files;
  bool fallback = false;
  std::string problem;
};
RestartCandidates restartCandidates(const std::filesystem::path& outputDir,
                                    const std::string& restart);

// A restart from (step, time) continues the logs: history.csv keeps its rows with step <= step,
// probes.csv those with time <= time (rows a crashed run wrote after its checkpoint go). Both
// are rewritten atomically; a missing file is left missing.
void truncateHistory(const std::filesystem::path& file, std::int64_t step);
void truncateProbes(const std::filesystem::path& file, double time);

// Removes snapshots/snap_NNNNNN.{h5,xmf}, snap_NNNNNN_grid.xmf (and leftover .tmp) numbered `first`
// and above: those a crashed run wrote after its checkpoint; the restart writes them again.
void removeSnapshotsFrom(const std::filesystem::path& snapshotDir, int first);

} // namespace spall::app
