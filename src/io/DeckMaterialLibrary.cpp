// material.library: a published material set in a file of its own (decks/materials/NAME.toml,
// its source in its header), merged into the deck's [[material]] entry before the deck is read,
// so that every check, override and the deck as run treat its keys as the deck's own.
#include "DeckDetail.hpp"

#include <cstdlib>
#include <filesystem>
#include <set>

namespace spall::io::deck_detail {

namespace fs = std::filesystem;

namespace {

void appendPaths(std::vector<fs::path>& dirs, const std::string& list) {
  for (std::size_t from = 0; from <= list.size();) {
    const std::size_t to = std::min(list.find(':', from), list.size());
    if (to > from) dirs.emplace_back(list.substr(from, to - from));
    from = to + 1;
  }
}

// Where a library name is looked up, in order: materials/ beside the deck, SPALL_MATERIAL_PATH
// (colon-separated), the source tree's decks/materials and the installed share/spall/materials.
std::vector<fs::path> libraryDirs(const std::string& deckPath) {
  std::vector<fs::path> dirs{fs::path(deckPath).parent_path() / "materials"};
  if (const char* env = std::getenv("SPALL_MATERIAL_PATH")) appendPaths(dirs, env);
#ifdef SPALL_MATERIALS_DIRS
  appendPaths(dirs, SPALL_MATERIALS_DIRS);
#endif
  return dirs;
}

// The deck's keys win. A sub-table the deck gives (eos = {min_pressure = ...}) takes the
// library's keys it lacks, unless it names another type: then it is the deck's own model. The
// library's nodes are moved, not copied: a move keeps their place in the file, so errors point
// into it.
void merge(toml::table& into, toml::table& library) {
  for (auto&& [key, value] : library) {
    toml::node* mine = into.get(key);
    if (!mine) {
      into.insert(key, std::move(value));
      continue;
    }
    toml::table* mt = mine->as_table();
    toml::table* lt = value.as_table();
    if (!mt || !lt) continue;
    const auto* myType = mt->get_as<std::string>("type");
    const auto* libType = lt->get_as<std::string>("type");
    if (myType && libType && myType->get() != libType->get()) continue;
    for (auto&& [k, v] : *lt)
      if (!mt->contains(k)) mt->insert(k, std::move(v));
  }
}

bool plainName(const std::string& name) {
  if (name.empty()) return false;
  for (const char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return false;
  return true;
}

} // namespace

std::vector<std::string> inlineMaterialLibrary(toml::table& root, const std::string& deckPath) {
  std::vector<std::string> used;
  toml::array* materials = root["material"].as_array();
  if (!materials) return used;
  const auto dirs = libraryDirs(deckPath);
  for (auto& node : *materials) {
    toml::table* t = node.as_table();
    if (!t) continue; // the reader reports it
    const toml::node* given = t->get("library");
    if (!given) continue;
    const SourceLocation at = locate(given->source(), deckPath);
    const auto* name = given->as_string();
    if (!name || !plainName(name->get()))
      throw DeckError(at, "'library' names a file of the material library: letters, digits, '_' "
                          "and '-' (decks/materials/NAME.toml)");
    fs::path file;
    for (const auto& d : dirs)
      if (std::error_code ec; fs::is_regular_file(d / (name->get() + ".toml"), ec)) {
        file = d / (name->get() + ".toml");
        break;
      }
    if (file.empty()) {
      std::set<std::string> known;
      for (const auto& d : dirs) {
        std::error_code ec;
        for (const auto& e : fs::directory_iterator(d, ec))
          if (e.path().extension() == ".toml") known.insert(e.path().stem().string());
      }
      const Names candidates(known.begin(), known.end());
      std::string searched;
      for (const auto& d : dirs) searched += (searched.empty() ? "" : ", ") + d.string();
      throw DeckError(at, "no material '" + name->get() + "' in the library" +
                              didYouMean(name->get(), candidates) + " (searched " + searched +
                              "; it holds: " + (known.empty() ? "nothing" : joined(candidates)) +
                              ")");
    }
    toml::table library;
    try {
      library = toml::parse_file(file.string());
    } catch (const toml::parse_error& e) {
      const auto& b = e.source().begin;
      throw DeckError({file.string(), static_cast<int>(b.line), static_cast<int>(b.column)},
                      std::string(e.description()));
    }
    for (const char* own : {"name", "library"})
      if (const toml::node* n = library.get(own))
        throw DeckError(locate(n->source(), file.string()),
                        std::string("a library material does not set '") + own +
                            "': the deck's [[material]] names it and picks the file");
    merge(*t, library);
    t->erase("library");
    used.push_back(name->get() + " (" + file.string() + ")");
  }
  return used;
}

} // namespace spall::io::deck_detail
