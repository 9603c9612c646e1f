#include "Simulation.hpp"

#include "spall/app/StopSignals.hpp"
#include "spall/app/SystemInfo.hpp"

#include <cmath>
#include <fmt/format.h>
#include <fstream>

// The closing summary: the lines a user reads and summary.json, which tools read.
namespace spall::app {

namespace fs = std::filesystem;

namespace {

// The command that continues this run, as the user would type it (any rank count will do).
std::string resumeCommand(const RunOptions& o) {
  auto quote = [](const std::string& a) {
    if (a.find_first_of(" \t'\"$`\\[]*?{}()<>|&;") == std::string::npos) return a;
    std::string q = "'";
    for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
  };
  std::string cmd = "spall run " + quote(o.deckPath);
  for (const auto& v : o.overrides) cmd += " --set " + quote(v);
  if (o.outputDir) cmd += " --output " + quote(*o.outputDir);
  return cmd + " --restart latest";
}

// A JSON object whose members keep the order they were added in; values are rendered by the
// caller (numbers in the precision each one needs).
class JsonObject {
public:
  JsonObject& value(const std::string& key, std::string rendered) {
    members_.emplace_back(key, std::move(rendered));
    return *this;
  }
  JsonObject& text(const std::string& key, const std::string& s) {
    std::string q = "\"";
    for (char c : s) {
      if (c == '"' || c == '\\') q += '\\';
      q += c;
    }
    return value(key, q + "\"");
  }
  // A nested object, written on one line.
  JsonObject& object(const std::string& key, const JsonObject& o) {
    return value(key, o.str(false));
  }
  std::string str(bool multiline) const {
    std::string out = "{";
    for (std::size_t k = 0; k < members_.size(); ++k)
      out += fmt::format("{}{}\"{}\": {}", k ? "," : "", multiline ? "\n  " : (k ? " " : ""),
                         members_[k].first, members_[k].second);
    return out + (multiline ? "\n}\n" : "}");
  }

private:
  std::vector<std::pair<std::string, std::string>> members_;
};

std::string fixed6(double v) {
  return fmt::format("{:.6f}", v);
}

} // namespace

template <int Dim>
void Simulation<Dim>::finish(RunLog& log, const RunOptions& options, Clock::time_point wall0,
                             int stopSignal) {
  const auto& st = method_->stats();
  const auto& phases = st.phases;
  const double wall = std::chrono::duration<double>(Clock::now() - wall0).count();
  // The stepping rate of this job: checkpoint writing is reported on its own line.
  const std::int64_t steps = step_ - startStep_;
  const double pSteps = static_cast<double>(particles()) * static_cast<double>(steps);
  const double stepping = wall - phases[methods::kCheckpoint];
  const double rate = stepping > 0.0 ? pSteps / stepping : 0.0;
  const auto& t = last_;
  const double massErr = std::abs(t.mass - totals0_.mass) / totals0_.mass;
  double momScale = 0.0, momErr = 0.0;
  for (int d = 0; d < 3; ++d) {
    momScale = std::max(
        {momScale, std::abs(totals0_.momentum[d]), t.momentumScale[d], totals0_.momentumScale[d]});
    momErr = std::max(momErr, std::abs(t.momentum[d] - totals0_.momentum[d]));
  }
  momErr = momScale > 0.0 ? momErr / momScale : 0.0;
  const double e0 = totals0_.total();
  const double energyErr = std::abs(t.total() - e0) / std::max(std::abs(e0), 1e-300);
  const std::size_t peak =
      static_cast<std::size_t>(mpi_.sum(static_cast<double>(peakResidentBytes())));
  const std::size_t base = static_cast<std::size_t>(mpi_.sum(static_cast<double>(baselineRss_)));
  const double pairs = mpi_.sum(static_cast<double>(st.pairs));
  const double ghostFraction = mpi_.max(st.ghostFractionMax);
  const std::uint64_t crossPairs = mpi_.sum(st.crossPairs) / 2;
  const bool reproducible =
      deck_.decomposition.reproducible && mpi_.max(st.canonicalLost ? 1.0 : 0.0) == 0.0;
  const double meanNeighbors =
      st.evaluations > 0 ? pairs / (static_cast<double>(st.evaluations) *
                                    std::max<double>(1.0, static_cast<double>(particles())))
                         : 0.0;
  // The share of each stepping phase (checkpoints have their own line).
  std::string shares;
  for (int p = 0; p < methods::kCheckpoint; ++p)
    shares += fmt::format("{}{} {:.1f}%", p ? " " : "", methods::kPhaseNames[p],
                          100 * phases[static_cast<methods::Phase>(p)] / wall);
  std::vector<std::string> lines = {
      fmt::format("{}: {} steps to t = {:.6g} s (step {}) in {:.2f} s wall | {:.3g} "
                  "particle-steps/s ({:.3g} per core)",
                  stopSignal ? "stopped" : "done", steps, time_, step_, wall, rate,
                  rate / mpi_.size()),
      fmt::format("conservation: mass {:.1e} | momentum {:.1e} | total energy {:.1e} (relative)",
                  massErr, momErr, energyErr),
      "time: " + shares};
  if (checkpointsWritten_ > 0)
    lines.push_back(fmt::format(
        "checkpoints: {} written, {:.1f} MB each ({:.0f} B/particle), {:.2f} s in all "
        "({:.0f} MB/s); latest {}",
        checkpointsWritten_, checkpointBytes_ / 1e6,
        static_cast<double>(checkpointBytes_) /
            std::max<double>(1.0, static_cast<double>(particles())),
        checkpointWriteSeconds_,
        checkpointWriteSeconds_ > 0 ? checkpointWriteBytes_ / 1e6 / checkpointWriteSeconds_ : 0.0,
        (dir_ / "checkpoints" / checkpointFileName(lastCheckpointStep_)).string()));
  if (stopSignal)
    lines.push_back(fmt::format("stopped by {} at step {}: resume with\n  {}",
                                StopSignals::name(stopSignal), step_, resumeCommand(options)));
  if (mpi_.size() > 1)
    lines.push_back(fmt::format(
        "decomposition: {} {} on {} ranks | {} rebalances, cost max/mean {:.3f} | ghosts up to "
        "{:.1f}% of a rank's particles, {} pairs across ranks | {} migrations, up to {} ranks in "
        "one step{}",
        deck_.decomposition.curve, deck_.decomposition.partitioner, mpi_.size(), st.rebalances,
        st.imbalance, 100.0 * ghostFraction, crossPairs, st.migratedTotal, st.maxRankDistance,
        st.metisEdgeCut >= 0 ? fmt::format(" | METIS edge cut {} pairs", st.metisEdgeCut) : ""));
  if (deck_.decomposition.reproducible && !reproducible)
    lines.push_back("note: a rank's particles were too sparse for the canonical neighbor grid; "
                    "other rank counts agree with this run to round-off, not bit for bit");
  lines.push_back(
      fmt::format("output in {} (open snapshots/series.xmf in ParaView)", dir_.string()));
  log.summary(lines);
  if (!mpi_.root()) return;

  JsonObject phaseSeconds;
  for (int p = 0; p < methods::kPhaseCount; ++p)
    phaseSeconds.value(methods::kPhaseNames[p], fixed6(phases[static_cast<methods::Phase>(p)]));
  phaseSeconds.value("other", fixed6(std::max(0.0, wall - phases.total())));
  JsonObject checkpoint;
  checkpoint.value("written", fmt::format("{}", checkpointsWritten_))
      .value("bytes", fmt::format("{}", checkpointBytes_))
      .value("bytes_per_particle",
             fmt::format("{:.1f}", static_cast<double>(checkpointBytes_) /
                                       std::max<double>(1.0, static_cast<double>(particles()))))
      .value("write_seconds", fixed6(checkpointWriteSeconds_))
      .value("write_bytes", fmt::format("{}", checkpointWriteBytes_))
      .value("read_seconds", fixed6(checkpointReadSeconds_))
      .value("read_bytes", fmt::format("{}", checkpointReadBytes_))
      .text("restarted_from", resumedFrom_)
      .value("ranks_written", fmt::format("{}", checkpointRanks_));
  JsonObject decomposition;
  decomposition.text("curve", deck_.decomposition.curve)
      .text("partitioner", deck_.decomposition.partitioner)
      .value("rebalances", fmt::format("{}", st.rebalances))
      .value("imbalance", fixed6(st.imbalance))
      .value("ghost_fraction_max", fixed6(ghostFraction))
      .value("migrated", fmt::format("{}", st.migratedTotal))
      .value("max_rank_distance", fmt::format("{}", st.maxRankDistance))
      .value("pairs_across_ranks", fmt::format("{}", crossPairs))
      .value("metis_edge_cut", fmt::format("{}", st.metisEdgeCut))
      .value("reproducible", reproducible ? "true" : "false");
  JsonObject conservation;
  conservation.value("mass_relative", fmt::format("{:.6e}", massErr))
      .value("momentum_relative", fmt::format("{:.6e}", momErr))
      .value("energy_relative", fmt::format("{:.6e}", energyErr));
  JsonObject summary;
  summary.text("deck", options.deckPath)
      .text("title", deck_.run.title)
      .value("ranks", fmt::format("{}", mpi_.size()))
      .value("dimension", fmt::format("{}", Dim))
      .value("particles", fmt::format("{}", particles()))
      .value("steps", fmt::format("{}", step_))
      .value("time", fmt::format("{:.17g}", time_))
      .value("wall_seconds", fixed6(wall))
      .value("particle_steps_per_second", fmt::format("{:.6g}", rate))
      .value("particle_steps_per_second_per_core", fmt::format("{:.6g}", rate / mpi_.size()))
      .text("status", stopSignal ? "stopped" : "finished")
      .value("steps_this_run", fmt::format("{}", steps))
      .value("mean_neighbors", fmt::format("{:.3f}", meanNeighbors))
      .value("peak_rss_bytes", fmt::format("{}", peak))
      .value("baseline_rss_bytes", fmt::format("{}", base))
      .value("bytes_per_particle",
             fmt::format("{:.1f}", particles() > 0
                                       ? static_cast<double>(peak - std::min(peak, base)) /
                                             static_cast<double>(particles())
                                       : 0.0))
      .object("phases", phaseSeconds)
      .object("checkpoint", checkpoint)
      .object("decomposition", decomposition)
      .object("conservation", conservation);
  std::ofstream(dir_ / "summary.json") << summary.str(true);
}

template class Simulation<1>;
template class Simulation<2>;
template class Simulation<3>;

} // namespace spall::app
