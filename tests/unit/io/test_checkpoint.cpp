// Checkpoint files on one rank: every checkpointed column round-trips bit for bit whatever its
// type and shape (including a field only this test registers: new fields need no checkpoint
// code), non-checkpointed columns stay out, the bookkeeping round-trips, and damaged or
// mismatched files are refused with a CheckpointError naming the file, never a crash.
#include "spall/io/Checkpoint.hpp"
#include "unit/MpiForTests.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <vector>

using namespace spall;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("spall_test_ckpt_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

struct Synthetic {
  ParticleStore s;
  Field<ParticleId> id;
  Field<Vec<3>> x;
  Field<Tensor<3>> sigma;
  Field<std::int32_t> flag;
  Field<double> scratch;
  explicit Synthetic(std::size_t n) {
    id = s.add<ParticleId>("id");
    x = s.add<Vec<3>>("position");
    sigma = s.add<Tensor<3>>("a_field_only_this_test_knows");
    flag = s.add<std::int32_t>("flag");
    scratch = s.add<double>("scratch", kOutput); // not part of the restartable state
    s.resizeLocal(n);
    for (std::size_t i = 0; i < n; ++i) {
      s[id][i] = 1000 + 7 * i;
      s[x][i] = Vec<3>(0.1 * static_cast<double>(i), -1.0 / (1.0 + static_cast<double>(i)), 3.0);
      s[sigma][i] = Tensor<3>::Constant(std::sqrt(static_cast<double>(i) + 0.5));
      s[flag][i] = -static_cast<std::int32_t>(i);
      s[scratch][i] = 42.0;
    }
  }
};

io::CheckpointState someState() {
  io::CheckpointState st;
  st.reals["dt"] = {1.0 / 3.0};
  st.reals["empty"] = {};
  st.integers["snapshot_index"] = {-5, 7};
  st.unsignedIntegers["begins"] = {0, ~std::uint64_t{0}};
  st.texts["deck"] = "[run]\ndimension = 3\n# unicode: \xc2\xb5m\n";
  return st;
}

} // namespace

TEST(Checkpoint, RoundTripsEveryCheckpointedColumnBitForBit) {
  fixtures::requireMpi();
  const fs::path dir = scratch("roundtrip");
  const std::string path = (dir / "ckpt_000012.h5").string();
  Synthetic a(257);
  const auto w = io::writeCheckpoint(MPI_COMM_WORLD, path, a.s, 0.125, 12, 3, "test", someState());
  EXPECT_GT(w.bytes, 257u * (8 + 24 + 72 + 4));
  EXPECT_FALSE(fs::exists(path + ".tmp"));

  const auto h = io::readCheckpointHeader(MPI_COMM_WORLD, path);
  EXPECT_EQ(h.dimension, 3);
  EXPECT_EQ(h.step, 12);
  EXPECT_EQ(h.time, 0.125);
  EXPECT_EQ(h.particles, 257u);
  ASSERT_EQ(h.rankCounts.size(), 1u);
  EXPECT_EQ(h.state.real("dt"), 1.0 / 3.0);
  EXPECT_TRUE(h.state.realArray("empty").empty());
  EXPECT_EQ(h.state.integerArray("snapshot_index"), (std::vector<std::int64_t>{-5, 7}));
  EXPECT_EQ(h.state.unsignedArray("begins")[1], ~std::uint64_t{0});
  EXPECT_EQ(h.state.text("deck"), someState().texts["deck"]);
  EXPECT_EQ(h.fields.size(), 4u); // scratch is not checkpointed
  EXPECT_THROW(h.state.real("missing"), io::CheckpointError);

  Synthetic b(3); // other contents, same fields
  b.s[b.scratch][0] = -1.0;
  io::readCheckpointParticles(MPI_COMM_WORLD, h, b.s, true);
  ASSERT_EQ(b.s.localCount(), 257u);
  for (std::size_t i = 0; i < 257; ++i) {
    EXPECT_EQ(b.s[b.id][i], a.s[a.id][i]);
    EXPECT_EQ(b.s[b.x][i], a.s[a.x][i]);
    EXPECT_EQ(b.s[b.sigma][i], a.s[a.sigma][i]);
    EXPECT_EQ(b.s[b.flag][i], a.s[a.flag][i]);
  }
  fs::remove_all(dir);
}

TEST(Checkpoint, ChecksumIsIndependentOfHowRowsAreSplit) {
  std::vector<double> v(1000);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::sin(static_cast<double>(i));
  const auto whole = io::rowChecksum(v.data(), 8, v.size(), 0);
  // Three readers with uneven slices sum to the same value (wrap-around addition).
  const auto parts = io::rowChecksum(v.data(), 8, 10, 0) +
                     io::rowChecksum(v.data() + 10, 8, 700, 10) +
                     io::rowChecksum(v.data() + 710, 8, 290, 710);
  EXPECT_EQ(whole, parts);
  // A single flipped bit, or two rows swapped, changes it.
  auto flipped = v;
  reinterpret_cast<unsigned char*>(flipped.data())[4003] ^= 0x04;
  EXPECT_NE(io::rowChecksum(flipped.data(), 8, v.size(), 0), whole);
  auto swapped = v;
  std::swap(swapped[3], swapped[4]);
  EXPECT_NE(io::rowChecksum(swapped.data(), 8, v.size(), 0), whole);
}

TEST(Checkpoint, DamagedFilesAreRefusedNamingTheFile) {
  fixtures::requireMpi();
  const fs::path dir = scratch("damaged");
  const std::string path = (dir / "good.h5").string();
  Synthetic a(500);
  io::writeCheckpoint(MPI_COMM_WORLD, path, a.s, 1.0, 3, 3, "test", someState());
  std::ifstream in(path, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});

  auto refused = [&](const std::string& file, const std::string& expect) {
    Synthetic b(1);
    bool headerRead = false;
    try {
      const auto h = io::readCheckpointHeader(MPI_COMM_WORLD, file);
      headerRead = true;
      io::readCheckpointParticles(MPI_COMM_WORLD, h, b.s, true);
      ADD_FAILURE() << file << " was accepted";
    } catch (const io::CheckpointError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(file), std::string::npos) << m;
      EXPECT_NE(m.find(expect), std::string::npos) << m;
    }
    if (headerRead) {
      EXPECT_EQ(b.s.localCount(), 0u); // nothing half-loaded
    }
  };

  const std::string truncated = (dir / "truncated.h5").string();
  std::ofstream(truncated, std::ios::binary)
      .write(bytes.data(), static_cast<long>(bytes.size() / 2));
  refused(truncated, "truncated");

  // Flip one byte inside the tensor field's data: HDF5 reads it happily; the checksum does not.
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, "particles/a_field_only_this_test_knows", H5P_DEFAULT);
  const haddr_t offset = H5Dget_offset(d);
  H5Dclose(d);
  H5Fclose(f);
  ASSERT_NE(offset, HADDR_UNDEF);
  const std::string flipped = (dir / "flipped.h5").string();
  auto copy = bytes;
  copy[offset + 250 * 72 + 5] ^= 0x01;
  std::ofstream(flipped, std::ios::binary).write(copy.data(), static_cast<long>(copy.size()));
  refused(flipped, "checksum");

  const std::string garbage = (dir / "garbage.h5").string();
  std::ofstream(garbage) << "not hdf5 at all\n";
  refused(garbage, "not a readable HDF5 file");
  refused((dir / "missing.h5").string(), "no such file");
  fs::remove_all(dir);
}

TEST(Checkpoint, FieldsMustMatchOneForOne) {
  fixtures::requireMpi();
  const fs::path dir = scratch("fields");
  const std::string path = (dir / "c.h5").string();
  Synthetic a(10);
  io::writeCheckpoint(MPI_COMM_WORLD, path, a.s, 0.0, 0, 3, "test", someState());
  const auto h = io::readCheckpointHeader(MPI_COMM_WORLD, path);

  Synthetic more(1);
  more.s.add<double>("plastic_strain");
  try {
    io::readCheckpointParticles(MPI_COMM_WORLD, h, more.s, true);
    ADD_FAILURE() << "accepted a checkpoint without plastic_strain";
  } catch (const io::CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("lacks particle field 'plastic_strain'"),
              std::string::npos)
        << e.what();
  }

  ParticleStore fewer;
  fewer.add<ParticleId>("id");
  EXPECT_THROW(io::readCheckpointParticles(MPI_COMM_WORLD, h, fewer, true), io::CheckpointError);

  ParticleStore otherShape; // same names, a 2D position
  otherShape.add<ParticleId>("id");
  otherShape.add<Vec<2>>("position");
  otherShape.add<Tensor<3>>("a_field_only_this_test_knows");
  otherShape.add<std::int32_t>("flag");
  try {
    io::readCheckpointParticles(MPI_COMM_WORLD, h, otherShape, true);
    ADD_FAILURE() << "accepted a 3-vector as a 2-vector";
  } catch (const io::CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("float64[3], this run needs float64[2]"),
              std::string::npos)
        << e.what();
  }
  fs::remove_all(dir);
}
