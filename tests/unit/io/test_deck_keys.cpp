// The key tables (io/DeckKeys.hpp) are the deck reader's allow-list and the user's reference:
// they must form one tree of tables, with every key described once, and the typed tables' `type`
// lists must name exactly the types that have sections.
#include "spall/io/Deck.hpp"
#include "spall/io/DeckKeys.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>

namespace {

using spall::io::deckKeySections;
using spall::io::KeySection;
using spall::io::KeySpec;

const KeySpec* findKey(std::string_view path, std::string_view name) {
  for (const auto& s : deckKeySections())
    if (s.path == path)
      for (const auto& k : s.keys)
        if (k.name == name) return &k;
  return nullptr;
}

TEST(DeckKeys, EveryKeyIsDescribedOncePerSection) {
  for (const auto& s : deckKeySections()) {
    std::set<std::string_view> seen;
    for (const auto& k : s.keys) {
      const std::string where = std::string(s.path) + "." + std::string(k.name) +
                                (s.type.empty() ? "" : " [" + std::string(s.type) + "]");
      EXPECT_TRUE(seen.insert(k.name).second) << where << " twice";
      EXPECT_FALSE(k.type.empty()) << where << ": no type";
      EXPECT_FALSE(k.fallback.empty()) << where << ": no default (or required / none)";
      EXPECT_FALSE(k.meaning.empty()) << where << ": no meaning";
      EXPECT_LE(k.meaning.size(), 160u) << where << ": a meaning is one line";
    }
  }
}

TEST(DeckKeys, EverySectionIsATableKeyOfItsParent) {
  for (const auto& s : deckKeySections()) {
    if (s.path.empty()) continue;
    const auto dot = s.path.rfind('.');
    const std::string_view parent = dot == std::string_view::npos ? "" : s.path.substr(0, dot);
    const std::string_view name = dot == std::string_view::npos ? s.path : s.path.substr(dot + 1);
    const KeySpec* k = findKey(parent, name);
    ASSERT_NE(k, nullptr) << s.path << " is not a key of '" << parent << "'";
    EXPECT_TRUE(k->type == "table" || k->type == "[[table]]")
        << s.path << " is a section but its key's type is '" << k->type << "'";
  }
}

TEST(DeckKeys, TypedTablesListTheirTypes) {
  std::map<std::string_view, std::string> types; // path -> "a, b, c" from the sections
  for (const auto& s : deckKeySections()) {
    if (s.type.empty()) continue;
    auto& list = types[s.path];
    list += (list.empty() ? "" : ", ") + std::string(s.type);
    for (const auto& k : s.keys) EXPECT_NE(k.name, "type") << s.path << " [" << s.type << "]";
  }
  ASSERT_EQ(types.size(), 6u); // eos, strength, damage, porosity, body.shape, boundary
  for (const auto& [path, list] : types) {
    const KeySpec* type = findKey(path, "type");
    ASSERT_NE(type, nullptr) << path << " has types but no 'type' key";
    EXPECT_EQ(type->type, "one of: " + list) << path;
  }
}

// "one of: a, b, c" from an enum's names (`skip`: a name that is no deck value, e.g. damage's
// "none", which a deck writes by leaving the table out).
template <class E, std::size_t N>
std::string oneOf(const spall::NameTable<E, N>& names, std::string_view skip = {}) {
  std::string s = "one of: ";
  bool first = true;
  for (auto n : names.names()) {
    if (n == skip) continue;
    s += (first ? "" : ", ") + std::string(n);
    first = false;
  }
  return s;
}

// The reader turns each name into an enum through the enum's own table: the key tables and the
// enum tables must list the same names, in the same order.
TEST(DeckKeys, ChoicesAreTheEnumsNames) {
  const std::map<std::string, std::string> want{
      {"material.erosion", oneOf(spall::materials::kErosionNames)},
      {"body.shape.type", oneOf(spall::kShapeNames)},
      {"body.lattice", oneOf(spall::kLatticeNames)},
      {"boundary.type", oneOf(spall::kBoundaryTypeNames)},
      {"probe.track", oneOf(spall::kProbeTrackNames)},
      {"decomposition.curve", oneOf(spall::kCurveNames)},
      {"decomposition.partitioner", oneOf(spall::kPartitionerNames)},
      {"solver.method", oneOf(spall::kSolverMethodNames)},
      {"solver.kernel", oneOf(spall::kKernelNames)},
      {"solver.density", oneOf(spall::kDensityNames)},
      {"solver.stress_form", oneOf(spall::kStressFormNames)},
      {"solver.velocity_gradient", oneOf(spall::kVelocityGradientNames)},
      {"solver.contact", oneOf(spall::kContactNames)},
      {"solver.mpm.shape", oneOf(spall::kMpmShapeNames)},
      {"solver.mpm.transfer", oneOf(spall::kMpmTransferNames)},
  };
  std::map<std::string, std::string> got;
  for (const auto& s : deckKeySections())
    for (const auto& k : s.keys) {
      const std::string path = std::string(s.path) + "." + std::string(k.name);
      if (want.count(path)) got[path] = std::string(k.type);
    }
  for (const auto& [path, type] : want) EXPECT_EQ(got[path], type) << path;
  // The material models' types and choices (eos, strength, damage, porosity) are not enums:
  // their key functions (src/io/keys/) both list and read them.
  EXPECT_EQ(got.count("material.strength.type"), 0u);
}

} // namespace
