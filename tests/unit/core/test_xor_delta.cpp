// The rescue copy's packing (core/XorDelta.hpp): rows come back bit for bit, whatever the values
// (NaN payloads, -0, subnormals, infinities, random bits) and shapes (scalars, vectors,
// tensors, 4- and 8-byte scalars, no row, one row); smooth rows in curve order take fewer bytes;
// damaged data is refused rather than read past its end.
#include "spall/core/XorDelta.hpp"

#include <cmath>
#include <cstring>
#include <gtest/gtest.h>
#include <limits>
#include <random>

using namespace spall;

namespace {
template <class T> std::vector<std::byte> bytesOf(const std::vector<T>& v) {
  std::vector<std::byte> b(v.size() * sizeof(T));
  if (!v.empty()) std::memcpy(b.data(), v.data(), b.size());
  return b;
}

template <class T> void roundTrip(const std::vector<T>& values, std::size_t perRow) {
  const std::size_t rows = values.size() / perRow, stride = perRow * sizeof(T);
  const auto raw = bytesOf(values);
  const auto packed = xordelta::pack(raw.data(), rows, stride, sizeof(T));
  std::vector<std::byte> back(raw.size(), std::byte{0x5a});
  xordelta::unpack(packed, back.data(), rows, stride, sizeof(T));
  EXPECT_EQ(back, raw) << rows << " rows of " << perRow << " scalars of " << sizeof(T) << " bytes";
  // At most a tag per scalar and the slack above the raw bytes.
  EXPECT_LE(packed.size(), raw.size() + (rows * perRow + 1) / 2 + 8);
}
} // namespace

TEST(XorDelta, RowsComeBackBitForBit) {
  std::mt19937_64 rng(3);
  std::vector<double> special = {0.0,
                                 -0.0,
                                 std::numeric_limits<double>::denorm_min(),
                                 -std::numeric_limits<double>::infinity(),
                                 std::numeric_limits<double>::quiet_NaN(),
                                 std::numeric_limits<double>::max(),
                                 1.0,
                                 1.0 + 1e-16,
                                 -1e-300};
  std::uint64_t payloadNaN = 0x7ff0000000000abcULL;
  double weird;
  std::memcpy(&weird, &payloadNaN, sizeof(double));
  special.push_back(weird);
  std::vector<double> random(999);
  for (auto& v : random) {
    const std::uint64_t bits = rng();
    std::memcpy(&v, &bits, sizeof(double));
  }
  for (std::size_t perRow : {1, 3, 9}) {
    roundTrip(special, 1);
    std::vector<double> r(random.begin(), random.begin() + 111 * perRow);
    roundTrip(r, perRow);
  }
  std::vector<std::int32_t> ints = {0, -1, 7, 7, std::numeric_limits<std::int32_t>::min(), 65536};
  for (int k = 0; k < 300; ++k) ints.push_back(static_cast<std::int32_t>(rng()));
  roundTrip(ints, 1);
  roundTrip(ints, 2);
  std::vector<std::uint64_t> ids(1000);
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = 1000000 + 3 * i;
  roundTrip(ids, 1);
  roundTrip(std::vector<double>{}, 3);               // no row
  roundTrip(std::vector<double>{2.5, -3.0, 4.0}, 3); // one row: nothing before it
}

// A smooth field in curve order packs: positions of a lattice row by row keep their leading
// bytes (about 0.6 of the raw bytes here); ids counting up keep one byte of eight.
TEST(XorDelta, SmoothRowsPack) {
  std::vector<double> x;
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 20; ++i) x.insert(x.end(), {0.01 * i + 0.3, 0.01 * j - 0.2, 0.01 * k});
  const auto raw = bytesOf(x);
  const auto packed = xordelta::pack(raw.data(), 8000, 24, 8);
  EXPECT_LT(packed.size(), 0.75 * static_cast<double>(raw.size()));
  std::vector<std::uint64_t> ids(8000);
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = i;
  const auto rawIds = bytesOf(ids);
  // (Tags: half a byte; kept bytes: one where the XOR of consecutive ids is below 256.)
  EXPECT_LT(xordelta::pack(rawIds.data(), 8000, 8, 8).size(), 0.2 * 8.0 * 8000.0);
}

TEST(XorDelta, DamagedDataIsRefused) {
  const std::vector<double> v = {1.0, 2.0, 3.0, 4.0};
  const auto raw = bytesOf(v);
  auto packed = xordelta::pack(raw.data(), 4, 8, 8);
  std::vector<std::byte> back(raw.size());
  EXPECT_THROW(xordelta::unpack(std::span<const std::byte>(packed).first(3), back.data(), 4, 8, 8),
               std::invalid_argument);
  packed[0] = std::byte{0xff}; // a tag past 8 bytes
  EXPECT_THROW(xordelta::unpack(packed, back.data(), 4, 8, 8), std::invalid_argument);
  EXPECT_THROW(xordelta::pack(raw.data(), 4, 8, 3), std::invalid_argument);
}
