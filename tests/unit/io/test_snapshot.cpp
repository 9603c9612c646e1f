// Snapshots round-trip exactly through HDF5 (every scalar type and shape the solvers write), the
// write is atomic, failures are RunErrors without HDF5 noise, and the XDMF files describe what
// was written. MPI comes from tests/unit/test_mpi_environment.cpp; this runs on one rank.
#include "spall/core/Error.hpp"
#include "spall/io/Snapshot.hpp"
#include "spall/io/Xdmf.hpp"
#include "unit/MpiForTests.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

using namespace spall;
namespace fs = std::filesystem;

namespace {

fs::path scratchDir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("spall_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Element nesting is balanced and every tag closes: enough to catch a broken writer without
// an XML library.
bool wellFormed(const std::string& xml) {
  std::vector<std::string> open;
  for (std::size_t i = xml.find('<'); i != std::string::npos; i = xml.find('<', i + 1)) {
    const std::size_t end = xml.find('>', i);
    if (end == std::string::npos) return false;
    const std::string tag = xml.substr(i + 1, end - i - 1);
    if (tag.empty() || tag[0] == '?' || tag[0] == '!') continue;
    const std::string name =
        tag.substr(tag[0] == '/', tag.find_first_of(" />", 1) - (tag[0] == '/'));
    if (tag[0] == '/') {
      if (open.empty() || open.back() != name) return false;
      open.pop_back();
    } else if (tag.back() != '/') {
      open.push_back(name);
    }
  }
  return open.empty();
}

// A 2D snapshot with one field of each kind the solvers produce.
struct Sample {
  static constexpr std::size_t n = 5;
  std::vector<std::uint64_t> id{0, 7, 3, (1ull << 60) + 1, ~0ull}; // above 2^53: kept exactly
  std::vector<double> position, pressure, tensor;
  std::vector<std::int32_t> material{0, 1, 2, -1, 2147483647};
  std::vector<FieldInfo> infos{{"id", ScalarType::U64, {}},
                               {"position", ScalarType::F64, {2}},
                               {"pressure", ScalarType::F64, {}},
                               {"stress", ScalarType::F64, {3, 3}},
                               {"material", ScalarType::I32, {}}};
  Sample() {
    for (std::size_t i = 0; i < n; ++i) {
      position.push_back(0.1 * i + 1e-300);
      position.push_back(-1.0 / 3.0 * i);
      pressure.push_back(1e9 * i + 0.5);
      for (int k = 0; k < 9; ++k) tensor.push_back(100.0 * i + k + 1.0 / 7.0);
    }
  }
  std::vector<io::SnapshotField> fields() const {
    return {{infos[0], id.data()},
            {infos[1], position.data(), {}, "m"},
            {infos[2], pressure.data()},
            {infos[3], tensor.data()},
            {infos[4], material.data()}};
  }
};

} // namespace

TEST(Snapshot, RoundTripsEveryFieldExactly) {
  fixtures::requireMpi();
  const fs::path dir = scratchDir("roundtrip");
  const std::string path = (dir / "snap_000007.h5").string();
  const Sample s;
  const auto fields = s.fields();
  io::SnapshotAttributes attrs{1.25e-6,
                               7,
                               2,
                               "0.1.0-test",
                               "rz",
                               "r z",
                               {"steel", "tungsten"},
                               {"target", "rod_segment1", "rod_segment2"}};
  io::writeSnapshot(MPI_COMM_WORLD, path, attrs, Sample::n, fields);
  EXPECT_TRUE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".tmp"));

  const io::SnapshotData d = io::readSnapshot(path);
  EXPECT_EQ(d.time, 1.25e-6);
  EXPECT_EQ(d.step, 7);
  EXPECT_EQ(d.dimension, 2);
  EXPECT_EQ(d.version, "0.1.0-test");
  EXPECT_EQ(d.geometry, "rz");
  EXPECT_EQ(d.axes, "r z");
  EXPECT_EQ(d.materialNames, attrs.materialNames);
  EXPECT_EQ(d.bodyNames, attrs.bodyNames);
  EXPECT_EQ(d.units.at("position"), "m");
  EXPECT_EQ(d.units.count("material"), 0u); // none given, none written
  EXPECT_EQ(d.count, Sample::n);
  EXPECT_EQ(d.id, s.id);
  EXPECT_EQ(d.shapes.at("id"), std::vector<int>{});
  EXPECT_EQ(d.shapes.at("position"), std::vector<int>{2});
  EXPECT_EQ(d.shapes.at("stress"), (std::vector<int>{3, 3}));
  EXPECT_EQ(d.fields.at("position"), s.position);
  EXPECT_EQ(d.fields.at("pressure"), s.pressure);
  // The buffer is column-major (Eigen's); the file and the reader are row-major.
  for (std::size_t i = 0; i < Sample::n; ++i)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        EXPECT_EQ(d.fields.at("stress")[9 * i + 3 * a + b], s.tensor[9 * i + 3 * b + a]);
  for (std::size_t i = 0; i < Sample::n; ++i)
    EXPECT_EQ(d.fields.at("material")[i], double(s.material[i]));
  EXPECT_EQ(d.fields.at("id")[2], 3.0); // small ids are exact as doubles too
  fs::remove_all(dir);
}

TEST(Snapshot, EmptySnapshotIsValid) {
  fixtures::requireMpi();
  const fs::path dir = scratchDir("empty");
  const std::string path = (dir / "snap_000000.h5").string();
  const FieldInfo pos{"position", ScalarType::F64, {3}};
  const std::vector<io::SnapshotField> fields{{pos, nullptr}};
  io::writeSnapshot(MPI_COMM_WORLD, path, {0.0, 0, 3, "v", "3d", "x y z", {}, {}}, 0, fields);
  const auto d = io::readSnapshot(path);
  EXPECT_EQ(d.count, 0u);
  EXPECT_EQ(d.shapes.at("position"), std::vector<int>{3});
  EXPECT_TRUE(d.fields.at("position").empty());
  fs::remove_all(dir);
}

TEST(Snapshot, FailureIsARunErrorWithoutHdf5Noise) {
  fixtures::requireMpi();
  const Sample s;
  const auto fields = s.fields();
  const std::string path = "/nonexistent_spall_dir/snap_000001.h5";
  ::testing::internal::CaptureStderr();
  try {
    io::writeSnapshot(MPI_COMM_WORLD, path, {0.0, 1, 2, "v", "plane", "x y", {}, {}}, Sample::n,
                      fields);
    ADD_FAILURE() << "no exception";
  } catch (const RunError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("H5Fcreate"), std::string::npos) << e.what();
  }
  EXPECT_THROW(io::readSnapshot(path), RunError);
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

TEST(Xdmf, SnapshotDescribesEveryDataset) {
  const fs::path dir = scratchDir("xdmf");
  const Sample s;
  io::writeSnapshotXdmf((dir / "snap_000007.xmf").string(), "snap_000007.h5", 2,
                        {"particles", Sample::n, s.infos});
  EXPECT_FALSE(fs::exists(dir / "snap_000007.xmf.tmp"));
  const std::string x = slurp(dir / "snap_000007.xmf");
  EXPECT_TRUE(wellFormed(x)) << x;
  EXPECT_NE(x.find(R"(<Xdmf Version="3.0")"), std::string::npos);
  EXPECT_EQ(x.find("<Time"), std::string::npos); // meshio refuses a Time in a grid
  EXPECT_EQ(x.find("Collection"), std::string::npos);
  EXPECT_NE(x.find(R"(TopologyType="Polyvertex" NumberOfElements="5" NodesPerElement="1")"),
            std::string::npos);
  EXPECT_NE(x.find(R"(<DataItem Dimensions="5 1" NumberType="Int" Precision="4" )"
                   R"(Format="HDF">snap_000007.h5:/xdmf/particles_vertices</DataItem>)"),
            std::string::npos)
      << x;
  EXPECT_NE(x.find(R"(GeometryType="XY")"), std::string::npos);
  EXPECT_NE(x.find(R"(<DataItem Dimensions="5 2" NumberType="Float" Precision="8" )"
                   R"(Format="HDF">snap_000007.h5:/particles/position</DataItem>)"),
            std::string::npos)
      << x;
  EXPECT_NE(x.find(R"(Dimensions="5 3 3" NumberType="Float" Precision="8" )"
                   R"(Format="HDF">snap_000007.h5:/particles/stress<)"),
            std::string::npos);
  EXPECT_NE(x.find(R"(Name="stress" AttributeType="Tensor")"), std::string::npos);
  EXPECT_NE(x.find(R"(Dimensions="5" NumberType="UInt" Precision="8" )"
                   R"(Format="HDF">snap_000007.h5:/particles/id<)"),
            std::string::npos);
  EXPECT_NE(x.find(R"(Dimensions="5" NumberType="Int" Precision="4" )"
                   R"(Format="HDF">snap_000007.h5:/particles/material<)"),
            std::string::npos);
  // The position is point data too: meshio's time series reads the geometry of the first grid
  // only, and particles move.
  EXPECT_NE(x.find(R"(Attribute Name="position" AttributeType="Vector")"), std::string::npos);
  fs::remove_all(dir);
}

TEST(Xdmf, LowDimensionalShapes) {
  const fs::path dir = scratchDir("xdmf_low");
  // 1D: the points padded to 3D in /xdmf; one-component vectors and tensors are scalars.
  const std::vector<FieldInfo> one{{"position", ScalarType::F64, {1}},
                                   {"velocity", ScalarType::F64, {1}},
                                   {"stress", ScalarType::F64, {1, 1}}};
  io::writeSnapshotXdmf((dir / "a.xmf").string(), "a.h5", 1, {"particles", 4, one});
  const std::string x1 = slurp(dir / "a.xmf");
  EXPECT_TRUE(wellFormed(x1)) << x1;
  EXPECT_NE(x1.find(R"(<Geometry GeometryType="XYZ">)"), std::string::npos);
  EXPECT_NE(x1.find(R"(Dimensions="4 3" NumberType="Float" Precision="8" )"
                    R"(Format="HDF">a.h5:/xdmf/particles_points<)"),
            std::string::npos)
      << x1;
  EXPECT_EQ(x1.find("Function"), std::string::npos);
  EXPECT_NE(x1.find(R"(Name="velocity" AttributeType="Scalar")"), std::string::npos);
  EXPECT_NE(x1.find(R"(Name="stress" AttributeType="Scalar")"), std::string::npos);
  // 2D tensors: a Matrix flattened to N x 4 (declared N 2 2, ParaView reads 2 components).
  const std::vector<FieldInfo> two{{"position", ScalarType::F64, {2}},
                                   {"stress", ScalarType::F64, {2, 2}}};
  io::writeSnapshotXdmf((dir / "b.xmf").string(), "b.h5", 2, {"grid", 4, two});
  const std::string x2 = slurp(dir / "b.xmf");
  EXPECT_NE(x2.find(R"(Name="stress" AttributeType="Matrix")"), std::string::npos);
  EXPECT_NE(x2.find(R"(Dimensions="4 4" NumberType="Float" Precision="8" Format="HDF">b.h5)"),
            std::string::npos);
  EXPECT_NE(x2.find("b.h5:/xdmf/grid_vertices"), std::string::npos);
  EXPECT_THROW(io::writeSnapshotXdmf((dir / "c.xmf").string(), "c.h5", 2,
                                     {"particles", 4, std::span(two).subspan(1)}),
               RunError);
  fs::remove_all(dir);
}

TEST(Xdmf, SeriesHoldsEverySnapshotsGridWithItsTime) {
  const fs::path dir = scratchDir("series");
  const std::vector<FieldInfo> fields{{"position", ScalarType::F64, {2}},
                                      {"density", ScalarType::F64, {}}};
  for (int k = 0; k < 3; ++k)
    io::writeSnapshotXdmf((dir / ("snap_00000" + std::to_string(k) + ".xmf")).string(),
                          "snap_00000" + std::to_string(k) + ".h5", 2,
                          {"particles", std::size_t(10 + k), fields});
  const std::string series = (dir / "series.xmf").string();
  io::writeSeriesXdmf(
      series, {{0.0, "snap_000000.xmf"}, {2e-7, "snap_000002.xmf"}, {1e-7, "snap_000001.xmf"}});
  EXPECT_FALSE(fs::exists(series + ".tmp"));
  const std::string x = slurp(series);
  EXPECT_TRUE(wellFormed(x)) << x;
  EXPECT_NE(x.find(R"(<Xdmf Version="3.0">)"), std::string::npos);
  EXPECT_EQ(x.find("xi:include"), std::string::npos); // meshio does not follow XInclude
  EXPECT_NE(x.find(R"(GridType="Collection" CollectionType="Temporal")"), std::string::npos);
  // In time order, each grid with its time and its own file's datasets.
  const auto at = [&](const std::string& t, const std::string& h5) {
    const std::size_t time = x.find("<Time Value=\"" + t + "\"/>");
    EXPECT_NE(time, std::string::npos) << t;
    EXPECT_NE(x.find(h5 + ":/particles/density", time), std::string::npos) << h5;
    return time;
  };
  const std::size_t t0 = at("0", "snap_000000.h5"), t1 = at("1e-07", "snap_000001.h5"),
                    t2 = at("2e-07", "snap_000002.h5");
  EXPECT_LT(t0, t1);
  EXPECT_LT(t1, t2);
  EXPECT_NE(x.find(R"(NumberOfElements="11")", t1), std::string::npos);
  EXPECT_THROW(io::writeSeriesXdmf(series, {{0.0, "missing.xmf"}}), RunError);
  fs::remove_all(dir);
}
