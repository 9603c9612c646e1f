// `--set KEY=VALUE`: applied to the parsed table before validation, so an overridden value is
// checked exactly like one written in the deck. Values are parsed with "--set KEY=VALUE" as their
// TOML source path, which is how later errors point at the override instead of a deck line.
#include "DeckDetail.hpp"

#include <cctype>
#include <cstdio>
#include <stdexcept>

namespace spall::io::deck_detail {

namespace {

std::string trim(std::string_view s) {
  const auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  while (!s.empty() && space(s.front())) s.remove_prefix(1);
  while (!s.empty() && space(s.back())) s.remove_suffix(1);
  return std::string(s);
}

std::vector<std::string> split(const std::string& key) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (;;) {
    const std::size_t dot = key.find('.', start);
    parts.push_back(trim(std::string_view(key).substr(start, dot - start)));
    if (dot == std::string::npos) return parts;
    start = dot + 1;
  }
}

// A TOML basic string holding `s` verbatim.
std::string quoteToml(std::string_view s) {
  std::string q = "\"";
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      q += '\\';
      q += c;
    } else if (u < 0x20 || u == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", u);
      q += buf;
    } else {
      q += c;
    }
  }
  return q + "\"";
}

// `v = VALUE` parsed with the override as its source path; a document holding only `v`.
std::optional<toml::table> parseAsValue(const std::string& text, const std::string& label) {
  try {
    toml::table doc = toml::parse(std::string_view(text), std::string_view(label));
    if (doc.size() == 1 && doc.contains("v")) return doc;
  } catch (const toml::parse_error&) {
  }
  return std::nullopt;
}

// VALUE as TOML, or else as a bare string (`--set solver.method=asph`).
toml::table parseValue(const std::string& raw, const std::string& label) {
  if (auto doc = parseAsValue("v = " + raw, label)) return std::move(*doc);
  if (auto doc = parseAsValue("v = " + quoteToml(raw), label)) return std::move(*doc);
  throw DeckError({label, 0, 0}, "the value is neither TOML nor valid UTF-8 text");
}

// The [[kind]] entry `selector` names, by `name` or else by 1-based index, and its index.
std::pair<toml::table*, std::size_t> findEntry(toml::table& parent, const std::string& kind,
                                               const std::string& selector,
                                               const std::string& label,
                                               const std::string& deckPath) {
  const SourceLocation here{label, 0, 0};
  toml::array* entries = parent.get_as<toml::array>(kind);
  if (!entries || entries->empty())
    throw DeckError(here,
                    "the deck has no [[" + kind + "]] entries to address as '" + selector + "'");
  std::vector<std::string> names;
  for (std::size_t i = 0; i < entries->size(); ++i) {
    toml::node& e = *entries->get(i);
    toml::table* t = e.as_table();
    if (!t)
      throw DeckError(locate(e.source(), deckPath), "'" + kind +
                                                        "' must be an array of tables ([[" + kind +
                                                        "]]), got an array "
                                                        "holding a " +
                                                        typeName(e));
    if (const auto* n = t->get_as<std::string>("name")) {
      if (n->get() == selector) return {t, i};
      names.push_back(n->get());
    }
  }
  const bool digits =
      !selector.empty() && selector.find_first_not_of("0123456789") == std::string::npos;
  if (digits && selector.size() < 6) {
    const std::size_t index = std::stoul(selector);
    if (index >= 1 && index <= entries->size())
      return {entries->get(index - 1)->as_table(), index - 1};
  }
  Names candidates(names.begin(), names.end());
  std::string m = "no " + kind + " named '" + selector + "'" + didYouMean(selector, candidates);
  m += isNamedArray(kind) ? " (" + kind + " names: " + joined(candidates) + ")"
                          : " (address [[" + kind + "]] entries by index, 1 to " +
                                std::to_string(entries->size()) + ")";
  throw DeckError(here, m);
}

void applyOne(toml::table& root, const std::string& text, const std::string& deckPath) {
  const std::string label = "--set " + text;
  const SourceLocation here{label, 0, 0};
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos) throw DeckError(here, "expected --set KEY=VALUE");
  const std::string key = trim(std::string_view(text).substr(0, eq));
  const std::vector<std::string> segments = split(key);
  for (const auto& s : segments)
    if (s.empty())
      throw DeckError(here, "'" + key + "' is not a dotted key path such as run.end_time");

  toml::table* table = &root;
  std::string schemaPath;
  Context context;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const std::string& segment = segments[i];
    const Names& known = *schemaKeys(schemaPath);
    if (!contains(known, segment))
      throw DeckError(here, unknownKeyMessage(segment, context, known));
    const std::string childPath = schemaPath.empty() ? segment : schemaPath + "." + segment;
    const std::string dotted = context.dotted.empty() ? segment : context.dotted + "." + segment;

    if (isArrayOfTables(childPath)) {
      if (i + 2 >= segments.size())
        throw DeckError(here, "'" + key + "' must name a key of one [[" + segment +
                                  "]] entry, as " + segment + "." +
                                  (isNamedArray(childPath) ? "NAME" : "INDEX") + ".KEY");
      const auto [entry, index] = findEntry(*table, segment, segments[++i], label, deckPath);
      table = entry;
      context = Context::entry(segment, *table, index);
      schemaPath = childPath;
      continue;
    }
    if (i + 1 == segments.size()) {
      toml::table doc = parseValue(trim(std::string_view(text).substr(eq + 1)), label);
      table->insert_or_assign(segment, std::move(*doc.get("v")));
      return;
    }
    if (!schemaKeys(childPath)) throw DeckError(here, "'" + dotted + "' is a value, not a table");
    toml::node* node = table->get(segment);
    if (!node) {
      // A missing optional table: create it, positioned at this override.
      toml::table doc = parseValue("{}", label);
      node = &table->insert_or_assign(segment, std::move(*doc.get("v"))).first->second;
    }
    table = node->as_table();
    if (!table)
      throw DeckError(locate(node->source(), deckPath),
                      "'" + dotted + "' must be a table, got " + typeName(*node));
    context = context.child(segment);
    schemaPath = childPath;
  }
}

} // namespace

void writeDefaults(toml::table& root, const std::vector<AppliedDefault>& defaults) {
  for (const auto& d : defaults) {
    toml::table* t = &root;
    for (const auto& step : d.table) {
      if (step.index) {
        toml::array* a = t->get_as<toml::array>(step.key);
        t = a && *step.index < a->size() ? a->get(*step.index)->as_table() : nullptr;
      } else {
        toml::node* n = t->get(step.key);
        t = n ? n->as_table()
              : t->insert_or_assign(step.key, toml::table{}).first->second.as_table();
      }
      if (!t) throw std::logic_error("internal: a default's table is not in the deck");
    }
    toml::table doc = parseValue(d.toml, "default of " + d.key);
    t->insert_or_assign(d.key, std::move(*doc.get("v")));
  }
}

void applyOverrides(toml::table& root, const std::vector<std::string>& overrides,
                    const std::string& deckPath) {
  for (const auto& text : overrides) applyOne(root, text, deckPath);
}

} // namespace spall::io::deck_detail
