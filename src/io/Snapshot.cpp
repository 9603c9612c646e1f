#include "spall/io/Snapshot.hpp"

#include "spall/core/Error.hpp"

#include <hdf5.h>

#include <cstdio>
#include <utility>

namespace spall::io {
namespace {

// HDF5 prints its error stack to stderr by default; we turn every failure into a RunError
// instead, so silence it while we work and restore whatever the caller had afterwards.
class QuietHdf5 {
public:
  QuietHdf5() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietHdf5() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }
  QuietHdf5(const QuietHdf5&) = delete;
  QuietHdf5& operator=(const QuietHdf5&) = delete;

private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

// The most specific message on the HDF5 error stack (e.g. the errno text of a failed open).
std::string hdf5Detail() {
  std::string detail;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned n, const H5E_error2_t* e, void* out) -> herr_t {
        if (n == 0 && e->desc) *static_cast<std::string*>(out) = e->desc;
        return 0;
      },
      &detail);
  H5Eclear2(H5E_DEFAULT);
  return detail;
}

[[noreturn]] void fail(const std::string& path, const std::string& call) {
  const std::string detail = hdf5Detail();
  throw RunError(path + ": " + call + " failed" + (detail.empty() ? "" : ": " + detail));
}

// Owns one HDF5 identifier and closes it with the matching H5?close.
class Handle {
public:
  using Closer = herr_t (*)(hid_t);
  Handle(hid_t id, Closer close, const std::string& path, const char* call)
      : id_(id), close_(close) {
    if (id_ < 0) fail(path, call);
  }
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  operator hid_t() const { return id_; }
  // Closes now, reporting failure (a file's close flushes, so it can fail).
  void close(const std::string& path, const char* call) {
    const herr_t rc = close_(id_);
    id_ = -1;
    if (rc < 0) fail(path, call);
  }

private:
  hid_t id_;
  Closer close_;
};

void check(herr_t rc, const std::string& path, const char* call) {
  if (rc < 0) fail(path, call);
}

hid_t fileType(ScalarType t) {
  switch (t) {
  case ScalarType::F64:
    return H5T_IEEE_F64LE;
  case ScalarType::U64:
    return H5T_STD_U64LE;
  case ScalarType::I32:
    return H5T_STD_I32LE;
  }
  return H5T_IEEE_F64LE;
}

hid_t memoryType(ScalarType t) {
  switch (t) {
  case ScalarType::F64:
    return H5T_NATIVE_DOUBLE;
  case ScalarType::U64:
    return H5T_NATIVE_UINT64;
  case ScalarType::I32:
    return H5T_NATIVE_INT32;
  }
  return H5T_NATIVE_DOUBLE;
}

void writeScalarAttribute(hid_t loc, const char* name, hid_t fileT, hid_t memT, const void* value,
                          const std::string& path) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, path, "H5Screate");
  Handle attr(H5Acreate2(loc, name, fileT, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, path,
              "H5Acreate2");
  check(H5Awrite(attr, memT, value), path, "H5Awrite");
}

// Fixed-length, null-terminated: simple in parallel HDF5 and read by every tool.
void writeStringAttribute(hid_t loc, const char* name, const std::string& value,
                          const std::string& path) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose, path, "H5Tcopy");
  check(H5Tset_size(type, value.size() + 1), path, "H5Tset_size");
  check(H5Tset_strpad(type, H5T_STR_NULLTERM), path, "H5Tset_strpad");
  writeScalarAttribute(loc, name, type, type, value.c_str(), path);
}

void writeField(hid_t group, hid_t dxpl, const SnapshotField& f, std::uint64_t globalCount,
                std::uint64_t offset, std::size_t localCount, const std::string& path) {
  const int rank = 1 + static_cast<int>(f.info.shape.size());
  std::vector<hsize_t> dims{globalCount}, local{localCount}, start{offset};
  for (int s : f.info.shape) {
    dims.push_back(static_cast<hsize_t>(s));
    local.push_back(static_cast<hsize_t>(s));
    start.push_back(0);
  }
  Handle fileSpace(H5Screate_simple(rank, dims.data(), nullptr), H5Sclose, path,
                   "H5Screate_simple");
  Handle memSpace(H5Screate_simple(rank, local.data(), nullptr), H5Sclose, path,
                  "H5Screate_simple");
  Handle dset(H5Dcreate2(group, f.info.name.c_str(), fileType(f.info.scalar), fileSpace,
                         H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
              H5Dclose, path, ("H5Dcreate2(" + f.info.name + ")").c_str());
  if (localCount == 0) {
    // Collective I/O: a rank without rows still joins the write with an empty selection.
    check(H5Sselect_none(fileSpace), path, "H5Sselect_none");
    check(H5Sselect_none(memSpace), path, "H5Sselect_none");
  } else {
    check(H5Sselect_hyperslab(fileSpace, H5S_SELECT_SET, start.data(), nullptr, local.data(),
                              nullptr),
          path, "H5Sselect_hyperslab");
  }
  // A dataset with no rows has no storage to write to; every rank knows, so all skip together.
  if (globalCount == 0) return;
  static const double dummy = 0.0; // HDF5 rejects a null buffer even for an empty selection
  std::vector<std::byte> scratch;
  const void* buf = f.data;
  if (!buf && f.fill && localCount > 0) {
    const std::size_t scalarBytes = f.info.scalar == ScalarType::I32 ? 4 : 8;
    scratch.resize(localCount * f.info.scalarsPerParticle() * scalarBytes);
    f.fill(scratch.data());
    buf = scratch.data();
  }
  if (!buf) buf = &dummy;
  check(H5Dwrite(dset, memoryType(f.info.scalar), memSpace, fileSpace, dxpl, buf), path,
        ("H5Dwrite(" + f.info.name + ")").c_str());
}

void writeFile(MPI_Comm comm, const std::string& tmp, const SnapshotAttributes& attrs,
               std::size_t localCount, std::span<const SnapshotField> fields) {
  std::uint64_t local = localCount, offset = 0, global = 0;
  MPI_Exscan(&local, &offset, 1, MPI_UINT64_T, MPI_SUM, comm);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) offset = 0; // MPI_Exscan leaves rank 0's result undefined
  MPI_Allreduce(&local, &global, 1, MPI_UINT64_T, MPI_SUM, comm);

  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, tmp, "H5Pcreate");
  check(H5Pset_fapl_mpio(fapl, comm, MPI_INFO_NULL), tmp, "H5Pset_fapl_mpio");
  Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl), H5Fclose, tmp, "H5Fcreate");

  writeScalarAttribute(file, "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &attrs.time, tmp);
  writeScalarAttribute(file, "step", H5T_STD_I64LE, H5T_NATIVE_INT64, &attrs.step, tmp);
  writeScalarAttribute(file, "dimension", H5T_STD_I32LE, H5T_NATIVE_INT, &attrs.dimension, tmp);
  writeStringAttribute(file, "spall_version", attrs.version, tmp);

  Handle group(H5Gcreate2(file, "particles", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, tmp,
               "H5Gcreate2(particles)");
  Handle dxpl(H5Pcreate(H5P_DATASET_XFER), H5Pclose, tmp, "H5Pcreate");
  check(H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE), tmp, "H5Pset_dxpl_mpio");
  for (const auto& f : fields) writeField(group, dxpl, f, global, offset, localCount, tmp);
  group.close(tmp, "H5Gclose");
  file.close(tmp, "H5Fclose");
}

} // namespace

void writeSnapshot(MPI_Comm comm, const std::string& path, const SnapshotAttributes& attrs,
                   std::size_t localCount, std::span<const SnapshotField> fields) {
  QuietHdf5 quiet;
  const std::string tmp = path + ".tmp";
  writeFile(comm, tmp, attrs, localCount, fields);

  // Every rank has closed the file (H5Fclose is collective); rank 0 publishes it, and the
  // broadcast of the outcome keeps the other ranks from returning before the rename.
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  int ok = 1;
  if (rank == 0) ok = std::rename(tmp.c_str(), path.c_str()) == 0 ? 1 : 0;
  MPI_Bcast(&ok, 1, MPI_INT, 0, comm);
  MPI_Barrier(comm);
  if (!ok) throw RunError(path + ": cannot rename " + tmp + " to it");
}

namespace {

template <class T>
T readScalarAttribute(hid_t loc, const char* name, hid_t memT, const std::string& path) {
  Handle attr(H5Aopen(loc, name, H5P_DEFAULT), H5Aclose, path,
              (std::string("H5Aopen(") + name + ")").c_str());
  T value{};
  check(H5Aread(attr, memT, &value), path, "H5Aread");
  return value;
}

std::string readStringAttribute(hid_t loc, const char* name, const std::string& path) {
  Handle attr(H5Aopen(loc, name, H5P_DEFAULT), H5Aclose, path,
              (std::string("H5Aopen(") + name + ")").c_str());
  Handle type(H5Aget_type(attr), H5Tclose, path, "H5Aget_type");
  if (H5Tis_variable_str(type) > 0) { // written by another tool
    char* s = nullptr;
    Handle memT(H5Tcopy(H5T_C_S1), H5Tclose, path, "H5Tcopy");
    check(H5Tset_size(memT, H5T_VARIABLE), path, "H5Tset_size");
    check(H5Aread(attr, memT, &s), path, "H5Aread");
    std::string out = s ? s : "";
    H5free_memory(s);
    return out;
  }
  std::string buf(H5Tget_size(type), '\0');
  check(H5Aread(attr, type, buf.data()), path, "H5Aread");
  return buf.substr(0, buf.find('\0'));
}

} // namespace

SnapshotData readSnapshot(const std::string& path) {
  QuietHdf5 quiet;
  SnapshotData out;
  Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, path, "H5Fopen");
  out.time = readScalarAttribute<double>(file, "time", H5T_NATIVE_DOUBLE, path);
  out.step = readScalarAttribute<std::int64_t>(file, "step", H5T_NATIVE_INT64, path);
  out.dimension = readScalarAttribute<int>(file, "dimension", H5T_NATIVE_INT, path);
  out.version = readStringAttribute(file, "spall_version", path);

  Handle group(H5Gopen2(file, "particles", H5P_DEFAULT), H5Gclose, path, "H5Gopen2(particles)");
  H5G_info_t info;
  check(H5Gget_info(group, &info), path, "H5Gget_info");
  bool first = true;
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t len =
        H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (len < 0) fail(path, "H5Lget_name_by_idx");
    std::string name(static_cast<std::size_t>(len) + 1, '\0');
    H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size(),
                       H5P_DEFAULT);
    name.resize(static_cast<std::size_t>(len));

    Handle dset(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose, path,
                ("H5Dopen2(" + name + ")").c_str());
    Handle space(H5Dget_space(dset), H5Sclose, path, "H5Dget_space");
    const int rank = H5Sget_simple_extent_ndims(space);
    if (rank < 1) throw RunError(path + ": dataset /particles/" + name + " has no particle axis");
    std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
    H5Sget_simple_extent_dims(space, dims.data(), nullptr);
    if (first) out.count = dims[0];
    if (dims[0] != out.count)
      throw RunError(path + ": dataset /particles/" + name + " has " + std::to_string(dims[0]) +
                     " rows, expected " + std::to_string(out.count));
    first = false;

    std::size_t n = 1;
    auto& shape = out.shapes[name];
    for (int d = 0; d < rank; ++d) {
      n *= dims[static_cast<std::size_t>(d)];
      if (d > 0) shape.push_back(static_cast<int>(dims[static_cast<std::size_t>(d)]));
    }
    auto& values = out.fields[name];
    values.resize(n);
    if (n > 0)
      check(H5Dread(dset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), path,
            ("H5Dread(" + name + ")").c_str());
    if (name == "id") {
      out.id.resize(n);
      if (n > 0)
        check(H5Dread(dset, H5T_NATIVE_UINT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.id.data()), path,
              "H5Dread(id)");
    }
  }
  return out;
}

} // namespace spall::io
