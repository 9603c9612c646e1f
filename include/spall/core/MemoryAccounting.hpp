#pragma once
// A run's memory by part (summary.json's "memory_parts", tools/bench's table): the bytes that
// containers hold allocated (their capacity, not their size), added up where they live.
#include <cstddef>
#include <string>

namespace spall {

template <class... V> std::size_t allocatedBytes(const V&... v) {
  return (std::size_t{0} + ... + (v.capacity() * sizeof(typename V::value_type)));
}

// v.resize(n) growing by an eighth when it must grow, not by a factor of two (libstdc++ doubles the
// capacity: per-row scratch that grows by a few ghost rows would hold twice its rows).
template <class V> void resizeWithHeadroom(V& v, std::size_t n) {
  if (n > v.capacity()) v.reserve(n + n / 8);
  v.resize(n);
}

struct MemoryPart {
  std::string name;
  std::size_t bytes = 0;
};

} // namespace spall
