#pragma once
// `spall run` and `spall check`: set-up from a validated deck, the step loop, output.
#include "spall/io/Deck.hpp"
#include "spall/parallel/Mpi.hpp"

#include <optional>
#include <string>
#include <vector>

namespace spall::app {

struct RunOptions {
  std::string deckPath;
  std::vector<std::string> overrides;
  std::optional<std::string> outputDir; // default: the deck's output.directory
  std::optional<std::string> restart;
  bool overwrite = false;
  bool quiet = false;
  bool strict = false;                  // plausibility warnings are errors (exit 2)
  std::vector<std::string> commandLine; // argv, for summary.json
};

// Runs a deck to its end. Throws DeckError / UsageError before anything is written, RunError
// when the run fails.
void runDeck(const Deck& deck, const RunOptions& options, const parallel::MpiContext& mpi);

// Sets the deck up without running it and prints a summary on rank 0, its plausibility warnings
// on stderr ("FILE:LINE:COLUMN: warning: ..."). Returns how many warnings there were.
std::size_t checkDeck(const Deck& deck, const parallel::MpiContext& mpi);

} // namespace spall::app
