#include "spall/io/Checkpoint.hpp"

#include "Hdf5Util.hpp"
#include "spall/parallel/Mpi.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

namespace spall::io {
namespace {

using hdf5::check;
using hdf5::fail;
using hdf5::Handle;

constexpr const char* kFormat = "spall-checkpoint";

// ---- checksum --------------------------------------------------------------------------------

std::uint64_t mix(std::uint64_t z) { // splitmix64 finaliser
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// ---- writing ---------------------------------------------------------------------------------

void writeChecksum(hid_t dset, std::uint64_t sum, const std::string& path) {
  hdf5::writeScalarAttribute(dset, "checksum", H5T_STD_U64LE, H5T_NATIVE_UINT64, &sum, path);
}

// A 1-D state array written by rank 0 alone (the others join with empty selections).
// The state is rank 0's: its values and its checksums (each rank writes the checksum attribute,
// so a rank whose copy differed, a wall clock, would otherwise leave a checksum that does not
// match the data).
std::uint64_t rootChecksum(MPI_Comm comm, std::uint64_t sum) {
  MPI_Bcast(&sum, 1, MPI_UINT64_T, 0, comm);
  return sum;
}

void writeStateArray(MPI_Comm comm, hid_t group, hid_t dxpl, bool root, const std::string& name,
                     hid_t fileT, hid_t memT, const void* data, std::size_t count,
                     std::size_t scalarBytes, const std::string& path) {
  const hsize_t dims[1] = {count};
  Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose, path, "H5Screate_simple");
  Handle dset(H5Dcreate2(group, name.c_str(), fileT, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
              H5Dclose, path, "H5Dcreate2(state/" + name + ")");
  writeChecksum(dset, rootChecksum(comm, rowChecksum(data, scalarBytes, count, 0)), path);
  if (count == 0) return;
  Handle mem(H5Screate_simple(1, dims, nullptr), H5Sclose, path, "H5Screate_simple");
  if (!root) {
    check(H5Sselect_none(space), path, "H5Sselect_none");
    check(H5Sselect_none(mem), path, "H5Sselect_none");
  }
  check(H5Dwrite(dset, memT, mem, space, dxpl, data), path, "H5Dwrite(state)");
}

void writeStateText(MPI_Comm comm, hid_t group, hid_t dxpl, bool root, const std::string& name,
                    const std::string& text, const std::string& path) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose, path, "H5Tcopy");
  check(H5Tset_size(type, text.size() + 1), path, "H5Tset_size");
  check(H5Tset_strpad(type, H5T_STR_NULLTERM), path, "H5Tset_strpad");
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, path, "H5Screate");
  Handle dset(H5Dcreate2(group, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
              H5Dclose, path, "H5Dcreate2(state/" + name + ")");
  writeChecksum(dset, rootChecksum(comm, rowChecksum(text.data(), text.size(), 1, 0)), path);
  Handle mem(H5Screate(H5S_SCALAR), H5Sclose, path, "H5Screate");
  if (!root) {
    check(H5Sselect_none(space), path, "H5Sselect_none");
    check(H5Sselect_none(mem), path, "H5Sselect_none");
  }
  check(H5Dwrite(dset, type, mem, space, dxpl, text.c_str()), path, "H5Dwrite(state)");
}

// Testing hook (tests/mpi/test_restart.py): SPALL_TEST_KILL_IN_CHECKPOINT=N makes rank 0 kill
// itself with SIGKILL halfway through the data of the N-th checkpoint this process writes, to
// prove a killed writer never leaves a `latest` that points at a broken file.
void maybeDieHere(int rank) {
  static int written = 0;
  static const char* env = std::getenv("SPALL_TEST_KILL_IN_CHECKPOINT");
  if (!env || rank != 0) return;
  if (++written == std::atoi(env)) std::raise(SIGKILL);
}

void syncPath(const std::string& path, bool directory) {
  const int fd = ::open(path.c_str(), directory ? O_RDONLY | O_DIRECTORY : O_RDONLY);
  if (fd < 0) throw RunError(path + ": cannot open to sync: " + std::strerror(errno));
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  // Some file systems cannot sync a directory (EINVAL); the rename itself is still atomic.
  if (rc != 0 && !(directory && err == EINVAL))
    throw RunError(path + ": fsync failed: " + std::strerror(err));
}

} // namespace

std::uint64_t rowChecksum(const void* rows, std::size_t bytesPerRow, std::size_t count,
                          std::uint64_t firstRow) {
  const auto* p = static_cast<const unsigned char*>(rows);
  std::uint64_t sum = 0;
  for (std::size_t i = 0; i < count; ++i, p += bytesPerRow) {
    std::uint64_t h = mix(firstRow + i + 0x9e3779b97f4a7c15ull);
    std::size_t k = 0;
    for (; k + 8 <= bytesPerRow; k += 8) {
      std::uint64_t w;
      std::memcpy(&w, p + k, 8);
      h = (h ^ w) * 0x100000001b3ull;
      h ^= h >> 29;
    }
    for (; k < bytesPerRow; ++k) h = (h ^ p[k]) * 0x100000001b3ull;
    sum += mix(h);
  }
  return sum;
}

CheckpointWrite writeCheckpoint(MPI_Comm comm, const std::string& path, const ParticleStore& s,
                                double time, std::int64_t step, int dimension,
                                const std::string& version, const CheckpointState& state) {
  hdf5::Quiet quiet;
  const auto t0 = std::chrono::steady_clock::now();
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const bool root = rank == 0;
  const std::string tmp = path + ".tmp";

  std::uint64_t local = s.localCount(), offset = 0, global = 0;
  MPI_Exscan(&local, &offset, 1, MPI_UINT64_T, MPI_SUM, comm);
  if (root) offset = 0; // MPI_Exscan leaves rank 0's result undefined
  MPI_Allreduce(&local, &global, 1, MPI_UINT64_T, MPI_SUM, comm);
  std::vector<std::uint64_t> rankCounts(static_cast<std::size_t>(size));
  MPI_Allgather(&local, 1, MPI_UINT64_T, rankCounts.data(), 1, MPI_UINT64_T, comm);

  // Checksums first: attributes are written collectively with the same value on every rank.
  std::vector<const ColumnBase*> columns;
  for (const auto& c : s.columns())
    if (c->info().flags & kCheckpoint) columns.push_back(c.get());
  std::vector<std::uint64_t> sums(columns.size());
  for (std::size_t k = 0; k < columns.size(); ++k)
    sums[k] = rowChecksum(columns[k]->raw(), columns[k]->bytesPerParticle(), local, offset);
  MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_UINT64_T, MPI_SUM,
                comm);

  {
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, tmp, "H5Pcreate");
    check(H5Pset_fapl_mpio(fapl, comm, MPI_INFO_NULL), tmp, "H5Pset_fapl_mpio");
    Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl), H5Fclose, tmp,
                "H5Fcreate");
    const int formatVersion = kCheckpointFormatVersion;
    hdf5::writeStringAttribute(file, "format", kFormat, tmp);
    hdf5::writeScalarAttribute(file, "format_version", H5T_STD_I32LE, H5T_NATIVE_INT,
                               &formatVersion, tmp);
    hdf5::writeStringAttribute(file, "spall_version", version, tmp);
    hdf5::writeScalarAttribute(file, "dimension", H5T_STD_I32LE, H5T_NATIVE_INT, &dimension, tmp);
    hdf5::writeScalarAttribute(file, "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &time, tmp);
    hdf5::writeScalarAttribute(file, "step", H5T_STD_I64LE, H5T_NATIVE_INT64, &step, tmp);
    hdf5::writeScalarAttribute(file, "particles", H5T_STD_U64LE, H5T_NATIVE_UINT64, &global, tmp);
    hdf5::writeScalarAttribute(file, "ranks", H5T_STD_I32LE, H5T_NATIVE_INT, &size, tmp);

    Handle dxpl(H5Pcreate(H5P_DATASET_XFER), H5Pclose, tmp, "H5Pcreate");
    check(H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE), tmp, "H5Pset_dxpl_mpio");
    writeStateArray(comm, file, dxpl, root, "rank_counts", H5T_STD_U64LE, H5T_NATIVE_UINT64,
                    rankCounts.data(), rankCounts.size(), 8, tmp);
    {
      Handle g(H5Gcreate2(file, "state", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, tmp,
               "H5Gcreate2(state)");
      for (const auto& [name, v] : state.reals)
        writeStateArray(comm, g, dxpl, root, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data(),
                        v.size(), 8, tmp);
      for (const auto& [name, v] : state.integers)
        writeStateArray(comm, g, dxpl, root, name, H5T_STD_I64LE, H5T_NATIVE_INT64, v.data(),
                        v.size(), 8, tmp);
      for (const auto& [name, v] : state.unsignedIntegers)
        writeStateArray(comm, g, dxpl, root, name, H5T_STD_U64LE, H5T_NATIVE_UINT64, v.data(),
                        v.size(), 8, tmp);
      for (const auto& [name, t] : state.texts) writeStateText(comm, g, dxpl, root, name, t, tmp);
    }
    Handle g(H5Gcreate2(file, "particles", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, tmp,
             "H5Gcreate2(particles)");
    for (std::size_t k = 0; k < columns.size(); ++k) {
      if (k == columns.size() / 2) maybeDieHere(rank);
      hdf5::writeRows(g, dxpl, columns[k]->info(), global, offset, local, columns[k]->raw(), tmp,
                      [&](hid_t dset) { writeChecksum(dset, sums[k], tmp); });
    }
    g.close(tmp, "H5Gclose");
    // With MPI-IO, a flush is an MPI_File_sync on every rank: the data is on disk, not in caches.
    check(H5Fflush(file, H5F_SCOPE_GLOBAL), tmp, "H5Fflush");
    file.close(tmp, "H5Fclose");
  }

  // Publish: rank 0 syncs the file, renames it and syncs the directory; the agreement keeps
  // the other ranks from going on before the checkpoint exists under its name.
  parallel::onRoot<RunError>(comm, [&] {
    syncPath(tmp, false);
    if (std::rename(tmp.c_str(), path.c_str()) != 0)
      throw RunError(path + ": cannot rename " + tmp + " to it: " + std::strerror(errno));
    const auto parent = std::filesystem::path(path).parent_path();
    syncPath(parent.empty() ? "." : parent.string(), true);
  });

  CheckpointWrite out;
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  MPI_Allreduce(MPI_IN_PLACE, &seconds, 1, MPI_DOUBLE, MPI_MAX, comm);
  out.seconds = seconds;
  std::uint64_t bytes = 0;
  if (root) {
    std::error_code ec;
    bytes = std::filesystem::file_size(path, ec);
  }
  MPI_Bcast(&bytes, 1, MPI_UINT64_T, 0, comm);
  out.bytes = bytes;
  return out;
}

// ---- reading ---------------------------------------------------------------------------------

namespace {

hid_t openForReading(const std::string& path) {
  if (!std::filesystem::exists(path)) throw CheckpointError(path + ": no such file");
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, path, "H5Pcreate");
  // Every rank opens the file on its own (serial driver, read only): no collective call can be
  // left waiting when one rank finds the file broken. Locks are not needed and not supported
  // on every parallel file system.
  check(H5Pset_file_locking(fapl, false, true), path, "H5Pset_file_locking");
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl);
  if (f < 0) {
    const std::string d = hdf5::detail();
    throw CheckpointError(path + ": not a readable HDF5 file (truncated or corrupt?)" +
                          (d.empty() ? "" : ": " + d));
  }
  return f;
}

std::uint64_t readChecksum(hid_t dset, const std::string& path, const std::string& what) {
  if (H5Aexists(dset, "checksum") <= 0)
    throw CheckpointError(path + ": " + what + " has no checksum");
  return hdf5::readScalarAttribute<std::uint64_t>(dset, "checksum", H5T_NATIVE_UINT64, path);
}

template <class T>
std::vector<T> readArray(hid_t dset, hid_t memT, const std::string& path, const std::string& what) {
  Handle space(H5Dget_space(dset), H5Sclose, path, "H5Dget_space");
  if (H5Sget_simple_extent_ndims(space) != 1)
    throw CheckpointError(path + ": " + what + " is not a 1-D array");
  hsize_t n = 0;
  H5Sget_simple_extent_dims(space, &n, nullptr);
  std::vector<T> v(n);
  if (n > 0) check(H5Dread(dset, memT, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), path, "H5Dread");
  if (rowChecksum(v.data(), sizeof(T), v.size(), 0) != readChecksum(dset, path, what))
    throw CheckpointError(path + ": " + what + " fails its checksum (corrupt file)");
  return v;
}

ScalarType scalarOf(hid_t type, const std::string& path, const std::string& name) {
  const H5T_class_t cls = H5Tget_class(type);
  const std::size_t size = H5Tget_size(type);
  if (cls == H5T_FLOAT && size == 8) return ScalarType::F64;
  if (cls == H5T_INTEGER && size == 8 && H5Tget_sign(type) == H5T_SGN_NONE) return ScalarType::U64;
  if (cls == H5T_INTEGER && size == 4 && H5Tget_sign(type) == H5T_SGN_2) return ScalarType::I32;
  if (cls == H5T_INTEGER && size == 8 && H5Tget_sign(type) == H5T_SGN_2) return ScalarType::I64;
  throw CheckpointError(path + ": particle field '" + name + "' has an unsupported type");
}

const char* scalarName(ScalarType t) {
  switch (t) {
  case ScalarType::F64:
    return "float64";
  case ScalarType::U64:
    return "uint64";
  case ScalarType::I32:
    return "int32";
  case ScalarType::I64:
    return "int64";
  }
  return "?";
}

std::string shapeText(const std::vector<int>& shape) {
  std::string s = "[";
  for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? "," : "") + std::to_string(shape[i]);
  return s + "]";
}

CheckpointHeader readHeaderLocal(const std::string& path) {
  hdf5::Quiet quiet;
  CheckpointHeader h;
  h.path = path;
  h.state.path = path;
  try {
    Handle file(openForReading(path), H5Fclose, path, "H5Fopen");
    if (H5Aexists(file, "format") <= 0 ||
        hdf5::readStringAttribute(file, "format", path) != kFormat)
      throw CheckpointError(
          path + ": not a spall checkpoint (no 'format = " + std::string(kFormat) + "' attribute)");
    h.formatVersion = hdf5::readScalarAttribute<int>(file, "format_version", H5T_NATIVE_INT, path);
    h.version = hdf5::readStringAttribute(file, "spall_version", path);
    if (h.formatVersion != kCheckpointFormatVersion)
      throw CheckpointError(path + ": checkpoint format version " +
                            std::to_string(h.formatVersion) + " (written by spall " + h.version +
                            "); this spall reads version " +
                            std::to_string(kCheckpointFormatVersion));
    h.dimension = hdf5::readScalarAttribute<int>(file, "dimension", H5T_NATIVE_INT, path);
    h.time = hdf5::readScalarAttribute<double>(file, "time", H5T_NATIVE_DOUBLE, path);
    h.step = hdf5::readScalarAttribute<std::int64_t>(file, "step", H5T_NATIVE_INT64, path);
    h.particles =
        hdf5::readScalarAttribute<std::uint64_t>(file, "particles", H5T_NATIVE_UINT64, path);
    {
      Handle d(H5Dopen2(file, "rank_counts", H5P_DEFAULT), H5Dclose, path, "H5Dopen2(rank_counts)");
      h.rankCounts = readArray<std::uint64_t>(d, H5T_NATIVE_UINT64, path, "rank_counts");
    }
    std::uint64_t sum = 0;
    for (auto c : h.rankCounts) sum += c;
    if (h.rankCounts.empty() || sum != h.particles)
      throw CheckpointError(path + ": rank_counts do not add up to the particle count");

    Handle state(H5Gopen2(file, "state", H5P_DEFAULT), H5Gclose, path, "H5Gopen2(state)");
    H5G_info_t info;
    check(H5Gget_info(state, &info), path, "H5Gget_info");
    for (hsize_t i = 0; i < info.nlinks; ++i) {
      const std::string name = hdf5::linkName(state, i, path);
      const std::string what = "state/" + name;
      Handle d(H5Dopen2(state, name.c_str(), H5P_DEFAULT), H5Dclose, path,
               "H5Dopen2(" + what + ")");
      Handle type(H5Dget_type(d), H5Tclose, path, "H5Dget_type");
      const H5T_class_t cls = H5Tget_class(type);
      if (cls == H5T_STRING) {
        std::string buf(H5Tget_size(type), '\0');
        check(H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()), path, "H5Dread");
        buf.resize(buf.find('\0') == std::string::npos ? buf.size() : buf.find('\0'));
        if (rowChecksum(buf.data(), buf.size(), 1, 0) != readChecksum(d, path, what))
          throw CheckpointError(path + ": " + what + " fails its checksum (corrupt file)");
        h.state.texts[name] = std::move(buf);
      } else if (cls == H5T_FLOAT) {
        h.state.reals[name] = readArray<double>(d, H5T_NATIVE_DOUBLE, path, what);
      } else if (cls == H5T_INTEGER && H5Tget_sign(type) == H5T_SGN_NONE) {
        h.state.unsignedIntegers[name] = readArray<std::uint64_t>(d, H5T_NATIVE_UINT64, path, what);
      } else if (cls == H5T_INTEGER) {
        h.state.integers[name] = readArray<std::int64_t>(d, H5T_NATIVE_INT64, path, what);
      } else {
        throw CheckpointError(path + ": " + what + " has an unsupported type");
      }
    }

    Handle particles(H5Gopen2(file, "particles", H5P_DEFAULT), H5Gclose, path,
                     "H5Gopen2(particles)");
    check(H5Gget_info(particles, &info), path, "H5Gget_info");
    for (hsize_t i = 0; i < info.nlinks; ++i) {
      FieldInfo f;
      f.name = hdf5::linkName(particles, i, path);
      Handle d(H5Dopen2(particles, f.name.c_str(), H5P_DEFAULT), H5Dclose, path,
               "H5Dopen2(" + f.name + ")");
      Handle type(H5Dget_type(d), H5Tclose, path, "H5Dget_type");
      f.scalar = scalarOf(type, path, f.name);
      Handle space(H5Dget_space(d), H5Sclose, path, "H5Dget_space");
      const int rank = H5Sget_simple_extent_ndims(space);
      if (rank < 1 || rank > 3)
        throw CheckpointError(path + ": particle field '" + f.name + "' has a bad shape");
      hsize_t dims[3] = {0, 0, 0};
      H5Sget_simple_extent_dims(space, dims, nullptr);
      if (dims[0] != h.particles)
        throw CheckpointError(path + ": particle field '" + f.name + "' has " +
                              std::to_string(dims[0]) + " rows, expected " +
                              std::to_string(h.particles));
      for (int k = 1; k < rank; ++k) f.shape.push_back(static_cast<int>(dims[k]));
      h.fields.push_back(std::move(f));
    }
  } catch (const CheckpointError&) {
    throw;
  } catch (const std::exception& e) {
    throw CheckpointError(std::string(e.what()) + " (truncated or corrupt checkpoint?)");
  }
  return h;
}

} // namespace

CheckpointHeader readCheckpointHeader(MPI_Comm comm, const std::string& path) {
  CheckpointHeader h;
  parallel::agreeOnFailure<CheckpointError>(comm, [&] { h = readHeaderLocal(path); });
  return h;
}

std::uint64_t readCheckpointParticles(MPI_Comm comm, const CheckpointHeader& header,
                                      ParticleStore& s, bool sameLayout) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const std::string& path = header.path;
  std::vector<ColumnBase*> columns;
  for (const auto& c : s.columns())
    if (c->info().flags & kCheckpoint) columns.push_back(c.get());

  // The same fields, one for one: a checkpoint from a build with other fields cannot continue.
  for (const ColumnBase* c : columns) {
    const auto& need = c->info();
    auto it = std::find_if(header.fields.begin(), header.fields.end(),
                           [&](const FieldInfo& f) { return f.name == need.name; });
    if (it == header.fields.end())
      throw CheckpointError(path + ": lacks particle field '" + need.name +
                            "' that this run needs (written by spall " + header.version +
                            " with other models or an older format?)");
    if (it->scalar != need.scalar || it->shape != need.shape)
      throw CheckpointError(path + ": particle field '" + need.name + "' is " +
                            scalarName(it->scalar) + shapeText(it->shape) + ", this run needs " +
                            scalarName(need.scalar) + shapeText(need.shape));
  }
  for (const auto& f : header.fields)
    if (std::none_of(columns.begin(), columns.end(),
                     [&](const ColumnBase* c) { return c->info().name == f.name; }))
      throw CheckpointError(path + ": holds particle field '" + f.name +
                            "' that this run does not have (a deck with other models?)");

  std::uint64_t first = 0, count = 0;
  if (sameLayout) {
    for (int r = 0; r < rank; ++r) first += header.rankCounts[static_cast<std::size_t>(r)];
    count = header.rankCounts[static_cast<std::size_t>(rank)];
  } else {
    const std::uint64_t n = header.particles, R = static_cast<std::uint64_t>(size);
    first = n * static_cast<std::uint64_t>(rank) / R;
    count = n * static_cast<std::uint64_t>(rank + 1) / R - first;
  }
  s.resizeLocal(0);
  s.appendLocal(count);

  std::vector<std::uint64_t> sums(columns.size(), 0), expected(columns.size(), 0);
  std::uint64_t bytes = 0;
  try {
    parallel::agreeOnFailure<CheckpointError>(comm, [&] {
      hdf5::Quiet quiet;
      try {
        Handle file(openForReading(path), H5Fclose, path, "H5Fopen");
        Handle g(H5Gopen2(file, "particles", H5P_DEFAULT), H5Gclose, path, "H5Gopen2(particles)");
        for (std::size_t k = 0; k < columns.size(); ++k) {
          ColumnBase* c = columns[k];
          const FieldInfo& info = c->info();
          Handle d(H5Dopen2(g, info.name.c_str(), H5P_DEFAULT), H5Dclose, path,
                   "H5Dopen2(" + info.name + ")");
          expected[k] = readChecksum(d, path, "particle field '" + info.name + "'");
          if (count == 0) continue;
          const int dims = 1 + static_cast<int>(info.shape.size());
          std::vector<hsize_t> mine{count}, start{first};
          for (int e : info.shape) {
            mine.push_back(static_cast<hsize_t>(e));
            start.push_back(0);
          }
          Handle fileSpace(H5Dget_space(d), H5Sclose, path, "H5Dget_space");
          check(H5Sselect_hyperslab(fileSpace, H5S_SELECT_SET, start.data(), nullptr, mine.data(),
                                    nullptr),
                path, "H5Sselect_hyperslab");
          Handle memSpace(H5Screate_simple(dims, mine.data(), nullptr), H5Sclose, path,
                          "H5Screate_simple");
          check(
              H5Dread(d, hdf5::memoryType(info.scalar), memSpace, fileSpace, H5P_DEFAULT, c->raw()),
              path, ("H5Dread(" + info.name + ")").c_str());
          sums[k] = rowChecksum(c->raw(), c->bytesPerParticle(), count, first);
          bytes += count * c->bytesPerParticle();
        }
      } catch (const CheckpointError&) {
        throw;
      } catch (const std::exception& e) {
        throw CheckpointError(std::string(e.what()) + " (truncated or corrupt checkpoint?)");
      }
    });
    MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_UINT64_T, MPI_SUM,
                  comm);
    for (std::size_t k = 0; k < columns.size(); ++k)
      if (sums[k] != expected[k])
        throw CheckpointError(path + ": particle field '" + columns[k]->info().name +
                              "' fails its checksum (corrupt file)");
  } catch (...) {
    s.resizeLocal(0);
    throw;
  }
  return bytes;
}

// ---- state lookups -----------------------------------------------------------------------------

namespace {
template <class M>
const typename M::mapped_type& lookup(const M& m, const std::string& name,
                                      const std::string& path) {
  auto it = m.find(name);
  if (it == m.end())
    throw CheckpointError(path + ": lacks state/" + name + " (an older or foreign checkpoint?)");
  return it->second;
}
} // namespace

const std::vector<double>& CheckpointState::realArray(const std::string& name) const {
  return lookup(reals, name, path);
}
const std::vector<std::int64_t>& CheckpointState::integerArray(const std::string& name) const {
  return lookup(integers, name, path);
}
const std::vector<std::uint64_t>& CheckpointState::unsignedArray(const std::string& name) const {
  return lookup(unsignedIntegers, name, path);
}
const std::string& CheckpointState::text(const std::string& name) const {
  return lookup(texts, name, path);
}
double CheckpointState::real(const std::string& name) const {
  const auto& v = realArray(name);
  if (v.size() != 1) throw CheckpointError(path + ": state/" + name + " is not a single value");
  return v[0];
}
std::int64_t CheckpointState::integer(const std::string& name) const {
  const auto& v = integerArray(name);
  if (v.size() != 1) throw CheckpointError(path + ": state/" + name + " is not a single value");
  return v[0];
}

} // namespace spall::io
