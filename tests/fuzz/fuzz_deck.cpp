// libFuzzer over the deck reader and validator (io/Deck*): every input either loads or throws a
// DeckError that names a position ("FILE:LINE:COLUMN: error: ..." or "--set KEY=VALUE: error:
// ..."); anything else escaping, a crash, a hang or a sanitizer report is a failure.
// The input is a deck, optionally followed by a NUL byte and `--set` overrides separated by NULs.
#include "spall/io/Deck.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

const std::string& deckPath() {
  static const std::string path = [] {
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir ? dir : "/tmp") + "/spall-fuzz-" + std::to_string(getpid()) + ".toml";
  }();
  return path;
}

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz_deck: %s\n", what.c_str());
  std::abort();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::size_t nul = input.find('\0');
  std::vector<std::string> overrides;
  if (nul != std::string::npos) {
    std::size_t from = nul + 1;
    while (from <= input.size()) {
      const std::size_t to = std::min(input.find('\0', from), input.size());
      if (to > from) overrides.push_back(input.substr(from, to - from));
      from = to + 1;
    }
  }
  {
    std::ofstream out(deckPath(), std::ios::binary | std::ios::trunc);
    out.write(input.data(), static_cast<std::streamsize>(std::min(nul, input.size())));
  }
  try {
    const spall::Deck deck = spall::loadDeck(deckPath(), overrides);
    if (deck.run.dimension < 1 || deck.run.dimension > 3) fail("a deck of dimension outside 1-3");
    if (deck.bodies.empty() || deck.materials.empty()) fail("a deck without bodies or materials");
  } catch (const spall::DeckError& e) {
    const std::string text = e.formatted();
    if (e.where().file.empty() || text.find(": error: ") == std::string::npos)
      fail("a deck error without its position: " + text);
  }
  return 0;
}
