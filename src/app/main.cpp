// spall: the command line (docs/reference.md). Exit codes: 0 finished, 1 the run failed, 2 usage or
// deck error (nothing run, nothing written).
#include "spall/app/Element.hpp"
#include "spall/app/History.hpp"
#include "spall/app/Plan.hpp"
#include "spall/app/Run.hpp"
#include "spall/app/SystemInfo.hpp"
#include "spall/core/Error.hpp"
#include "spall/core/Threads.hpp"
#include "spall/io/Deck.hpp"
#include "spall/io/DeckKeys.hpp"
#include "spall/parallel/Mpi.hpp"

#include <CLI/CLI.hpp>

#include <fmt/format.h>
#include <malloc.h>
#include <map>

namespace {

int fail(const spall::parallel::MpiContext& mpi, int code, const std::string& message) {
  if (mpi.root()) fmt::print(stderr, "{}\n", message);
  return code;
}

// `spall element`'s options (the single-element driver, docs/reference.md).
CLI::App* addElementCommand(CLI::App& cli, spall::app::ElementOptions& element) {
  auto* elementCmd = cli.add_subcommand(
      "element", "drive one material point through an F-table (single-element driver)");
  elementCmd->add_option("deck", element.deckPath, "deck file (TOML) with the material")
      ->required();
  elementCmd->add_option("--material", element.material, "the deck material to drive")->required();
  elementCmd->add_option("--table", element.table, "the F-table (t F11 ... F33 [theta ax ay az])")
      ->required();
  elementCmd->add_option("--output", element.output, "the CSV to write")->required();
  elementCmd->add_option("--set", element.overrides, "override a deck value: KEY=VALUE");
  elementCmd->add_option("--substeps", element.substeps,
                         "steps between two rows of the table (default 100)");
  // Parsed once, here: the driver sees the enum.
  elementCmd
      ->add_option_function<std::string>(
          "--kinematics",
          [&element](const std::string& v) {
            using K = spall::app::ElementOptions::Kinematics;
            element.kinematics = v == "midpoint" ? K::Midpoint : K::Run;
          },
          "velocity gradient from F: midpoint (Austin Eq. 4.8, exact under superimposed "
          "rotation; the default for a table) or run (Eq. 4.10, a run's; the default with --state)")
      ->check(CLI::IsMember({"run", "midpoint"}));
  elementCmd->add_option("--state", element.state,
                         "a recorded particle's particle_ID.csv: its density and energy each row");
  elementCmd->add_flag("--every-substep", element.everySubstep,
                       "a CSV row per substep (default: one per table row)");
  elementCmd->add_option("--flaw-volume", element.flawVolume,
                         "volume (m^3) a Grady-Kipp material's flaws are drawn for (default 1e-9)");
  elementCmd->add_flag("--overwrite", element.overwrite, "replace an existing CSV");
  return elementCmd;
}

// `spall plan`'s options (a deck's decomposition for virtual ranks, docs/reference.md).
CLI::App* addPlanCommand(CLI::App& cli, spall::app::PlanOptions& plan,
                         std::vector<std::string>& overrides) {
  auto* planCmd = cli.add_subcommand(
      "plan", "a deck's particles and decomposition for N virtual ranks, no physics: owned "
              "particles, ghosts, neighbor ranks, bytes, memory, predicted efficiency");
  planCmd->add_option("deck", plan.deckPath, "deck file (TOML)")->required();
  planCmd->add_option("--ranks", plan.ranks, "rank counts, e.g. 64,256,1024")
      ->required()
      ->delimiter(',');
  planCmd->add_option("--threads", plan.threads, "threads per rank (default 1)");
  planCmd->add_option("--set", overrides, "override a deck value: KEY=VALUE");
  planCmd->add_option("--cores", plan.cores,
                      "cores the ranks share (default: one per rank, as on a cluster)");
  planCmd->add_option(
      "--measured", plan.measured,
      "a 1-rank, 1-thread run of this deck: its steady rate and bytes per particle");
  planCmd->add_option("--rate", plan.costs.rate, "particle-steps/s per core, one thread");
  planCmd->add_option("--ghost-cost", plan.costs.ghost,
                      "a ghost's cost a step relative to an owned particle's");
  planCmd->add_option("--all-cores-slowdown", plan.costs.slowdown,
                      "a core's compute time when every core works, over one core's alone");
  planCmd->add_option("--latency", plan.costs.latency, "seconds a message (default 2e-6)");
  planCmd->add_option("--bandwidth", plan.costs.bandwidth, "bytes/s a rank (default 5e9)");
  planCmd->add_flag("--per-rank", plan.perRank, "the per-rank table for every rank count");
  planCmd->add_option("--json", plan.json, "also write the plan as JSON to this file");
  return planCmd;
}

} // namespace

int main(int argc, char** argv) {
  // Particle arrays of a megabyte or more are mapped and unmapped on their own, always: glibc
  // otherwise raises this threshold to the largest block freed, and the arrays that grow with
  // the ghosts and lists are then carved from a heap that never shrinks (a Taylor bar's resident
  // memory grew by 40% over its first searches).
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  spall::parallel::MpiSession session(argc, argv);
  spall::parallel::MpiContext mpi;
  spall::configureThreads();

  CLI::App cli{"spall: a particle hydrocode for impact, penetration and fragmentation of solids"};
  cli.set_version_flag("--version", std::string("spall ") + spall::app::BuildInfo::version());
  cli.require_subcommand(1);

  spall::app::RunOptions run;
  run.commandLine.assign(argv, argv + argc);
  std::string outputDir, restart;
  auto* runCmd = cli.add_subcommand("run", "run a deck");
  runCmd->add_option("deck", run.deckPath, "deck file (TOML)")->required();
  runCmd->add_option("--set", run.overrides, "override a deck value: KEY=VALUE (dotted path)");
  runCmd->add_option("--restart", restart, "continue from a checkpoint: latest or a path");
  runCmd->add_option("--output", outputDir,
                     "output directory (default: the deck's output.directory)");
  runCmd->add_flag("--overwrite", run.overwrite, "replace results already in the output directory");
  runCmd->add_flag("--quiet", run.quiet, "print errors and warnings only");
  runCmd->add_flag("--strict", run.strict,
                   "refuse (exit 2) a deck with plausibility warnings (a unit typed wrong?)");

  std::string checkDeckPath;
  std::vector<std::string> checkOverrides;
  auto* checkCmd =
      cli.add_subcommand("check", "parse and validate a deck, print a summary; runs nothing");
  checkCmd->add_option("deck", checkDeckPath, "deck file (TOML)")->required();
  checkCmd->add_option("--set", checkOverrides, "override a deck value: KEY=VALUE");
  bool checkStrict = false;
  checkCmd->add_flag("--strict", checkStrict,
                     "exit 2 if the deck has plausibility warnings (a unit typed wrong?)");

  bool keysMarkdown = false;
  std::string keysPrefix;
  auto* keysCmd = cli.add_subcommand(
      "keys", "every deck key: path, type, default, unit, accepted values, meaning");
  keysCmd->add_option("prefix", keysPrefix, "only the keys whose path begins so (e.g. solver.)");
  keysCmd->add_flag("--markdown", keysMarkdown, "the page decks/keys.md (all keys)");

  auto* infoCmd =
      cli.add_subcommand("info", "version, git revision, compiler, MPI, HDF5, METIS, features");

  spall::app::ElementOptions element;
  auto* elementCmd = addElementCommand(cli, element);
  spall::app::HistoryOptions history;
  auto* historyCmd = cli.add_subcommand(
      "history", "a particle's deformation history as an F-table (for spall element)");
  historyCmd->add_option("outdir", history.outputDir, "a run's output directory")->required();
  historyCmd->add_option("--particle", history.particle, "the particle's id")->required();
  historyCmd->add_option("--output", history.output, "the F-table to write (- for stdout)")
      ->required();
  historyCmd->add_flag("--overwrite", history.overwrite, "replace an existing file");

  spall::app::PlanOptions plan;
  std::vector<std::string> planOverrides;
  auto* planCmd = addPlanCommand(cli, plan, planOverrides);

  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" with exit code 0 in CLI11.
    int code = 0;
    if (mpi.root())
      code = cli.exit(e);
    else
      code = e.get_exit_code();
    return code == 0 ? 0 : 2;
  }

  try {
    if (*infoCmd) {
      if (mpi.root()) fmt::print("{}", spall::app::infoText());
      return 0;
    }
    if (*keysCmd) {
      const std::string text = spall::io::formatDeckKeys(keysMarkdown, keysPrefix);
      if (text.empty()) throw spall::UsageError("no deck key begins with '" + keysPrefix + "'");
      if (mpi.root()) fmt::print("{}", text);
      return 0;
    }
    if (*elementCmd) {
      if (mpi.size() > 1) throw spall::UsageError("spall element runs on one rank");
      spall::app::runElement(element);
      // Which kinematics it used, and why, when the user did not choose.
      using K = spall::app::ElementOptions::Kinematics;
      const K used = spall::app::kinematicsFor(element);
      const char* why = element.kinematics      ? "as asked"
                        : element.state.empty() ? "the default for a table"
                                                : "the default for a recorded particle";
      fmt::print("element: wrote {} ({} kinematics, Austin 2013 Eq. {}, {})\n", element.output,
                 used == K::Midpoint ? "midpoint" : "run", used == K::Midpoint ? "4.8" : "4.10",
                 why);
      return 0;
    }
    if (*historyCmd) {
      if (mpi.root()) spall::app::writeHistory(history);
      return 0;
    }
    if (*planCmd) {
      const auto deck = spall::loadDeck(plan.deckPath, planOverrides);
      spall::app::runPlan(deck, plan, mpi);
      return 0;
    }
    if (*checkCmd) {
      const auto deck = spall::loadDeck(checkDeckPath, checkOverrides);
      const std::size_t warned = spall::app::checkDeck(deck, mpi);
      if (checkStrict && warned > 0)
        return fail(mpi, 2,
                    fmt::format("error: {} warning{} and --strict", warned, warned > 1 ? "s" : ""));
      return 0;
    }
    if (!outputDir.empty()) run.outputDir = outputDir;
    if (!restart.empty()) run.restart = restart;
    const auto deck = spall::loadDeck(run.deckPath, run.overrides);
    spall::app::runDeck(deck, run, mpi);
    return 0;
  } catch (const spall::DeckError& e) {
    return fail(mpi, 2, e.formatted());
  } catch (const spall::UsageError& e) {
    return fail(mpi, 2, std::string("error: ") + e.what());
  } catch (const spall::RunError& e) {
    // Run failures are detected collectively (global reductions), so every rank gets here. A
    // failed step's explanation is the same on every rank: rank 0 prints it.
    if (mpi.size() == 1 || e.isCollective()) return fail(mpi, 1, std::string("error: ") + e.what());
    fmt::print(stderr, "error (rank {}): {}\n", mpi.rank(), e.what());
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "internal error (rank {}): {}\n", mpi.rank(), e.what());
    MPI_Abort(mpi.comm(), 1);
    return 1;
  }
}
