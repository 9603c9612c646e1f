// Which keys of two resolved decks differ where a restart must not change anything.
#include "spall/io/Deck.hpp"

#include <toml++/toml.h>

#include <fmt/format.h>
#include <map>
#include <sstream>

namespace spall {
namespace {

bool mayChangeOnRestart(const std::string& key) {
  for (const char* k : {"run.end_time", "run.max_steps", "run.title"})
    if (key == k) return true;
  for (const char* t : {"output", "checkpoint", "decomposition", "fragments", "penetration"}) {
    const std::string table(t);
    if (key == table || key.rfind(table + ".", 0) == 0) return true;
  }
  return false;
}

// Shortest round-trip text for numbers (0.3, not 0.29999999999999999), TOML-like otherwise.
std::string valueText(const toml::node& n) {
  if (const auto* f = n.as_floating_point()) return fmt::format("{}", f->get());
  if (const auto* i = n.as_integer()) return std::to_string(i->get());
  if (const auto* s = n.as_string()) return "'" + s->get() + "'";
  if (const auto* a = n.as_array()) {
    std::string out = "[";
    for (std::size_t k = 0; k < a->size(); ++k) out += (k ? ", " : "") + valueText((*a)[k]);
    return out + "]";
  }
  std::ostringstream os;
  n.visit([&](const auto& v) { os << v; });
  return os.str();
}

// "a.b.c" -> value text, for every leaf; arrays of tables are keyed by their entries' names.
void flatten(const toml::node& n, const std::string& key, std::map<std::string, std::string>& out) {
  if (const auto* t = n.as_table()) {
    for (const auto& [k, v] : *t)
      flatten(v, key.empty() ? std::string(k.str()) : key + "." + std::string(k.str()), out);
    return;
  }
  if (const auto* a = n.as_array(); a && a->is_array_of_tables()) {
    for (std::size_t i = 0; i < a->size(); ++i) {
      const auto* t = (*a)[i].as_table();
      const auto* name = t->get("name");
      const std::string label =
          name && name->is_string() ? name->value_or(std::string()) : std::to_string(i);
      flatten(*t, key + "." + label, out);
    }
    return;
  }
  out[key] = valueText(n);
}

std::map<std::string, std::string> leaves(const std::string& text) {
  std::map<std::string, std::string> out;
  try {
    const toml::table root = toml::parse(text);
    flatten(root, "", out);
  } catch (const toml::parse_error&) {
    out["(deck)"] = "unreadable";
  }
  return out;
}

} // namespace

std::vector<std::string> deckPhysicsDifferences(const std::string& before, const std::string& now) {
  const auto a = leaves(before), b = leaves(now);
  std::vector<std::string> diffs;
  for (const auto& [k, v] : a) {
    if (mayChangeOnRestart(k)) continue;
    const auto it = b.find(k);
    if (it == b.end())
      diffs.push_back(k + ": " + v + " in the checkpoint, absent now");
    else if (it->second != v)
      diffs.push_back(k + ": " + v + " in the checkpoint, " + it->second + " now");
  }
  for (const auto& [k, v] : b)
    if (!mayChangeOnRestart(k) && !a.count(k))
      diffs.push_back(k + ": absent in the checkpoint, " + v + " now");
  return diffs;
}

} // namespace spall
