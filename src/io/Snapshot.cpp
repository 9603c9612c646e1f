#include "spall/io/Snapshot.hpp"

#include "Hdf5Util.hpp"
#include "spall/core/Error.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <utility>

namespace spall::io {
namespace {

using hdf5::check;
using hdf5::fail;
using hdf5::Handle;
using hdf5::readScalarAttribute;
using hdf5::readStringAttribute;
using hdf5::writeScalarAttribute;
using hdf5::writeStringAttribute;

// A [n, n] double field's rows, each transposed from the store's column-major to row-major.
void transposeRows(double* rows, std::size_t count, int n) {
  for (std::size_t i = 0; i < count; ++i) {
    double* T = rows + i * static_cast<std::size_t>(n * n);
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b) std::swap(T[a * n + b], T[b * n + a]);
  }
}

bool isMatrix(const FieldInfo& info) {
  return info.scalar == ScalarType::F64 && info.shape.size() == 2 &&
         info.shape[0] == info.shape[1] && info.shape[0] > 1;
}

void writeField(hid_t group, hid_t dxpl, const SnapshotField& f, std::uint64_t globalCount,
                std::uint64_t offset, std::size_t localCount, const std::string& path) {
  std::vector<std::byte> scratch;
  const void* buf = f.data;
  const bool matrix = isMatrix(f.info);
  if ((f.fill || matrix) && localCount > 0) {
    const std::size_t scalarBytes = f.info.scalar == ScalarType::I32 ? 4 : 8;
    scratch.resize(localCount * f.info.scalarsPerParticle() * scalarBytes);
    if (!f.data && f.fill)
      f.fill(scratch.data());
    else if (f.data)
      std::memcpy(scratch.data(), f.data, scratch.size());
    if (matrix)
      transposeRows(reinterpret_cast<double*>(scratch.data()), localCount, f.info.shape[0]);
    buf = scratch.data();
  }
  hdf5::writeRows(group, dxpl, f.info, globalCount, offset, localCount, buf, path, [&](hid_t d) {
    if (!f.unit.empty()) writeStringAttribute(d, "units", f.unit, path);
    if (matrix) writeStringAttribute(d, "layout", "row-major", path);
  });
}

// What an XDMF reader needs beyond the fields of a point set (Snapshot.hpp).
void writePointSetSupport(hid_t xdmf, hid_t dxpl, const SnapshotGroup& g, std::uint64_t globalCount,
                          std::uint64_t offset, const std::string& path) {
  const auto pos = std::find_if(g.fields.begin(), g.fields.end(),
                                [](const SnapshotField& f) { return f.info.name == "position"; });
  if (pos == g.fields.end()) return;
  const std::size_t n = g.localCount;
  const bool wide = globalCount > static_cast<std::uint64_t>(INT32_MAX);
  const FieldInfo vertices{g.name + "_vertices", wide ? ScalarType::I64 : ScalarType::I32, {1}, 0};
  std::vector<std::int32_t> v32(wide ? 0 : n);
  std::vector<std::int64_t> v64(wide ? n : 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (wide)
      v64[i] = static_cast<std::int64_t>(offset + i);
    else
      v32[i] = static_cast<std::int32_t>(offset + i);
  }
  hdf5::writeRows(xdmf, dxpl, vertices, globalCount, offset, n,
                  wide ? static_cast<const void*>(v64.data()) : v32.data(), path);
  if (pos->info.shape != std::vector<int>{1}) return;
  std::vector<double> x(n), xyz(3 * n, 0.0);
  if (n > 0) {
    if (pos->data)
      std::memcpy(x.data(), pos->data, n * sizeof(double));
    else
      pos->fill(x.data());
  }
  for (std::size_t i = 0; i < n; ++i) xyz[3 * i] = x[i];
  const FieldInfo points{g.name + "_points", ScalarType::F64, {3}, 0};
  hdf5::writeRows(xdmf, dxpl, points, globalCount, offset, n, xyz.data(), path,
                  [&](hid_t d) { writeStringAttribute(d, "units", pos->unit, path); });
}

void writeFile(MPI_Comm comm, const std::string& tmp, const SnapshotAttributes& attrs,
               std::span<const SnapshotGroup> groups) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, tmp, "H5Pcreate");
  check(H5Pset_fapl_mpio(fapl, comm, MPI_INFO_NULL), tmp, "H5Pset_fapl_mpio");
  Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl), H5Fclose, tmp, "H5Fcreate");

  writeScalarAttribute(file, "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &attrs.time, tmp);
  writeScalarAttribute(file, "step", H5T_STD_I64LE, H5T_NATIVE_INT64, &attrs.step, tmp);
  writeScalarAttribute(file, "dimension", H5T_STD_I32LE, H5T_NATIVE_INT, &attrs.dimension, tmp);
  writeStringAttribute(file, "spall_version", attrs.version, tmp);
  if (!attrs.geometry.empty()) writeStringAttribute(file, "geometry", attrs.geometry, tmp);
  if (!attrs.axes.empty()) writeStringAttribute(file, "axes", attrs.axes, tmp);
  hdf5::writeStringArrayAttribute(file, "material_names", attrs.materialNames, tmp);
  hdf5::writeStringArrayAttribute(file, "body_names", attrs.bodyNames, tmp);

  Handle dxpl(H5Pcreate(H5P_DATASET_XFER), H5Pclose, tmp, "H5Pcreate");
  check(H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE), tmp, "H5Pset_dxpl_mpio");
  Handle xdmf(H5Gcreate2(file, "xdmf", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, tmp,
              "H5Gcreate2(xdmf)");
  for (const auto& g : groups) {
    std::uint64_t local = g.localCount, offset = 0, global = 0;
    MPI_Exscan(&local, &offset, 1, MPI_UINT64_T, MPI_SUM, comm);
    if (rank == 0) offset = 0; // MPI_Exscan leaves rank 0's result undefined
    MPI_Allreduce(&local, &global, 1, MPI_UINT64_T, MPI_SUM, comm);
    Handle group(H5Gcreate2(file, g.name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                 tmp, ("H5Gcreate2(" + g.name + ")").c_str());
    for (const auto& f : g.fields) writeField(group, dxpl, f, global, offset, g.localCount, tmp);
    group.close(tmp, "H5Gclose");
    writePointSetSupport(xdmf, dxpl, g, global, offset, tmp);
  }
  xdmf.close(tmp, "H5Gclose");
  file.close(tmp, "H5Fclose");
}

} // namespace

void writeSnapshot(MPI_Comm comm, const std::string& path, const SnapshotAttributes& attrs,
                   std::span<const SnapshotGroup> groups) {
  hdf5::Quiet quiet;
  const std::string tmp = path + ".tmp";
  writeFile(comm, tmp, attrs, groups);

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

void writeSnapshot(MPI_Comm comm, const std::string& path, const SnapshotAttributes& attrs,
                   std::size_t localCount, std::span<const SnapshotField> fields) {
  const SnapshotGroup particles{"particles", localCount, fields};
  writeSnapshot(comm, path, attrs, std::span<const SnapshotGroup>(&particles, 1));
}

SnapshotData readSnapshot(const std::string& path) {
  hdf5::Quiet quiet;
  SnapshotData out;
  Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, path, "H5Fopen");
  out.time = readScalarAttribute<double>(file, "time", H5T_NATIVE_DOUBLE, path);
  out.step = readScalarAttribute<std::int64_t>(file, "step", H5T_NATIVE_INT64, path);
  out.dimension = readScalarAttribute<int>(file, "dimension", H5T_NATIVE_INT, path);
  out.version = readStringAttribute(file, "spall_version", path);
  if (hdf5::hasAttribute(file, "geometry"))
    out.geometry = readStringAttribute(file, "geometry", path);
  if (hdf5::hasAttribute(file, "axes")) out.axes = readStringAttribute(file, "axes", path);
  if (hdf5::hasAttribute(file, "material_names"))
    out.materialNames = hdf5::readStringArrayAttribute(file, "material_names", path);
  if (hdf5::hasAttribute(file, "body_names"))
    out.bodyNames = hdf5::readStringArrayAttribute(file, "body_names", path);

  Handle group(H5Gopen2(file, "particles", H5P_DEFAULT), H5Gclose, path, "H5Gopen2(particles)");
  H5G_info_t info;
  check(H5Gget_info(group, &info), path, "H5Gget_info");
  bool first = true;
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const std::string name = hdf5::linkName(group, i, path);

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
    if (hdf5::hasAttribute(dset, "units"))
      out.units[name] = readStringAttribute(dset, "units", path);
    // Files from before the `layout` attribute hold the store's column-major tensors.
    const FieldInfo asRead{name, ScalarType::F64, shape};
    if (isMatrix(asRead) && !hdf5::hasAttribute(dset, "layout"))
      transposeRows(values.data(), out.count, shape[0]);
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
