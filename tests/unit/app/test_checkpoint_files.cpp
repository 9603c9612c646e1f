// The restart chain's files: `latest` is replaced atomically, pruning keeps the newest N and
// never the one `latest` names, --restart latest tries the right files in the right order,
// and a restart trims the logs and snapshots a crashed run wrote after its checkpoint.
#include "spall/app/CheckpointFiles.hpp"
#include "spall/io/Deck.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

using namespace spall;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("spall_test_chain_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "checkpoints");
  return dir;
}

void touch(const fs::path& p) {
  std::ofstream(p) << "x";
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

} // namespace

TEST(CheckpointFiles, NamesSortByStep) {
  EXPECT_EQ(app::checkpointFileName(7), "ckpt_000007.h5");
  EXPECT_EQ(app::checkpointFileName(12345678), "ckpt_12345678.h5");
}

TEST(CheckpointFiles, PruneKeepsNewestAndNeverLatest) {
  const fs::path dir = scratch("prune");
  const fs::path ck = dir / "checkpoints";
  for (int s : {10, 20, 30, 40, 1000}) touch(ck / app::checkpointFileName(s));
  touch(ck / "ckpt_000050.h5.tmp"); // a killed writer's leftover
  app::publishLatest(ck, app::checkpointFileName(20));
  EXPECT_EQ(slurp(ck / "latest"), "ckpt_000020.h5\n");
  EXPECT_FALSE(fs::exists(ck / "latest.tmp"));
  app::pruneCheckpoints(ck, 2);
  EXPECT_TRUE(fs::exists(ck / "ckpt_001000.h5")); // newest two by step, not by name length
  EXPECT_TRUE(fs::exists(ck / "ckpt_000040.h5"));
  EXPECT_TRUE(fs::exists(ck / "ckpt_000020.h5")); // latest names it
  EXPECT_FALSE(fs::exists(ck / "ckpt_000030.h5"));
  EXPECT_FALSE(fs::exists(ck / "ckpt_000010.h5"));
  // A .tmp may be another writer's file in progress: only a restart clears them.
  EXPECT_TRUE(fs::exists(ck / "ckpt_000050.h5.tmp"));
  app::removeStaleTemporaries(ck);
  EXPECT_FALSE(fs::exists(ck / "ckpt_000050.h5.tmp"));
  EXPECT_TRUE(fs::exists(ck / "ckpt_000020.h5"));
  fs::remove_all(dir);
}

TEST(CheckpointFiles, RestartCandidatesFallBackNewestFirst) {
  const fs::path dir = scratch("candidates");
  const fs::path ck = dir / "checkpoints";
  auto c = app::restartCandidates(dir, "latest");
  EXPECT_TRUE(c.files.empty());
  EXPECT_NE(c.problem.find("latest does not exist"), std::string::npos) << c.problem;

  for (int s : {5, 15, 25}) touch(ck / app::checkpointFileName(s));
  touch(ck / "ckpt_000035.h5.tmp");
  app::publishLatest(ck, app::checkpointFileName(15));
  c = app::restartCandidates(dir, "latest");
  ASSERT_EQ(c.files.size(), 3u);
  EXPECT_TRUE(c.fallback);
  EXPECT_TRUE(c.problem.empty());
  EXPECT_EQ(c.files[0].filename(), "ckpt_000015.h5"); // what latest names comes first
  EXPECT_EQ(c.files[1].filename(), "ckpt_000025.h5");
  EXPECT_EQ(c.files[2].filename(), "ckpt_000005.h5");

  app::publishLatest(ck, "ckpt_000099.h5");
  c = app::restartCandidates(dir, "latest");
  EXPECT_NE(c.problem.find("names ckpt_000099.h5, which does not exist"), std::string::npos);
  ASSERT_EQ(c.files.size(), 3u);
  EXPECT_EQ(c.files[0].filename(), "ckpt_000025.h5");

  c = app::restartCandidates(dir, "/some/where/ckpt_000001.h5"); // a path: that file only
  ASSERT_EQ(c.files.size(), 1u);
  EXPECT_FALSE(c.fallback);
  fs::remove_all(dir);
}

TEST(CheckpointFiles, RestartTrimsWhatACrashedRunWroteAfterItsCheckpoint) {
  const fs::path dir = scratch("trim");
  std::ofstream(dir / "history.csv") << "step,time,dt\n0,0,0.1\n1,0.1,0.1\n2,0.2,0.1\n3,0.3,0.1\n";
  app::truncateHistory(dir / "history.csv", 2);
  EXPECT_EQ(slurp(dir / "history.csv"), "step,time,dt\n0,0,0.1\n1,0.1,0.1\n2,0.2,0.1\n");

  // Times exactly as written (17 significant digits) compare exactly.
  const double t = 0.1 + 0.2;
  std::ofstream(dir / "probes.csv") << "time,probe,field,value\n0,a,p,1\n"
                                    << "0.30000000000000004,a,p,2\n0.30000000000000009,a,p,3\n";
  app::truncateProbes(dir / "probes.csv", t);
  EXPECT_EQ(slurp(dir / "probes.csv"),
            "time,probe,field,value\n0,a,p,1\n0.30000000000000004,a,p,2\n");

  fs::create_directories(dir / "snapshots");
  for (const char* f : {"snap_000001.h5", "snap_000001.xmf", "snap_000002.h5", "snap_000002.xmf",
                        "snap_000003.h5.tmp", "series.xmf"})
    touch(dir / "snapshots" / f);
  app::removeSnapshotsFrom(dir / "snapshots", 2);
  EXPECT_TRUE(fs::exists(dir / "snapshots" / "snap_000001.h5"));
  EXPECT_TRUE(fs::exists(dir / "snapshots" / "snap_000001.xmf"));
  EXPECT_TRUE(fs::exists(dir / "snapshots" / "series.xmf"));
  EXPECT_FALSE(fs::exists(dir / "snapshots" / "snap_000002.h5"));
  EXPECT_FALSE(fs::exists(dir / "snapshots" / "snap_000002.xmf"));
  EXPECT_FALSE(fs::exists(dir / "snapshots" / "snap_000003.h5.tmp"));

  app::truncateHistory(dir / "absent.csv", 1); // nothing to trim, nothing created
  EXPECT_FALSE(fs::exists(dir / "absent.csv"));
  fs::remove_all(dir);
}

TEST(DeckPhysicsDifferences, OnlyPhysicsKeysCount) {
  const std::string before = R"(
[run]
dimension = 2
end_time = 1.0
[solver]
cfl = 0.3
[[body]]
name = "striker"
velocity = [1.0, 0.0]
[[body]]
name = "target"
velocity = [0.0, 0.0]
[output]
every = 0.1
[checkpoint]
every_steps = 10
)";
  // A longer run, other output and checkpoint settings, bodies listed in another order.
  const std::string extended = R"(
[run]
dimension = 2
end_time = 2.0
max_steps = 100
[solver]
cfl = 0.3
[[body]]
name = "target"
velocity = [0.0, 0.0]
[[body]]
name = "striker"
velocity = [1.0, 0.0]
[output]
every = 0.5
directory = "elsewhere"
[decomposition]
curve = "morton"
)";
  EXPECT_TRUE(deckPhysicsDifferences(before, extended).empty());

  std::string faster = before;
  faster.replace(faster.find("velocity = [1.0, 0.0]"), 21, "velocity = [2.0, 0.0]");
  faster.replace(faster.find("cfl = 0.3"), 9, "");
  const auto d = deckPhysicsDifferences(before, faster);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_NE(d[0].find("body.striker.velocity"), std::string::npos) << d[0];
  EXPECT_NE(d[1].find("solver.cfl: 0.3 in the checkpoint, absent now"), std::string::npos) << d[1];
}
