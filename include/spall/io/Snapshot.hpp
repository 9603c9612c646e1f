#pragma once
// Snapshots: one HDF5 file per output time, written collectively by all ranks through MPI-IO so
// the file is the same whatever the rank count (docs/reference.md, "Snapshot HDF5"), and a serial
// reader for tests and tools. A file describes itself: its geometry, the names behind the material
// and body indices, every dataset's unit, and tensors stored row-major (as h5py and numpy index
// them).
#include "spall/core/ParticleStore.hpp"

#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace spall::io {

// `localCount` rows of info.scalarsPerParticle() scalars of type info.scalar, contiguous (the
// per-particle shape is the trailing dimensions of the dataset). A [n, n] double field's rows are
// the store's column-major Eigen matrices; the file holds them row-major, T(a, b) at n a + b, and
// says so in the dataset's `layout` attribute. `unit` becomes the dataset's `units` attribute.
// A derived field (stress from pressure, H from h) may instead supply `fill`, which writes the
// rows into a buffer the writer allocates for that field alone, so derived fields never need
// storage of their own beyond the one being written.
struct SnapshotField {
  FieldInfo info;
  const void* data = nullptr;
  std::function<void(void* rows)> fill = {};
  std::string unit = {};
};

struct SnapshotAttributes {
  double time = 0.0;
  std::int64_t step = 0;
  int dimension = 0;
  std::string version;
  std::string geometry;                   // "1d", "plane", "rz", "3d"
  std::string axes;                       // the position's components: "x y", "r z", ...
  std::vector<std::string> materialNames; // material index -> name
  std::vector<std::string> bodyNames;     // body index -> name (a jet's segments included)
};

// A group of rows in the file: /particles, or MPM's /grid (a node per row). A group with a
// `position` field is a point set: /xdmf/GROUP_vertices gets its vertex list 0..N-1 (what XDMF
// readers such as meshio need as the polyvertex topology) and, in 1D, /xdmf/GROUP_points its
// points as [N, 3] (x, 0, 0), the geometry XDMF readers take.
struct SnapshotGroup {
  std::string name;
  std::size_t localCount = 0;
  std::span<const SnapshotField> fields;
};

// Collective over comm: every rank passes the same groups and field lists (names, order, types,
// shapes) with its own rows; rank r's rows go after those of ranks < r. Writes PATH.tmp and
// renames it to PATH once complete, so a killed writer never leaves a complete-looking file.
// Throws RunError naming the path and the failing HDF5 call.
void writeSnapshot(MPI_Comm comm, const std::string& path, const SnapshotAttributes& attrs,
                   std::span<const SnapshotGroup> groups);
// The particles alone.
void writeSnapshot(MPI_Comm comm, const std::string& path, const SnapshotAttributes& attrs,
                   std::size_t localCount, std::span<const SnapshotField> fields);

struct SnapshotData {
  double time = 0.0;
  std::int64_t step = 0;
  int dimension = 0;
  std::string version;
  std::string geometry, axes; // empty in files written before they were recorded
  std::vector<std::string> materialNames, bodyNames;
  std::size_t count = 0;
  std::map<std::string, std::vector<double>> fields; // every /particles dataset, as doubles
  std::map<std::string, std::string> units;          // each dataset's `units` (where recorded)
  std::map<std::string, std::vector<int>> shapes;    // per-particle shape of each dataset
  std::vector<std::uint64_t> id;                     // /particles/id exactly (empty if absent)
};

// Serial (no MPI needed): /particles (other groups, MPM's /grid, are left unread). Integer
// datasets are converted to double, exact below 2^53. Tensors come row-major, T(a, b) at
// n^2 i + n a + b, also from files written column-major before the `layout` attribute.
SnapshotData readSnapshot(const std::string& path);

} // namespace spall::io
