#pragma once
// Structure-of-arrays particle storage. Modules register the fields they need once, at set-up;
// every registered field then resizes, permutes, is copied to ghosts, migrates and is
// checkpointed by the generic code here, without that code knowing the field.
//
// Layout: particles [0, localCount) are owned by this rank; [localCount, size) are ghosts
// (periodic images, wall mirrors, later remote halo copies), rebuilt every step.
#include "spall/core/Threads.hpp"
#include "spall/core/Types.hpp"
#include "spall/core/XorDelta.hpp"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace spall {

enum class ScalarType { F64, U64, I32, I64 };
inline std::size_t scalarBytes(ScalarType t) {
  return t == ScalarType::I32 ? 4 : 8;
}

enum FieldFlag : unsigned {
  kOutput = 1u << 0,     // written to snapshots when the deck asks for it (default: all)
  kCheckpoint = 1u << 1, // part of the restartable state
  kHalo = 1u << 2,       // read of ghosts by the neighbor search or a pair loop: sent to them
                         // by every halo build
  kRefresh = 1u << 3,    // changed by the density pass (summation, EOS) after the ghosts were
                         // made: sent to them again before the force loop
  // What a rigid wall's mirror image does to the field (P = I - 2 n n^T); unflagged fields are
  // copied to the image as they are. (The type alone cannot say: in 1D a vector and a tensor
  // are both 1x1.)
  kReflectVector = 1u << 4, // P v
  kReflectTensor = 1u << 5, // P T P (Dim x Dim, or embedded in 3x3)
};

struct FieldInfo {
  std::string name;
  ScalarType scalar = ScalarType::F64;
  std::vector<int> shape; // per-particle shape: {} scalar, {Dim} vector, {Dim,Dim} tensor
  unsigned flags = kOutput | kCheckpoint;
  std::size_t scalarsPerParticle() const {
    std::size_t n = 1;
    for (int s : shape) n *= static_cast<std::size_t>(s);
    return n;
  }
};

// Maps a C++ element type to its HDF5-facing description.
template <class T> struct ElementTraits;
template <> struct ElementTraits<double> {
  static constexpr ScalarType scalar = ScalarType::F64;
  static std::vector<int> shape() { return {}; }
};
template <> struct ElementTraits<std::uint64_t> {
  static constexpr ScalarType scalar = ScalarType::U64;
  static std::vector<int> shape() { return {}; }
};
template <> struct ElementTraits<std::int64_t> {
  static constexpr ScalarType scalar = ScalarType::I64;
  static std::vector<int> shape() { return {}; }
};
template <> struct ElementTraits<std::int32_t> {
  static constexpr ScalarType scalar = ScalarType::I32;
  static std::vector<int> shape() { return {}; }
};
template <int R, int C> struct ElementTraits<Eigen::Matrix<double, R, C>> {
  static constexpr ScalarType scalar = ScalarType::F64;
  static std::vector<int> shape() { return C == 1 ? std::vector<int>{R} : std::vector<int>{R, C}; }
};

class ColumnBase {
public:
  explicit ColumnBase(FieldInfo info) : info_(std::move(info)) {}
  virtual ~ColumnBase() = default;
  const FieldInfo& info() const { return info_; }
  void addFlags(unsigned flags) { info_.flags |= flags; }
  virtual void resize(std::size_t n) = 0;
  virtual void copy(std::size_t from, std::size_t to) = 0;
  // After the call, element i holds what element order[i] held, for i < order.size().
  virtual void permutePrefix(std::span<const std::uint32_t> order) = 0;
  // Copies rows `rows` into `out` (bytesPerParticle() each, in that order) / rows
  // [first, first + count) from `in`: the generic path by which any field migrates, is copied to
  // remote ghosts and is checkpointed.
  virtual void pack(std::span<const std::uint32_t> rows, std::byte* out) const = 0;
  virtual void unpack(const std::byte* in, std::size_t first, std::size_t count) = 0;
  virtual void shrink(std::size_t n) = 0;
  virtual std::size_t bytesPerParticle() const = 0;
  virtual void* raw() = 0;
  virtual const void* raw() const = 0;

private:
  FieldInfo info_;
};

template <class T> class Column final : public ColumnBase {
public:
  explicit Column(FieldInfo info) : ColumnBase(std::move(info)) {}
  std::vector<T> values;
  void resize(std::size_t n) override { values.resize(n); }
  void copy(std::size_t from, std::size_t to) override { values[to] = values[from]; }
  void permutePrefix(std::span<const std::uint32_t> order) override {
    std::vector<T> tmp(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) tmp[i] = values[order[i]];
    std::copy(tmp.begin(), tmp.end(), values.begin());
  }
  void pack(std::span<const std::uint32_t> rows, std::byte* out) const override {
    for (std::size_t k = 0; k < rows.size(); ++k)
      std::memcpy(out + k * sizeof(T), static_cast<const void*>(&values[rows[k]]), sizeof(T));
  }
  void unpack(const std::byte* in, std::size_t first, std::size_t count) override {
    if (count > 0) std::memcpy(static_cast<void*>(&values[first]), in, count * sizeof(T));
  }
  void shrink(std::size_t n) override {
    values.resize(n);
    values.shrink_to_fit();
  }
  std::size_t bytesPerParticle() const override { return sizeof(T); }
  void* raw() override { return values.data(); }
  const void* raw() const override { return values.data(); }
};

// A typed handle to a registered field: looked up once, then used without strings.
template <class T> struct Field {
  std::size_t index = static_cast<std::size_t>(-1);
  bool valid() const { return index != static_cast<std::size_t>(-1); }
};

class ParticleStore {
public:
  // Registers a field (or returns the existing one of the same name and type).
  template <class T> Field<T> add(const std::string& name, unsigned flags = kOutput | kCheckpoint) {
    for (std::size_t i = 0; i < columns_.size(); ++i) {
      if (columns_[i]->info().name == name) {
        if (!dynamic_cast<Column<T>*>(columns_[i].get()))
          throw std::logic_error("field '" + name + "' registered twice with different types");
        return Field<T>{i};
      }
    }
    FieldInfo info{name, ElementTraits<T>::scalar, ElementTraits<T>::shape(), flags};
    auto col = std::make_unique<Column<T>>(std::move(info));
    col->resize(capacity_);
    columns_.push_back(std::move(col));
    return Field<T>{columns_.size() - 1};
  }

  template <class T> std::span<T> operator[](Field<T> f) {
    auto& v = static_cast<Column<T>*>(columns_[f.index].get())->values;
    return {v.data(), size_};
  }
  template <class T> std::span<const T> operator[](Field<T> f) const {
    const auto& v = static_cast<const Column<T>*>(columns_[f.index].get())->values;
    return {v.data(), size_};
  }

  // Exchanges the contents of two fields of the same type (e.g. current and previous rates).
  template <class T> void swapValues(Field<T> a, Field<T> b) {
    std::swap(static_cast<Column<T>*>(columns_[a.index].get())->values,
              static_cast<Column<T>*>(columns_[b.index].get())->values);
  }

  std::size_t size() const { return size_; }
  std::size_t localCount() const { return local_; }
  std::size_t ghostCount() const { return size_ - local_; }
  // Changes whenever rows are added, dropped or reordered: what was built on the rows (a ghost
  // layer, neighbor lists that index them) is stale when it differs from the value then.
  std::uint64_t layout() const { return layout_; }

  // Sets the number of owned particles; drops all ghosts.
  void resizeLocal(std::size_t n) {
    local_ = n;
    resizeAll(n);
  }
  void dropGhosts() { resizeAll(local_); }
  // Appends a ghost that copies every field of particle `source`; returns its index.
  std::size_t appendGhostCopy(std::size_t source) {
    const std::size_t g = size_;
    growTo(size_ + 1);
    for (auto& c : columns_) c->copy(source, g);
    return g;
  }
  // Reorders the owned particles (e.g. along a space-filling curve); ghosts are dropped.
  void permuteLocal(std::span<const std::uint32_t> order) {
    if (order.size() != local_)
      throw std::logic_error("permuteLocal: order must cover all owned particles");
    dropGhosts();
    for (auto& c : columns_) c->permutePrefix(order);
  }

  // Keeps the owned rows `rows`, in that order, as the new owned set (migration, start-up slice).
  void keepLocal(std::span<const std::uint32_t> rows) {
    dropGhosts();
    for (auto& c : columns_) c->permutePrefix(rows);
    local_ = rows.size();
    resizeAll(local_);
  }
  // Appends `count` owned rows (their values to be unpacked by the caller); drops ghosts.
  std::size_t appendLocal(std::size_t count) {
    dropGhosts();
    const std::size_t first = local_;
    growTo(local_ + count);
    local_ += count;
    return first;
  }
  // Sets every field of owned rows [first, first + count) to zero bits: particles that join a
  // running store start from nothing but what their maker sets (a grown column's rows may hold an
  // earlier ghost's values, and fixed-size Eigen types are not value-initialised).
  void zeroRows(std::size_t first, std::size_t count) {
    std::vector<std::byte> zeros;
    for (auto& c : columns_) {
      zeros.assign(count * c->bytesPerParticle(), std::byte{0});
      c->unpack(zeros.data(), first, count);
    }
  }
  // Appends `count` ghost rows (values to be unpacked by the caller); returns the first.
  std::size_t appendGhosts(std::size_t count) {
    const std::size_t first = size_;
    growTo(size_ + count);
    return first;
  }
  // Releases rows beyond the current size plus some headroom for ghosts (after the start-up
  // distribution every rank briefly held all particles).
  void shrinkToFit(double headroom = 0.25) {
    capacity_ = size_ + static_cast<std::size_t>(headroom * static_cast<double>(size_));
    for (auto& c : columns_) c->shrink(capacity_);
  }

  const std::vector<std::unique_ptr<ColumnBase>>& columns() const { return columns_; }
  const ColumnBase* find(std::string_view name) const {
    for (const auto& c : columns_)
      if (c->info().name == name) return c.get();
    return nullptr;
  }
  // The columns' allocated rows (owned, ghosts and headroom), every field's bytes.
  std::size_t fieldBytes() const { return capacity_ * bytesPerParticle(); }
  std::size_t bytesPerParticle() const {
    std::size_t b = 0;
    for (const auto& c : columns_) b += c->bytesPerParticle();
    return b;
  }
  // Copies row `from` of one column to row `to` (wall images refreshing from their source).
  void copyRow(std::size_t column, std::size_t from, std::size_t to) {
    columns_[column]->copy(from, to);
  }
  // Adds flags to a registered field (a module that needs another module's field on ghosts).
  void addFlags(std::size_t column, unsigned flags) { columns_[column]->addFlags(flags); }
  // The columns carrying all of `flags`, in registration order.
  std::vector<std::size_t> columnsWith(unsigned flags) const {
    std::vector<std::size_t> out;
    for (std::size_t i = 0; i < columns_.size(); ++i)
      if ((columns_[i]->info().flags & flags) == flags) out.push_back(i);
    return out;
  }

  // The owned rows of some columns, byte for byte: a state to return to (the run's rescue point).
  // Each column is kept packed (core/XorDelta.hpp: 0.57-0.77 of its bytes).
  struct RowsCopy {
    std::size_t count = 0;
    std::vector<std::size_t> columns;
    std::vector<std::vector<std::byte>> bytes; // packed
    std::size_t size() const {
      std::size_t b = 0;
      for (const auto& v : bytes) b += v.size();
      return b;
    }
  };
  // Copies the owned rows of the columns carrying all of `flags` into `out`.
  void copyRows(unsigned flags, RowsCopy& out) const {
    out.count = local_;
    out.columns = columnsWith(flags);
    out.bytes.resize(out.columns.size());
    const std::size_t columns = out.columns.size();
    // (An exception must not leave a parallel region: a failed allocation is carried out.)
    std::exception_ptr failure;
#pragma omp parallel for schedule(dynamic, 1) if (threaded(local_))
    for (std::size_t k = 0; k < columns; ++k) {
      const ColumnBase& c = *columns_[out.columns[k]];
      try {
        out.bytes[k] = xordelta::pack(static_cast<const std::byte*>(c.raw()), local_,
                                      c.bytesPerParticle(), scalarBytes(c.info().scalar));
      } catch (...) {
#pragma omp critical(spall_rows_copy_failure)
        if (!failure) failure = std::current_exception();
      }
    }
    if (failure) std::rethrow_exception(failure);
  }
  // Makes the copy's rows the owned rows again (no ghosts); the other columns keep whatever
  // their first `count` rows held.
  void restoreRows(const RowsCopy& in) {
    dropGhosts();
    if (in.count > local_) growTo(in.count);
    local_ = in.count;
    resizeAll(local_);
    for (std::size_t k = 0; k < in.columns.size(); ++k) {
      ColumnBase& c = *columns_[in.columns[k]];
      xordelta::unpack(in.bytes[k], static_cast<std::byte*>(c.raw()), local_, c.bytesPerParticle(),
                       scalarBytes(c.info().scalar));
    }
  }

private:
  void resizeAll(std::size_t n) {
    ++layout_;
    size_ = n;
    if (n > capacity_) capacity_ = n;
    for (auto& c : columns_) c->resize(capacity_);
  }
  void growTo(std::size_t n) {
    ++layout_;
    if (n > capacity_) {
      // Modest growth: ghost counts settle within a few steps, and every column pays the slack.
      capacity_ = std::max<std::size_t>(n, capacity_ + capacity_ / 8 + 16);
      for (auto& c : columns_) c->resize(capacity_);
    }
    size_ = n;
  }

  std::vector<std::unique_ptr<ColumnBase>> columns_;
  std::size_t size_ = 0;     // owned + ghosts
  std::size_t local_ = 0;    // owned
  std::size_t capacity_ = 0; // allocated rows in every column
  std::uint64_t layout_ = 0;
};

} // namespace spall
