#pragma once
// Private to the deck reader (Deck.cpp, DeckOverrides.cpp, DeckDetail.cpp): positions of nodes,
// typed access that reports FILE:LINE:COLUMN, the schema of known keys, did-you-mean suggestions.
#include "spall/core/Error.hpp"
#include "spall/core/NameTable.hpp"
#include "spall/io/Deck.hpp"
#include "spall/solvers/Config.hpp"

#include <toml++/toml.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace spall::io::deck_detail {

using Names = std::vector<std::string_view>;

// The node's position in the deck. Overrides are parsed with "--set KEY=VALUE" as their source
// path, so a value that came from one reports that string, with line 0.
SourceLocation locate(const toml::source_region& source, const std::string& deckPath);

std::string typeName(const toml::node& node); // "string", "float", "table", ...
std::string formatNumber(double v);
std::string joined(const Names& names); // "a, b, c"
bool contains(const Names& names, std::string_view name);

// " (did you mean 'x'?)" for the closest candidate within about a third of its length, else "".
std::string didYouMean(std::string_view word, const Names& candidates);

// Keys of each schema table, by schema path: "" (top level), "run", "solver.artificial_viscosity",
// "body", "body.shape", ... Sub-tables appear as keys of their parent and have their own entry;
// nullptr for a path that is not a table. Typed tables (eos, shape, boundary) hold the union over
// their types; typedKeys() narrows that to one type.
const Names* schemaKeys(std::string_view schemaPath);
bool isArrayOfTables(
    std::string_view schemaPath); // material, body, energy_source, boundary, probe, jet
bool isNamedArray(
    std::string_view schemaPath); // entries addressed by `name`: material, body, probe
// The type names of a typed table ("material.eos", "body.shape", "boundary") and the parameter
// keys of one of its types (without "type").
const Names& typeNames(std::string_view schemaPath);
const Names& typedKeys(std::string_view schemaPath, std::string_view type);

// How a table is named in messages: for people, and as the dotted path `--set` addresses it by.
// One step from the deck's root to a table: a key, and for an [[array]] entry its index.
struct PathStep {
  std::string key;
  std::optional<std::size_t> index;
};

struct Context {
  std::string human;  // "[run]", "body 'striker'", "the shape of body 'striker'"; "" at top level
  std::string dotted; // "run", "body.striker", "body.striker.shape"; "" at top level
  std::vector<PathStep> path; // the same table, for the program (names may hold any character)
  Context child(std::string_view key) const;
  // The `index`th (0-based) table of the array `key` in this one: "shape 2 of the shape of body
  // 'rod'", "body.rod.shape.shapes.2".
  Context item(std::string_view key, std::size_t index) const;
  // One [[kind]] entry: by its name where the kind has names (and this one a usable name), else
  // by its 1-based index ("boundary 2", "boundary.2").
  static Context entry(std::string_view kind, const toml::table& table, std::size_t index);
};

std::string unknownKeyMessage(std::string_view key, const Context& context, const Names& known,
                              const std::string& hint = {});

// TOML text with each float written in the fewest digits that read back as the same double
// (toml++ prints 17: "6.9999999999999994e-05" becomes "7e-05"). Strings, comments and keys are
// left as they are.
std::string shortestFloats(std::string_view text);

// Applies `--set KEY=VALUE` overrides in order (see Deck.hpp); throws DeckError.
void applyOverrides(toml::table& root, const std::vector<std::string>& overrides,
                    const std::string& deckPath);

// What reading a deck finds besides its values, collected across its tables: the defaults it
// applied to keys the deck leaves out (as `--set` takes them, "solver.cfl=0.25": the deck as run
// writes them explicitly) and its plausibility warnings.
struct AppliedDefault {
  std::vector<PathStep> table;
  std::string key, toml; // toml: the value as TOML text ("0.25", "\"auto\"")
};
struct DeckNotes {
  std::vector<AppliedDefault> defaults;
  std::vector<DeckWarning> warnings;
  bool si = true; // run.units: the bounds of SI values apply
  // A warning of a value a unit slip would give: none for a scaled deck.
  void unitWarning(DeckWarning w) {
    if (si) warnings.push_back(std::move(w));
  }
};

// Writes the defaults the reader applied into the deck's tables (creating a table the deck left
// out, such as [solver]), so that the deck as run states them.
void writeDefaults(toml::table& root, const std::vector<AppliedDefault>& defaults);

// Typed, checked reads from one table. Every failure is a DeckError at the offending value, or at
// the table itself for a missing key.
class TableReader {
public:
  TableReader(const toml::table& table, Context context, const std::string& deckPath,
              DeckNotes* notes = nullptr)
      : table_(table), context_(std::move(context)), deckPath_(deckPath), notes_(notes) {}

  const toml::table& table() const { return table_; }
  const Context& context() const { return context_; }
  const std::string& deckPath() const { return deckPath_; }
  DeckNotes* notes() const { return notes_; }
  // A default applied to the absent `key`, `toml` its value as TOML ("0.25", "\"auto\"").
  void noteDefault(std::string_view key, const std::string& toml) const;
  // A value the deck as run states resolved (`toml`): a file's absolute path.
  void noteResolved(std::string_view key, const std::string& toml) const { noteDefault(key, toml); }

  // A plausibility warning of a value a unit slip would give, at the key's value (or the table,
  // if absent); none in a scaled deck.
  void warn(std::string_view key, const std::string& message) const;
  SourceLocation where() const;                          // the table's own position
  SourceLocation whereValue(std::string_view key) const; // the value's, or the table's if absent
  SourceLocation whereNode(const toml::node& node) const;
  bool has(std::string_view key) const { return table_.contains(key); }
  std::string quoted(std::string_view key) const; // "'body.striker.spacing'"

  // Throws at the first key (in deck order) that `known` does not hold.
  void allowOnly(const Names& known, const std::string& hint = {}) const;

  [[noreturn]] void fail(std::string_view key, const std::string& message) const;
  [[noreturn]] void missing(std::string_view key) const;
  // `what` completes "'KEY' must be ...", e.g. "> 0".
  void check(bool ok, std::string_view key, std::string_view what, double got) const;

  // Absent keys give nullopt (or nullptr / empty); present ones must have the right type.
  std::optional<double> number(std::string_view key, bool allowInfinite = false) const;
  std::optional<std::int64_t> integer(std::string_view key) const;
  std::optional<std::string> string(std::string_view key) const;
  std::optional<bool> boolean(std::string_view key) const;
  std::optional<std::vector<double>> vector(std::string_view key, std::size_t n) const;
  std::optional<std::vector<std::vector<double>>> matrix(std::string_view key,
                                                         std::size_t n) const; // n x n
  // Any number of points of n coordinates each: [[x, y], ...].
  std::optional<std::vector<std::vector<double>>> points(std::string_view key, std::size_t n) const;
  std::optional<std::vector<std::string>> strings(std::string_view key) const;
  std::optional<std::vector<std::int64_t>> integers(std::string_view key) const;
  const toml::table* subtable(std::string_view key) const;
  std::vector<const toml::table*> tables(std::string_view key) const; // [[key]]
  // A string from `allowed`; `fallback` when absent (or a missing-key error without one).
  std::string choice(std::string_view key, const Names& allowed,
                     std::optional<std::string_view> fallback) const;
  // The same for an enum, by the names of its table.
  template <class E, std::size_t N>
  E choice(std::string_view key, const NameTable<E, N>& names,
           std::optional<std::type_identity_t<E>> fallback) const {
    return names.at(
        choice(key, names.names(),
               fallback ? std::optional<std::string_view>(names(*fallback)) : std::nullopt));
  }

  template <class T> T required(std::optional<T> value, std::string_view key) const {
    if (!value) missing(key);
    return *value;
  }

private:
  double numberFrom(const toml::node& node, std::string_view key, bool allowInfinite) const;

  const toml::table& table_;
  Context context_;
  const std::string& deckPath_;
  DeckNotes* notes_;
};

// The index of the [[material]] named by the table's 'material' key (else a DeckError there).
int materialIndex(const TableReader& r, const std::string& name,
                  const std::vector<MaterialConfig>& materials);

// What MPM does not take yet (DeckSolver.cpp).
void checkMpmScope(const Deck& deck);
// One [[material]] table (DeckMaterial.cpp).
void readMaterial(const TableReader& r, MaterialConfig& m);

// [[jet]] (DeckJet.cpp): a jet's `file` read into its table as `segments` (rows [segment, radius,
// length, velocity, insert_time]) before the deck is resolved, so that deck.toml and checkpoints
// carry the segments themselves; then each segment made a body named NAME_segmentK.
void inlineJetFiles(toml::table& root, const std::string& deckPath);
// Merges each [[material]]'s `library` file into it (the deck's keys win) and drops the key;
// returns "NAME (FILE)" for each one used. Throws DeckError at the name or in the file.
std::vector<std::string> inlineMaterialLibrary(toml::table& root, const std::string& deckPath);
void readJet(const TableReader& r, std::size_t dimension, bool rz,
             const std::vector<MaterialConfig>& materials, std::vector<BodyConfig>& bodies,
             const std::string& name);

// The Euclidean length of a vector value.
double norm(const std::vector<double>& v);

// Plausibility of the deck's resolution (docs/reference.md, "Warnings"): fewer than 3 particles
// across a body's thinnest extent or a penetrator's radius.
void resolutionWarnings(const Deck& deck, DeckNotes& notes);
// Balsara's switch on a deck that loads a body with a pressure boundary (and settles it).
void loadedBalsaraWarning(const Deck& deck, DeckNotes& notes);

// A [[boundary]] type = "pressure"'s `pressure` table (DeckPressureTable.cpp): (time s, Pa) rows,
// times rising from >= 0.
std::vector<std::pair<double, double>> readPressureTable(const TableReader& r);

// A typed table ({type = ..., ...}) takes "type" and the keys of its type (schema above).
void allowTypedKeys(const TableReader& r, std::string_view path, const std::string& type,
                    const std::string& noun);

// A typed table's `type` (one of the types its key tables list, required), its keys checked
// against that type's; the value the enum's table gives the name.
template <class E, std::size_t N>
E readType(const TableReader& r, std::string_view path, const NameTable<E, N>& names,
           const std::string& noun) {
  const std::string type = r.choice("type", typeNames(path), std::nullopt);
  allowTypedKeys(r, path, type, noun);
  return names.at(type);
}

} // namespace spall::io::deck_detail
