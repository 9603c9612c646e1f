// Which keys of two resolved decks differ where a restart must not change anything.
#include "spall/io/Deck.hpp"

#include <toml++/toml.h>

#include <fmt/format.h>
#include <fmt/ranges.h>
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

// The names of an array of tables' entries, in order ("body", "material").
std::vector<std::string> entryNames(const toml::table& root, const char* array) {
  std::vector<std::string> names;
  if (const auto* a = root.get_as<toml::array>(array))
    for (const auto& e : *a)
      if (const auto* t = e.as_table())
        names.push_back(t->get("name") ? t->get("name")->value_or(std::string()) : std::string());
  return names;
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

std::vector<std::string> deckPhysicsDifferences(const std::string& before, const std::string& now,
                                                const std::vector<std::string>& free,
                                                std::vector<std::string>* freeChanges) {
  const auto a = leaves(before), b = leaves(now);
  const auto isFree = [&](const std::string& key) {
    for (const auto& table : free)
      if (key.rfind(table + ".", 0) == 0) return true;
    return false;
  };
  std::vector<std::string> diffs;
  const auto differs = [&](const std::string& key, const std::string& line) {
    if (isFree(key)) {
      if (freeChanges) freeChanges->push_back(line);
    } else if (!mayChangeOnRestart(key)) {
      diffs.push_back(line);
    }
  };
  for (const auto& [k, v] : a) {
    const auto it = b.find(k);
    if (it == b.end())
      differs(k, k + ": " + v + " in the checkpoint, absent now");
    else if (it->second != v)
      differs(k, k + ": " + v + " in the checkpoint, " + it->second + " now");
  }
  for (const auto& [k, v] : b)
    if (!a.count(k)) differs(k, k + ": absent in the checkpoint, " + v + " now");
  return diffs;
}

std::vector<std::string> restartFreeTables(const std::string& before, const Deck& now,
                                           const std::vector<std::int64_t>& waiting, double time) {
  toml::table root, rootNow;
  try {
    root = toml::parse(before);
    rootNow = toml::parse(now.resolved_toml);
  } catch (const toml::parse_error&) {
    return {}; // deckPhysicsDifferences says the checkpoint's deck is unreadable
  }
  // Particles hold their body's and material's index: both lists keep their order (the deck's
  // own [[body]] and [[material]] entries; a [[jet]]'s bodies follow them as its table says).
  for (const auto& [array, plural] :
       {std::pair{"body", "bodies"}, std::pair{"material", "materials"}})
    if (entryNames(root, array) != entryNames(rootNow, array))
      throw UsageError(fmt::format("the checkpoint's deck has the {} {}, the deck now {}: a "
                                   "restart keeps them and their order",
                                   plural, fmt::join(entryNames(root, array), ", "),
                                   fmt::join(entryNames(rootNow, array), ", ")));
  const std::size_t bodies = now.bodies.size(), materials = now.materials.size();
  if (waiting.size() != bodies) return {}; // restoreState refuses the checkpoint
  std::vector<std::string> free;
  std::vector<char> used(materials, 0);
  for (std::size_t b = 0; b < bodies; ++b) {
    const BodyConfig& body = now.bodies[b];
    if (!waiting[b]) {
      used[static_cast<std::size_t>(body.material_index)] = 1;
      continue;
    }
    if (body.joinedBy(time))
      throw DeckError(body.where,
                      fmt::format("body '{}' has not joined the run at the checkpoint's t = {:g} "
                                  "s, so it may change, but it must still join after it: "
                                  "insert_time = {:g} s",
                                  body.name, time, body.insert_time));
    free.push_back("body." + body.name);
  }
  for (std::size_t m = 0; m < materials; ++m)
    if (!used[m]) free.push_back("material." + now.materials[m].name);
  return free;
}

} // namespace spall
