#pragma once
// An enum's names as decks and outputs write them, in one table: the deck reader parses with it
// and summaries print with it, so the two cannot drift.
#include <array>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace spall {

template <class E, std::size_t N> struct NameTable {
  std::array<std::pair<E, std::string_view>, N> entries;

  constexpr std::string_view operator()(E value) const {
    for (const auto& [v, name] : entries)
      if (v == value) return name;
    return "?"; // a value the table lacks: each table lists its enum whole, beside it
  }
  constexpr std::optional<E> find(std::string_view name) const {
    for (const auto& [v, n] : entries)
      if (n == name) return v;
    return std::nullopt;
  }
  // The value of a name the deck reader has already checked against names().
  E at(std::string_view name) const {
    if (const auto v = find(name)) return *v;
    throw std::logic_error("internal: '" + std::string(name) + "' is not a known name");
  }
  std::vector<std::string_view> names() const {
    std::vector<std::string_view> out;
    for (const auto& e : entries) out.push_back(e.second);
    return out;
  }
};

} // namespace spall
