// Checkpoint files across rank counts on synthetic particles (no physics): written by some ranks
// with uneven counts (one rank empty), read back by all ranks in the writers' layout or in even
// slices, every particle exactly once with every field intact; a corrupt file is refused on
// every rank alike, with no rank left waiting.
#include "spall/io/Checkpoint.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <vector>

using namespace spall;
namespace fs = std::filesystem;

namespace {

int rankIn(MPI_Comm c) {
  int r = 0;
  MPI_Comm_rank(c, &r);
  return r;
}
int sizeIn(MPI_Comm c) {
  int s = 1;
  MPI_Comm_size(c, &s);
  return s;
}

// One directory for all ranks (rank 0's pid).
fs::path sharedScratch(const std::string& name) {
  long pid = ::getpid();
  MPI_Bcast(&pid, 1, MPI_LONG, 0, MPI_COMM_WORLD);
  const fs::path dir = fs::temp_directory_path() / ("spall_mpi_ckpt_" + name + std::to_string(pid));
  if (rankIn(MPI_COMM_WORLD) == 0) {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  return dir;
}

struct Store {
  ParticleStore s;
  Field<ParticleId> id;
  Field<Vec<2>> x;
  Field<std::int32_t> tag;
  Store() {
    id = s.add<ParticleId>("id");
    x = s.add<Vec<2>>("position");
    tag = s.add<std::int32_t>("tag");
  }
};

// Rank r of the writers holds 37 r particles (rank 0 none), ids from a global numbering.
Store writerStore(MPI_Comm writers) {
  Store w;
  const int r = rankIn(writers);
  std::uint64_t first = 0;
  for (int k = 0; k < r; ++k) first += 37 * static_cast<std::uint64_t>(k);
  const std::size_t n = 37 * static_cast<std::size_t>(r);
  w.s.resizeLocal(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t g = first + i;
    w.s[w.id][i] = 5 * g + 1;
    w.s[w.x][i] = Vec<2>(std::sqrt(static_cast<double>(g)), -1.0 / (static_cast<double>(g) + 3.0));
    w.s[w.tag][i] = static_cast<std::int32_t>(g % 11) - 5;
  }
  return w;
}

bool intact(const Store& r, std::size_t i) {
  const std::uint64_t g = (r.s[r.id][i] - 1) / 5;
  return r.s[r.x][i] ==
             Vec<2>(std::sqrt(static_cast<double>(g)), -1.0 / (static_cast<double>(g) + 3.0)) &&
         r.s[r.tag][i] == static_cast<std::int32_t>(g % 11) - 5;
}

} // namespace

TEST(CheckpointAcrossRanks, WrittenByFewerRanksReadByAll) {
  const fs::path dir = sharedScratch("fewer");
  const std::string path = (dir / "c.h5").string();
  // Writers: all ranks but the last (on one rank: that rank alone).
  const int world = sizeIn(MPI_COMM_WORLD), me = rankIn(MPI_COMM_WORLD);
  const int writersCount = world > 1 ? world - 1 : 1;
  MPI_Comm writers;
  MPI_Comm_split(MPI_COMM_WORLD, me < writersCount ? 0 : MPI_UNDEFINED, me, &writers);
  std::uint64_t total = 0;
  for (int k = 0; k < writersCount; ++k) total += 37 * static_cast<std::uint64_t>(k);
  if (writers != MPI_COMM_NULL) {
    Store w = writerStore(writers);
    io::CheckpointState st;
    st.reals["dt"] = {0.5};
    io::writeCheckpoint(writers, path, w.s, 2.0, 40, 2, "test", st);
    MPI_Comm_free(&writers);
  }
  MPI_Barrier(MPI_COMM_WORLD);

  const auto h = io::readCheckpointHeader(MPI_COMM_WORLD, path);
  EXPECT_EQ(h.particles, total);
  EXPECT_EQ(static_cast<int>(h.rankCounts.size()), writersCount);
  Store r;
  io::readCheckpointParticles(MPI_COMM_WORLD, h, r.s, false);
  // Even slices: floor/ceil of total / world.
  EXPECT_LE(r.s.localCount(), total / static_cast<std::uint64_t>(world) + 1);
  std::vector<std::uint64_t> ids(r.s[r.id].begin(),
                                 r.s[r.id].begin() + static_cast<long>(r.s.localCount()));
  int bad = 0;
  for (std::size_t i = 0; i < r.s.localCount(); ++i) bad += !intact(r, i);
  EXPECT_EQ(bad, 0);
  // Every id exactly once over all ranks.
  int n = static_cast<int>(ids.size());
  std::vector<int> counts(static_cast<std::size_t>(world)), displs(static_cast<std::size_t>(world));
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  for (int k = 1; k < world; ++k)
    displs[static_cast<std::size_t>(k)] =
        displs[static_cast<std::size_t>(k - 1)] + counts[static_cast<std::size_t>(k - 1)];
  std::vector<std::uint64_t> all(total);
  MPI_Allgatherv(ids.data(), n, MPI_UINT64_T, all.data(), counts.data(), displs.data(),
                 MPI_UINT64_T, MPI_COMM_WORLD);
  std::sort(all.begin(), all.end());
  for (std::uint64_t g = 0; g < total; ++g) ASSERT_EQ(all[g], 5 * g + 1);
  MPI_Barrier(MPI_COMM_WORLD);
  if (me == 0) fs::remove_all(dir);
}

TEST(CheckpointAcrossRanks, SameLayoutGivesEachRankItsOwnRows) {
  const fs::path dir = sharedScratch("same");
  const std::string path = (dir / "c.h5").string();
  Store w = writerStore(MPI_COMM_WORLD);
  io::writeCheckpoint(MPI_COMM_WORLD, path, w.s, 0.0, 0, 2, "test", {});
  Store r;
  io::readCheckpointParticles(MPI_COMM_WORLD, io::readCheckpointHeader(MPI_COMM_WORLD, path), r.s,
                              true);
  ASSERT_EQ(r.s.localCount(), w.s.localCount());
  for (std::size_t i = 0; i < r.s.localCount(); ++i) {
    EXPECT_EQ(r.s[r.id][i], w.s[w.id][i]);
    EXPECT_EQ(r.s[r.x][i], w.s[w.x][i]);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rankIn(MPI_COMM_WORLD) == 0) fs::remove_all(dir);
}

TEST(CheckpointAcrossRanks, CorruptionSeenByOneRankStopsAllRanks) {
  if (sizeIn(MPI_COMM_WORLD) < 2) GTEST_SKIP() << "needs a rank that holds no corrupt rows";
  const fs::path dir = sharedScratch("corrupt");
  const std::string path = (dir / "c.h5").string();
  Store w = writerStore(MPI_COMM_WORLD);
  io::writeCheckpoint(MPI_COMM_WORLD, path, w.s, 0.0, 0, 2, "test", {});
  const auto h = io::readCheckpointHeader(MPI_COMM_WORLD, path);
  if (rankIn(MPI_COMM_WORLD) == 0) {
    // Flip a byte in the last rank's rows of /particles/position: only that rank reads them,
    // yet every rank must refuse.
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const hid_t d = H5Dopen2(f, "particles/position", H5P_DEFAULT);
    const haddr_t offset = H5Dget_offset(d);
    H5Dclose(d);
    H5Fclose(f);
    std::fstream io(path, std::ios::in | std::ios::out | std::ios::binary);
    io.seekg(static_cast<long>(offset + h.particles * 16 - 3));
    char c = 0;
    io.read(&c, 1);
    c ^= 0x20;
    io.seekp(static_cast<long>(offset + h.particles * 16 - 3));
    io.write(&c, 1);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  Store r;
  try {
    io::readCheckpointParticles(MPI_COMM_WORLD, h, r.s, true);
    ADD_FAILURE() << "rank " << rankIn(MPI_COMM_WORLD) << " accepted a corrupt checkpoint";
  } catch (const io::CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("'position' fails its checksum"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(r.s.localCount(), 0u);
  MPI_Barrier(MPI_COMM_WORLD);
  if (rankIn(MPI_COMM_WORLD) == 0) fs::remove_all(dir);
}

TEST(CheckpointAcrossRanks, TheStateIsRankZerosEvenWhereRanksDisagree) {
  // A value only rank 0's copy of is stored (a wall clock differs on every rank): every rank
  // writes the checksum attribute, so each must write rank 0's checksum, or the file reads as
  // corrupt (as a 3-rank restart did) whichever rank's attribute landed.
  const fs::path dir = sharedScratch("state");
  const std::string path = (dir / "c.h5").string();
  Store w = writerStore(MPI_COMM_WORLD);
  const int me = rankIn(MPI_COMM_WORLD);
  io::CheckpointState st;
  st.reals["wall_seconds"] = {1.0 + me};
  st.texts["note"] = me == 0 ? "rank zero" : "rank nine"; // the same length: one dataset shape
  io::writeCheckpoint(MPI_COMM_WORLD, path, w.s, 0.0, 0, 2, "test", st);
  const auto h = io::readCheckpointHeader(MPI_COMM_WORLD, path);
  EXPECT_EQ(h.state.real("wall_seconds"), 1.0);
  EXPECT_EQ(h.state.texts.at("note"), "rank zero");
  MPI_Barrier(MPI_COMM_WORLD);
  if (me == 0) fs::remove_all(dir);
}
