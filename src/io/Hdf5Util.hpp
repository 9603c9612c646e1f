#pragma once
// Small RAII and error helpers shared by the snapshot and checkpoint files: every HDF5 failure
// becomes a RunError naming the file and the call, never a printed error stack.
#include "spall/core/Error.hpp"
#include "spall/core/ParticleStore.hpp"

#include <hdf5.h>

#include <algorithm>
#include <functional>
#include <string>
#include <vector>

namespace spall::io::hdf5 {

// HDF5 prints its error stack to stderr by default; silence it while we work and restore
// whatever the caller had afterwards.
class Quiet {
public:
  Quiet() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~Quiet() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }
  Quiet(const Quiet&) = delete;
  Quiet& operator=(const Quiet&) = delete;

private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

// The most specific message on the HDF5 error stack (e.g. the errno text of a failed open).
inline std::string detail() {
  std::string out;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned n, const H5E_error2_t* e, void* text) -> herr_t {
        if (n == 0 && e->desc) *static_cast<std::string*>(text) = e->desc;
        return 0;
      },
      &out);
  H5Eclear2(H5E_DEFAULT);
  return out;
}

[[noreturn]] inline void fail(const std::string& path, const std::string& call) {
  const std::string d = detail();
  throw RunError(path + ": " + call + " failed" + (d.empty() ? "" : ": " + d));
}

inline void check(herr_t rc, const std::string& path, const char* call) {
  if (rc < 0) fail(path, call);
}

// Owns one HDF5 identifier and closes it with the matching H5?close.
class Handle {
public:
  using Closer = herr_t (*)(hid_t);
  Handle(hid_t id, Closer close, const std::string& path, const std::string& call)
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

inline hid_t fileType(ScalarType t) {
  switch (t) {
  case ScalarType::F64:
    return H5T_IEEE_F64LE;
  case ScalarType::U64:
    return H5T_STD_U64LE;
  case ScalarType::I32:
    return H5T_STD_I32LE;
  case ScalarType::I64:
    return H5T_STD_I64LE;
  }
  return H5T_IEEE_F64LE;
}

inline hid_t memoryType(ScalarType t) {
  switch (t) {
  case ScalarType::F64:
    return H5T_NATIVE_DOUBLE;
  case ScalarType::U64:
    return H5T_NATIVE_UINT64;
  case ScalarType::I32:
    return H5T_NATIVE_INT32;
  case ScalarType::I64:
    return H5T_NATIVE_INT64;
  }
  return H5T_NATIVE_DOUBLE;
}

inline void writeScalarAttribute(hid_t loc, const char* name, hid_t fileT, hid_t memT,
                                 const void* value, const std::string& path) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, path, "H5Screate");
  Handle attr(H5Acreate2(loc, name, fileT, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, path,
              std::string("H5Acreate2(") + name + ")");
  check(H5Awrite(attr, memT, value), path, "H5Awrite");
}

// Fixed-length, null-terminated: simple in parallel HDF5 and read by every tool.
inline void writeStringAttribute(hid_t loc, const char* name, const std::string& value,
                                 const std::string& path) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose, path, "H5Tcopy");
  check(H5Tset_size(type, value.size() + 1), path, "H5Tset_size");
  check(H5Tset_strpad(type, H5T_STR_NULLTERM), path, "H5Tset_strpad");
  writeScalarAttribute(loc, name, type, type, value.c_str(), path);
}

// Fixed-length strings of the longest one's size, one per entry: h5py reads them as an array of
// bytes. An empty list is a null dataspace.
inline void writeStringArrayAttribute(hid_t loc, const char* name,
                                      const std::vector<std::string>& values,
                                      const std::string& path) {
  std::size_t width = 1;
  for (const auto& v : values) width = std::max(width, v.size() + 1);
  std::string buf(values.size() * width, '\0');
  for (std::size_t k = 0; k < values.size(); ++k)
    buf.replace(k * width, values[k].size(), values[k]);
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose, path, "H5Tcopy");
  check(H5Tset_size(type, width), path, "H5Tset_size");
  check(H5Tset_strpad(type, H5T_STR_NULLTERM), path, "H5Tset_strpad");
  const hsize_t n = values.size();
  Handle space(n ? H5Screate_simple(1, &n, nullptr) : H5Screate(H5S_NULL), H5Sclose, path,
               "H5Screate");
  Handle attr(H5Acreate2(loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, path,
              std::string("H5Acreate2(") + name + ")");
  if (n) check(H5Awrite(attr, type, buf.data()), path, "H5Awrite");
}

inline bool hasAttribute(hid_t loc, const char* name) {
  return H5Aexists(loc, name) > 0;
}

// The name of the i-th link of a group, in name order.
inline std::string linkName(hid_t group, hsize_t i, const std::string& path) {
  const ssize_t len =
      H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
  if (len < 0) fail(path, "H5Lget_name_by_idx");
  std::string name(static_cast<std::size_t>(len) + 1, '\0');
  H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size(),
                     H5P_DEFAULT);
  name.resize(static_cast<std::size_t>(len));
  return name;
}

template <class T>
T readScalarAttribute(hid_t loc, const char* name, hid_t memT, const std::string& path) {
  Handle attr(H5Aopen(loc, name, H5P_DEFAULT), H5Aclose, path,
              std::string("H5Aopen(") + name + ")");
  T value{};
  check(H5Aread(attr, memT, &value), path, "H5Aread");
  return value;
}

inline std::string readStringAttribute(hid_t loc, const char* name, const std::string& path) {
  Handle attr(H5Aopen(loc, name, H5P_DEFAULT), H5Aclose, path,
              std::string("H5Aopen(") + name + ")");
  Handle type(H5Aget_type(attr), H5Tclose, path, "H5Aget_type");
  if (H5Tget_class(type) != H5T_STRING)
    throw RunError(path + ": attribute '" + name + "' is not a string");
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

// A fixed-length string array attribute (writeStringArrayAttribute's).
inline std::vector<std::string> readStringArrayAttribute(hid_t loc, const char* name,
                                                         const std::string& path) {
  Handle attr(H5Aopen(loc, name, H5P_DEFAULT), H5Aclose, path,
              std::string("H5Aopen(") + name + ")");
  Handle type(H5Aget_type(attr), H5Tclose, path, "H5Aget_type");
  Handle space(H5Aget_space(attr), H5Sclose, path, "H5Aget_space");
  if (H5Tget_class(type) != H5T_STRING || H5Tis_variable_str(type) > 0)
    throw RunError(path + ": attribute '" + name + "' is not an array of fixed-length strings");
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  if (n <= 0) return {};
  const std::size_t width = H5Tget_size(type);
  std::string buf(static_cast<std::size_t>(n) * width, '\0');
  check(H5Aread(attr, type, buf.data()), path, "H5Aread");
  std::vector<std::string> out;
  for (hssize_t k = 0; k < n; ++k) {
    const std::string s = buf.substr(static_cast<std::size_t>(k) * width, width);
    out.push_back(s.substr(0, s.find('\0')));
  }
  return out;
}

// Creates group/NAME as [global, shape...] and writes this rank's `local` rows (`rows`, row-major)
// at row `offset`, collectively: a rank without rows joins with an empty selection, and with no
// rows anywhere nothing is written. `decorate` may add attributes to the new dataset.
inline void writeRows(hid_t group, hid_t dxpl, const FieldInfo& info, std::uint64_t global,
                      std::uint64_t offset, std::size_t local, const void* rows,
                      const std::string& path,
                      const std::function<void(hid_t)>& decorate = nullptr) {
  const int rank = 1 + static_cast<int>(info.shape.size());
  std::vector<hsize_t> dims{global}, mine{local}, start{offset};
  for (int e : info.shape) {
    dims.push_back(static_cast<hsize_t>(e));
    mine.push_back(static_cast<hsize_t>(e));
    start.push_back(0);
  }
  Handle fileSpace(H5Screate_simple(rank, dims.data(), nullptr), H5Sclose, path,
                   "H5Screate_simple");
  Handle memSpace(H5Screate_simple(rank, mine.data(), nullptr), H5Sclose, path, "H5Screate_simple");
  Handle dset(H5Dcreate2(group, info.name.c_str(), fileType(info.scalar), fileSpace, H5P_DEFAULT,
                         H5P_DEFAULT, H5P_DEFAULT),
              H5Dclose, path, "H5Dcreate2(" + info.name + ")");
  if (decorate) decorate(dset);
  if (global == 0) return; // no storage to write to; every rank knows, so all skip together
  if (local == 0) {
    check(H5Sselect_none(fileSpace), path, "H5Sselect_none");
    check(H5Sselect_none(memSpace), path, "H5Sselect_none");
  } else {
    check(
        H5Sselect_hyperslab(fileSpace, H5S_SELECT_SET, start.data(), nullptr, mine.data(), nullptr),
        path, "H5Sselect_hyperslab");
  }
  static const double dummy = 0.0; // HDF5 rejects a null buffer even for an empty selection
  check(H5Dwrite(dset, memoryType(info.scalar), memSpace, fileSpace, dxpl,
                 local > 0 && rows ? rows : &dummy),
        path, ("H5Dwrite(" + info.name + ")").c_str());
}

} // namespace spall::io::hdf5
