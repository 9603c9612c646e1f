#pragma once
// Every key a deck may hold, one table per section or model: its name, type, default, unit,
// bounds and meaning. The deck reader's allow-list is made from these tables (an unknown key is
// an error), `spall keys` prints them, and decks/keys.md is `spall keys --markdown`.
//
// A section is a TOML table by its schema path: "run", "solver.artificial_viscosity", "body",
// "body.shape". An array of tables ([[material]], [[body]], ...) has one section for all its
// entries; a typed table (material.eos, material.strength, material.damage, material.porosity,
// body.shape, boundary) has one section per type, which lists the keys of that type beside
// "type" itself.
#include <string>
#include <string_view>
#include <vector>

namespace spall::io {

struct KeySpec {
  std::string_view name;
  // As a deck writes the value: "float", "integer", "boolean", "string", "one of: a, b",
  // "float[dim]" (one per dimension), "float[n]", "table", "[[table]]", "strings", ...
  std::string type;
  // The value used when the key is absent, as a deck would write it; "required" when it must be
  // given; "none" when absence means the feature is off; prose for a derived value.
  std::string fallback;
  std::string_view unit; // SI; "" for a number without dimension or a non-number
  std::string bounds;    // what the reader accepts: "> 0", "[0, 1]", ""
  std::string_view meaning;
};

struct KeySection {
  std::string_view path; // schema path
  std::string_view type; // the type of a typed table this section is for; "" for others
  std::string_view meaning;
  std::vector<KeySpec> keys;
};

// All sections, in the order a reference reads them (top level, run, solver..., material...,
// body..., boundary, output, ...).
const std::vector<KeySection>& deckKeySections();

// The types of a typed table ("material.eos", "body.shape", "boundary"), in table order.
std::vector<std::string_view> deckTypeNames(std::string_view path);

// One line per key whose dotted path (as a deck writes it: "solver.cfl", "material.strength.A")
// begins with `prefix`, the path first; `markdown` gives the page decks/keys.md instead (all keys).
std::string formatDeckKeys(bool markdown, std::string_view prefix = {});

// The tables by section or model (src/io/keys/); deckKeySections() joins them.
namespace keys {
std::vector<KeySection> topLevel();   // the top level, [run], [decomposition]
std::vector<KeySection> solver();     // [solver] and its sub-tables
std::vector<KeySection> eos();        // material.eos, one per type
std::vector<KeySection> strength();   // material.strength, one per type
std::vector<KeySection> damage();     // material.damage, one per type
std::vector<KeySection> porosity();   // material.porosity, one per type
std::vector<KeySection> material();   // [[material]] itself
std::vector<KeySection> body();       // [[body]], its shapes and velocity fields, [[jet]]
std::vector<KeySection> boundaries(); // [[boundary]] by type, [[energy_source]]
std::vector<KeySection> output();     // [output], [checkpoint], [[probe]], [fragments],
                                      // [penetration], [damping]
} // namespace keys

} // namespace spall::io
