#pragma once
// The owned rows a pass computes: all of them, or (time bins: methods/TimeBins.hpp) the listed
// ones, in increasing order; the other rows keep what they hold. The k-th is rows[k].
#include <cstddef>
#include <cstdint>
#include <vector>

namespace spall {

struct EvaluatedRows {
  std::size_t owned = 0;
  const std::vector<std::uint32_t>* list = nullptr; // nullptr: every owned row
  std::size_t size() const { return list ? list->size() : owned; }
  std::size_t operator[](std::size_t k) const { return list ? (*list)[k] : k; }
};

} // namespace spall
