#include "DeckDetail.hpp"

#include "spall/io/DeckKeys.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fmt/format.h>
#include <limits>
#include <map>

namespace spall::io::deck_detail {

namespace {

struct TypedTable {
  std::string_view path; // schema path of the table
  std::vector<std::pair<std::string_view, Names>> types;
};

// The typed tables' types and their keys, from the key tables (io/DeckKeys.hpp): a section with a
// type holds that type's keys.
const std::vector<TypedTable>& typedTables() {
  static const std::vector<TypedTable> tables = [] {
    std::vector<TypedTable> t;
    for (const auto& section : deckKeySections()) {
      if (section.type.empty()) continue;
      auto it =
          std::find_if(t.begin(), t.end(), [&](const auto& x) { return x.path == section.path; });
      if (it == t.end()) it = t.insert(t.end(), TypedTable{section.path, {}});
      Names params;
      for (const auto& key : section.keys) params.push_back(key.name);
      it->types.emplace_back(section.type, std::move(params));
    }
    return t;
  }();
  return tables;
}

const TypedTable* findTyped(std::string_view path) {
  for (const auto& t : typedTables())
    if (t.path == path) return &t;
  return nullptr;
}

// The allow-list by schema path, from the key tables: a typed table's keys are "type" (its own
// section) and the union of its types' keys, each once.
const std::map<std::string, Names, std::less<>>& schema() {
  static const std::map<std::string, Names, std::less<>> s = [] {
    std::map<std::string, Names, std::less<>> m;
    for (const auto& section : deckKeySections()) {
      Names& names = m[std::string(section.path)];
      for (const auto& key : section.keys)
        if (!contains(names, key.name)) names.push_back(key.name);
    }
    return m;
  }();
  return s;
}

std::size_t levenshtein(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// Plurals ("bodies", "materials") are a common slip for array-of-tables names.
std::size_t distance(std::string_view word, std::string_view candidate) {
  std::size_t d = levenshtein(word, candidate);
  d = std::min(d, levenshtein(word, std::string(candidate) + "s"));
  if (!candidate.empty() && candidate.back() == 'y') {
    std::string plural(candidate.substr(0, candidate.size() - 1));
    d = std::min(d, levenshtein(word, plural + "ies"));
  }
  return d;
}

// Unknown keys are reported in deck order; values from overrides (line 0) come first.
bool before(const SourceLocation& a, const SourceLocation& b) {
  if (a.line != b.line) return a.line < b.line;
  return a.column < b.column;
}

} // namespace

SourceLocation locate(const toml::source_region& source, const std::string& deckPath) {
  if (!source.path) return {deckPath, 0, 0};
  // An override's value ("--set KEY=VALUE") has no line of its own; another file (a material
  // library's) does.
  if (*source.path != deckPath)
    return source.path->starts_with("--set ")
               ? SourceLocation{*source.path, 0, 0}
               : SourceLocation{*source.path, static_cast<int>(source.begin.line),
                                static_cast<int>(source.begin.column)};
  return {deckPath, static_cast<int>(source.begin.line), static_cast<int>(source.begin.column)};
}

std::string typeName(const toml::node& node) {
  switch (node.type()) {
  case toml::node_type::table:
    return "table";
  case toml::node_type::array:
    return "array";
  case toml::node_type::string:
    return "string";
  case toml::node_type::integer:
    return "integer";
  case toml::node_type::floating_point:
    return "float";
  case toml::node_type::boolean:
    return "boolean";
  case toml::node_type::date:
    return "date";
  case toml::node_type::time:
    return "time";
  case toml::node_type::date_time:
    return "date-time";
  case toml::node_type::none:
    break;
  }
  return "nothing";
}

void resolutionWarnings(const Deck& deck, DeckNotes& notes) {
  constexpr double kFewest = 3.0; // a gradient needs a particle either side of one
  const bool rz = deck.run.geometry == Geometry::RZ;
  const auto* pen = deck.penetration ? &deck.penetration->penetrator : nullptr;
  for (const auto& b : deck.bodies) {
    const double dx = b.spacing / deck.run.resolution;
    const double across = thinnestWidth(b.shape) / dx;
    const bool penetrator = pen && std::find(pen->begin(), pen->end(), b.name) != pen->end();
    const double radial = penetrator ? penetratorRadius(b.shape, rz) / dx : across;
    if (across >= kFewest && radial >= kFewest) continue;
    const bool byRadius = radial < across;
    notes.warnings.push_back(
        {b.spacingWhere,
         fmt::format(
             "body '{}' is {} particles across its {} ({} m at spacing {} m with "
             "run.resolution {}): under 3 a gradient has no particle either side; a "
             "smaller spacing or a larger run.resolution",
             b.name, formatNumber(std::round((byRadius ? radial : across) * 100) / 100),
             byRadius ? "radius (a penetrator)" : "thinnest extent",
             formatNumber(byRadius ? penetratorRadius(b.shape, rz) : thinnestWidth(b.shape)),
             formatNumber(dx), formatNumber(deck.run.resolution))});
  }
}

void loadedBalsaraWarning(const Deck& deck, DeckNotes& notes) {
  const auto& av = deck.solver.artificial_viscosity;
  if (!av.balsara || deck.solver.method == SolverMethod::Mpm) return;
  for (const auto& b : deck.boundaries) {
    if (b.type != BoundaryType::Pressure) continue;
    // At rest under a load, |div v| and |curl v| are both noise, the switch halves the viscosity
    // and a disturbance grows faster than damping removes it (decks/topics/penetration.md, "The
    // pre-stress needs the full viscosity": a confined sandstone cylinder blew up at 51-113 us).
    notes.warnings.push_back(
        {av.balsaraWhere,
         fmt::format("'solver.artificial_viscosity.balsara' with the pressure boundary on body "
                     "'{}': the switch leaves a body loaded at rest unsettled (a confined "
                     "sandstone cylinder blew up within 113 us at 6.9-103 MPa, where the full "
                     "viscosity settles it within 0.5%); balsara = false",
                     b.body)});
    return;
  }
}

double norm(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return std::sqrt(s);
}

std::string formatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string joined(const Names& names) {
  std::string s;
  for (auto n : names) {
    if (!s.empty()) s += ", ";
    s += n;
  }
  return s;
}

bool contains(const Names& names, std::string_view name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::string didYouMean(std::string_view word, const Names& candidates) {
  std::string_view best;
  std::size_t bestDistance = std::string_view::npos;
  for (auto c : candidates) {
    const std::size_t d = distance(word, c);
    const std::size_t limit = std::max<std::size_t>(2, c.size() / 3);
    // A suggestion that shares no letter with the word is no suggestion ("x" -> "s").
    if (d <= limit && d < std::max(word.size(), c.size()) && d < bestDistance) {
      best = c;
      bestDistance = d;
    }
  }
  return best.empty() ? std::string() : " (did you mean '" + std::string(best) + "'?)";
}

namespace {
// A nested shape (a union's shapes, a difference's from and minus, at any depth) is a shape:
// its schema path is body.shape's.
constexpr std::string_view kShape = "body.shape";
std::string_view canonical(std::string_view path) {
  if (!path.starts_with(kShape) || path.size() == kShape.size() || path[kShape.size()] != '.')
    return path;
  for (std::string_view rest = path.substr(kShape.size() + 1); !rest.empty();) {
    const std::size_t dot = rest.find('.');
    if (!contains({"shapes", "from", "minus"}, rest.substr(0, dot))) return path;
    rest = dot == std::string_view::npos ? std::string_view{} : rest.substr(dot + 1);
  }
  return kShape;
}
} // namespace

const Names* schemaKeys(std::string_view schemaPath) {
  const auto& s = schema();
  const auto it = s.find(canonical(schemaPath));
  return it == s.end() ? nullptr : &it->second;
}

bool isArrayOfTables(std::string_view schemaPath) {
  if (schemaPath != kShape && canonical(schemaPath) == kShape)
    return schemaPath.ends_with(".shapes") || schemaPath.ends_with(".minus");
  return contains({"material", "body", "energy_source", "boundary", "probe", "jet"}, schemaPath);
}

bool isNamedArray(std::string_view schemaPath) {
  return contains({"material", "body", "probe", "jet"}, schemaPath);
}

const Names& typeNames(std::string_view schemaPath) {
  static const std::map<std::string, Names, std::less<>> names = [] {
    std::map<std::string, Names, std::less<>> m;
    for (const auto& t : typedTables())
      for (const auto& [type, params] : t.types) m[std::string(t.path)].push_back(type);
    return m;
  }();
  return names.find(schemaPath)->second;
}

const Names& typedKeys(std::string_view schemaPath, std::string_view type) {
  for (const auto& [name, params] : findTyped(schemaPath)->types)
    if (name == type) return params;
  static const Names none;
  return none;
}

Context Context::child(std::string_view key) const {
  std::vector<PathStep> p = path;
  p.push_back({std::string(key), std::nullopt});
  if (dotted.empty()) return {"[" + std::string(key) + "]", std::string(key), std::move(p)};
  return {"the " + std::string(key) + " of " + human, dotted + "." + std::string(key),
          std::move(p)};
}

Context Context::item(std::string_view key, std::size_t index) const {
  std::vector<PathStep> p = path;
  p.push_back({std::string(key), index});
  const std::string i = std::to_string(index + 1);
  return {"entry " + i + " of the " + std::string(key) + " of " + human,
          dotted + "." + std::string(key) + "." + i, std::move(p)};
}

Context Context::entry(std::string_view kind, const toml::table& table, std::size_t index) {
  const std::string k(kind);
  std::vector<PathStep> p{{k, index}};
  if (isNamedArray(kind)) {
    if (const auto* name = table.get_as<std::string>("name")) {
      const std::string& n = name->get();
      if (!n.empty() && n.find('.') == std::string::npos)
        return {k + " '" + n + "'", k + "." + n, std::move(p)};
    }
  }
  const std::string i = std::to_string(index + 1);
  return {k + " " + i, k + "." + i, std::move(p)};
}

std::string unknownKeyMessage(std::string_view key, const Context& context, const Names& known,
                              const std::string& hint) {
  std::string m = context.human.empty()
                      ? "unknown top-level key '" + std::string(key) + "'"
                      : "unknown key '" + std::string(key) + "' in " + context.human;
  const std::string suggestion = didYouMean(key, known);
  if (!suggestion.empty()) return m + suggestion;
  return hint.empty() ? m : m + " (" + hint + ")";
}

// ---- TableReader ----

SourceLocation TableReader::where() const {
  return locate(table_.source(), deckPath_);
}

SourceLocation TableReader::whereValue(std::string_view key) const {
  const toml::node* n = table_.get(key);
  return n ? whereNode(*n) : where();
}

SourceLocation TableReader::whereNode(const toml::node& node) const {
  return locate(node.source(), deckPath_);
}

void TableReader::noteDefault(std::string_view key, const std::string& toml) const {
  if (notes_) notes_->defaults.push_back({context_.path, std::string(key), toml});
}

void TableReader::warn(std::string_view key, const std::string& message) const {
  if (notes_) notes_->unitWarning({whereValue(key), message});
}

std::string TableReader::quoted(std::string_view key) const {
  return "'" + (context_.dotted.empty() ? std::string() : context_.dotted + ".") +
         std::string(key) + "'";
}

void TableReader::allowOnly(const Names& known, const std::string& hint) const {
  std::optional<std::string> first;
  SourceLocation firstAt;
  for (auto&& [k, v] : table_) {
    if (contains(known, k.str())) continue;
    // Keys inserted by an override carry no position of their own; their values do.
    const SourceLocation at = k.source().path ? locate(k.source(), deckPath_) : whereNode(v);
    if (!first || before(at, firstAt)) {
      first = std::string(k.str());
      firstAt = at;
    }
  }
  if (first) throw DeckError(firstAt, unknownKeyMessage(*first, context_, known, hint));
}

void TableReader::fail(std::string_view key, const std::string& message) const {
  throw DeckError(whereValue(key), message);
}

void TableReader::missing(std::string_view key) const {
  std::string m = "missing required key '" + std::string(key) + "'";
  if (!context_.human.empty()) m += " in " + context_.human;
  throw DeckError(where(), m);
}

void TableReader::check(bool ok, std::string_view key, std::string_view what, double got) const {
  if (!ok) fail(key, quoted(key) + " must be " + std::string(what) + ", got " + formatNumber(got));
}

double TableReader::numberFrom(const toml::node& node, std::string_view key,
                               bool allowInfinite) const {
  double v = 0.0;
  if (const auto* i = node.as_integer())
    v = static_cast<double>(i->get());
  else if (const auto* f = node.as_floating_point())
    v = f->get();
  else
    throw DeckError(whereNode(node), quoted(key) + " must be a number, got " + typeName(node));
  if (std::isnan(v) || (!allowInfinite && std::isinf(v)))
    throw DeckError(whereNode(node),
                    quoted(key) + " must be a finite number, got " + formatNumber(v));
  return v;
}

std::optional<double> TableReader::number(std::string_view key, bool allowInfinite) const {
  const toml::node* n = table_.get(key);
  if (!n) return std::nullopt;
  return numberFrom(*n, key, allowInfinite);
}

std::optional<std::int64_t> TableReader::integer(std::string_view key) const {
  const toml::node* n = table_.get(key);
  if (!n) return std::nullopt;
  if (const auto* i = n->as_integer()) return i->get();
  // 1e6 is a natural way to write a step count; accept floats that are whole numbers.
  if (const auto* f = n->as_floating_point()) {
    const double v = f->get();
    if (std::isfinite(v) && v == std::floor(v) && std::abs(v) < 9.0e18)
      return static_cast<std::int64_t>(v);
    fail(key, quoted(key) + " must be an integer, got " + formatNumber(v));
  }
  fail(key, quoted(key) + " must be an integer, got " + typeName(*n));
}

std::optional<std::string> TableReader::string(std::string_view key) const {
  const toml::node* n = table_.get(key);
  if (!n) return std::nullopt;
  if (const auto* s = n->as_string()) return s->get();
  fail(key, quoted(key) + " must be a string, got " + typeName(*n));
}

std::optional<bool> TableReader::boolean(std::string_view key) const {
  const toml::node* n = table_.get(key);
  if (!n) return std::nullopt;
  if (const auto* b = n->as_boolean()) return b->get();
  fail(key, quoted(key) + " must be a boolean (true or false), got " + typeName(*n));
}

std::optional<std::vector<double>> TableReader::vector(std::string_view key, std::size_t n) const {
  const toml::node* node = table_.get(key);
  if (!node) return std::nullopt;
  const toml::array* a = node->as_array();
  if (!a)
    fail(key, quoted(key) + " must be an array of " + std::to_string(n) + " numbers, got " +
                  typeName(*node));
  if (a->size() != n)
    fail(key, quoted(key) + " must have " + std::to_string(n) + (n == 1 ? " entry" : " entries") +
                  " (one per dimension; run.dimension is " + std::to_string(n) + "), got " +
                  std::to_string(a->size()));
  std::vector<double> v;
  for (const toml::node& e : *a) v.push_back(numberFrom(e, key, false));
  return v;
}

std::optional<std::vector<std::vector<double>>> TableReader::matrix(std::string_view key,
                                                                    std::size_t n) const {
  const toml::node* node = table_.get(key);
  if (!node) return std::nullopt;
  const std::string shape = std::to_string(n) + " x " + std::to_string(n);
  const toml::array* rows = node->as_array();
  if (!rows || rows->size() != n)
    fail(key, quoted(key) + " must be a " + shape + " array of arrays (run.dimension is " +
                  std::to_string(n) + ")");
  std::vector<std::vector<double>> m;
  for (const toml::node& row : *rows) {
    const toml::array* r = row.as_array();
    if (!r || r->size() != n)
      throw DeckError(whereNode(row), quoted(key) + " must be a " + shape +
                                          " array of arrays: each row needs " + std::to_string(n) +
                                          " numbers");
    std::vector<double> values;
    for (const toml::node& e : *r) values.push_back(numberFrom(e, key, false));
    m.push_back(std::move(values));
  }
  return m;
}

std::optional<std::vector<std::vector<double>>> TableReader::points(std::string_view key,
                                                                    std::size_t n) const {
  const toml::node* node = table_.get(key);
  if (!node) return std::nullopt;
  const std::string what = quoted(key) + " must be an array of points, each [" +
                           std::string(n == 2 ? "x, y" : "x, y, z") + "]";
  const toml::array* rows = node->as_array();
  if (!rows) fail(key, what + ", got " + typeName(*node));
  std::vector<std::vector<double>> m;
  for (const toml::node& row : *rows) {
    const toml::array* r = row.as_array();
    if (!r || r->size() != n)
      throw DeckError(whereNode(row), what + ": each needs " + std::to_string(n) + " numbers");
    std::vector<double> values;
    for (const toml::node& e : *r) values.push_back(numberFrom(e, key, false));
    m.push_back(std::move(values));
  }
  return m;
}

namespace {

// An array of one TOML type ("strings", "integers"): get(node) is the entry's value, or nullptr.
template <class T, class Get>
std::optional<std::vector<T>> arrayOf(const TableReader& r, std::string_view key,
                                      const std::string& what, Get get) {
  const toml::node* node = r.table().get(key);
  if (!node) return std::nullopt;
  const toml::array* a = node->as_array();
  if (!a) r.fail(key, r.quoted(key) + " must be an array of " + what + ", got " + typeName(*node));
  std::vector<T> v;
  for (const toml::node& e : *a) {
    const auto* value = get(e);
    if (!value)
      throw DeckError(r.whereNode(e),
                      r.quoted(key) + " entries must be " + what + ", got " + typeName(e));
    v.push_back(value->get());
  }
  return v;
}

} // namespace

std::optional<std::vector<std::string>> TableReader::strings(std::string_view key) const {
  return arrayOf<std::string>(*this, key, "strings",
                              [](const toml::node& e) { return e.as_string(); });
}

std::optional<std::vector<std::int64_t>> TableReader::integers(std::string_view key) const {
  return arrayOf<std::int64_t>(*this, key, "integers",
                               [](const toml::node& e) { return e.as_integer(); });
}

const toml::table* TableReader::subtable(std::string_view key) const {
  const toml::node* n = table_.get(key);
  if (!n) return nullptr;
  if (const auto* t = n->as_table()) return t;
  fail(key, quoted(key) + " must be a table, got " + typeName(*n));
}

std::vector<const toml::table*> TableReader::tables(std::string_view key) const {
  const toml::node* n = table_.get(key);
  if (!n) return {};
  const std::string expected =
      quoted(key) + " must be an array of tables ([[" + std::string(key) + "]]), got ";
  const toml::array* a = n->as_array();
  if (!a) fail(key, expected + typeName(*n));
  std::vector<const toml::table*> out;
  for (const toml::node& e : *a) {
    const auto* t = e.as_table();
    if (!t) throw DeckError(whereNode(e), expected + "an array holding a " + typeName(e));
    out.push_back(t);
  }
  return out;
}

std::string TableReader::choice(std::string_view key, const Names& allowed,
                                std::optional<std::string_view> fallback) const {
  const auto s = string(key);
  if (!s) {
    if (!fallback) missing(key);
    return std::string(*fallback);
  }
  if (!contains(allowed, *s))
    fail(key, quoted(key) + " must be one of " + joined(allowed) + ", got '" + *s + "'" +
                  didYouMean(*s, allowed));
  return *s;
}

void allowTypedKeys(const TableReader& r, std::string_view path, const std::string& type,
                    const std::string& noun) {
  const Names& params = typedKeys(path, type);
  Names keys{"type"};
  keys.insert(keys.end(), params.begin(), params.end());
  r.allowOnly(keys, noun + " '" + type + "' takes: " +
                        (params.empty() ? std::string("nothing else") : joined(params)));
}

int materialIndex(const TableReader& r, const std::string& name,
                  const std::vector<MaterialConfig>& materials) {
  Names known;
  for (std::size_t i = 0; i < materials.size(); ++i) {
    if (materials[i].name == name) return static_cast<int>(i);
    known.push_back(materials[i].name);
  }
  r.fail("material", r.quoted("material") + " names no [[material]]: '" + name + "'" +
                         didYouMean(name, known) + " (materials: " + joined(known) + ")");
}

} // namespace spall::io::deck_detail
