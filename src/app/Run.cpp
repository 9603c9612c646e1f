#include "spall/app/Run.hpp"

#include "Simulation.hpp"
#include "spall/app/Setup.hpp"

#include <fmt/format.h>
#include <sstream>
#include <string>
#include <vector>

// `spall run` and `spall check`: the output directory, a new run or a restart, one dimension.
namespace spall::app {

namespace fs = std::filesystem;

namespace {

// Refuses to touch a directory that holds results, unless asked to; with --overwrite, removes
// only what a run writes there. A restart continues the results in place.
void prepareOutputDirectory(const fs::path& dir, const RunOptions& options) {
  static const char* ours[] = {"deck.toml", "history.csv", "probes.csv", "summary.json",
                               "run.log",   "snapshots",   "checkpoints"};
  if (!fs::exists(dir)) return;
  if (!fs::is_directory(dir))
    throw UsageError(fmt::format("output path '{}' exists and is not a directory", dir.string()));
  if (options.restart) return;
  bool hasResults = false;
  for (const char* name : ours) hasResults = hasResults || fs::exists(dir / name);
  if (!hasResults) return;
  if (!options.overwrite)
    throw UsageError(
        fmt::format("output directory '{}' already holds results; pass --overwrite to replace "
                    "them, --output DIR to write elsewhere or --restart latest to continue them",
                    dir.string()));
  for (const char* name : ours) fs::remove_all(dir / name);
  // The files a run writes beside them, named by what they hold: a stale failure record would
  // otherwise stand for the new run's (a run meeting the same failure keeps an existing one).
  std::vector<fs::path> stale;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (!entry.is_regular_file()) continue;
    const std::string name = entry.path().filename().string();
    const bool record = name.starts_with("failure_step") || name.starts_with("particle_");
    if (name == "penetration.csv" || name == "fragments.csv" ||
        (record && (name.ends_with(".csv") || name.ends_with(".ftable"))))
      stale.push_back(entry.path());
  }
  for (const auto& path : stale) fs::remove(path);
}

// The deck's plausibility warnings and the scene's (collective), printed on rank 0's stderr.
template <int Dim>
std::vector<std::string> printWarnings(const Deck& deck, const Simulation<Dim>& sim,
                                       const parallel::MpiContext& mpi) {
  std::vector<std::string> lines;
  for (const auto& w : deck.warnings) lines.push_back(w.formatted());
  for (const auto& w : sim.sceneWarnings()) lines.push_back(w.formatted());
  if (mpi.root())
    for (const auto& l : lines) fmt::print(stderr, "{}\n", l);
  return lines;
}

template <int Dim>
void runDim(const Deck& deck, const RunOptions& options, const parallel::MpiContext& mpi) {
  if (options.restart && options.overwrite)
    throw UsageError("--restart continues the results in the output directory; --overwrite "
                     "would delete them: pass one or the other");
  const fs::path dir =
      options.outputDir ? fs::path(*options.outputDir) : fs::path(deck.output.directory);
  Simulation<Dim> sim(deck, mpi); // every deck error surfaces here, before anything is written
  if (options.restart) {
    // Rank 0 looks at the directory; every rank needs the same list (one line each: the
    // fallback flag, what is wrong with `latest`, then the files).
    std::string text;
    parallel::onRoot<UsageError>(mpi.comm(), [&] {
      const RestartCandidates c = restartCandidates(dir, *options.restart);
      text = (c.fallback ? "1\n" : "0\n") + c.problem + "\n";
      for (const auto& f : c.files) text += f.string() + "\n";
    });
    parallel::broadcast(text, 0, mpi.comm());
    RestartCandidates candidates;
    std::istringstream lines(text);
    std::string line;
    std::getline(lines, line);
    candidates.fallback = line == "1";
    std::getline(lines, candidates.problem);
    while (std::getline(lines, line)) candidates.files.emplace_back(line);
    sim.resume(candidates); // nothing written yet: a bad checkpoint leaves the directory as it was
  } else {
    sim.generate();
  }
  const auto warnings = printWarnings(deck, sim, mpi);
  if (options.strict && !warnings.empty())
    throw UsageError(fmt::format("{} warning{} above, and --strict: nothing was run",
                                 warnings.size(), warnings.size() > 1 ? "s" : ""));
  sim.logWarnings(warnings);
  sim.prepareRecording();
  parallel::onRoot<UsageError>(mpi.comm(), [&] { prepareOutputDirectory(dir, options); });
  sim.run(options, dir);
}

template <int Dim> std::size_t checkDim(const Deck& deck, const parallel::MpiContext& mpi) {
  Simulation<Dim> sim(deck, mpi);
  sim.generate();
  const double dt = sim.firstTimeStep();
  const std::size_t warned = printWarnings(deck, sim, mpi).size();
  if (!mpi.root()) return warned;
  fmt::print("deck {}: OK\n", deck.path);
  if (!deck.run.title.empty()) fmt::print("  title      {}\n", deck.run.title);
  fmt::print("  dimension  {}D, solver {}\n", Dim, methodSummary(deck));
  for (std::size_t k = 0; k < sim.bodies().size(); ++k) {
    const auto& b = sim.bodies()[k];
    fmt::print("  body       {:<16} {:>10} particles  mass {:.6g} kg  spacing {:.4g} m{}\n", b.name,
               b.particles, b.mass, b.spacing, gradedText(deck, k));
  }
  fmt::print("  particles  {}\n  memory     ~{:.1f} MB (estimate)\n", sim.particles(),
             sim.memoryEstimate() / 1048576.0);
  fmt::print("  first dt   {:.4g} s ({}; end time {:.6g} s)\n", dt,
             deck.solver.method == SolverMethod::Mpm ? "the grid's" : "before viscosity",
             deck.run.end_time);
  fmt::print("  output     {}\n", deck.output.directory);
  for (const auto& w : sim.warnings()) fmt::print("  warning    {}\n", w);
  return warned;
}

} // namespace

void runDeck(const Deck& deck, const RunOptions& options, const parallel::MpiContext& mpi) {
  switch (deck.run.dimension) {
  case 1:
    return runDim<1>(deck, options, mpi);
  case 2:
    return runDim<2>(deck, options, mpi);
  default:
    return runDim<3>(deck, options, mpi);
  }
}

std::size_t checkDeck(const Deck& deck, const parallel::MpiContext& mpi) {
  switch (deck.run.dimension) {
  case 1:
    return checkDim<1>(deck, mpi);
  case 2:
    return checkDim<2>(deck, mpi);
  default:
    return checkDim<3>(deck, mpi);
  }
}

} // namespace spall::app
