#include "Simulation.hpp"

#include "spall/app/StopSignals.hpp"
#include "spall/app/SystemInfo.hpp"

#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fstream>
#include <nlohmann/json.hpp>

// The closing summary of a run: the lines a user reads and summary.json for tools.
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

using Json = nlohmann::ordered_json; // members in the order written

// Seconds and ratios to a microsecond: more digits are noise between runs.
double round6(double v) {
  return std::isfinite(v) ? std::round(v * 1e6) / 1e6 : v;
}
double round1(double v) {
  return std::round(v * 10.0) / 10.0;
}
// NaN and infinities are not JSON: null.
Json number(double v) {
  return std::isfinite(v) ? Json(v) : Json(nullptr);
}

} // namespace

// What a run's end reports: its rate, conservation, memory and decomposition (over all ranks).
template <int Dim> struct Simulation<Dim>::RunReport {
  double wall = 0.0, rate = 0.0;
  std::int64_t steps = 0;
  double massErr = 0.0, momErr = 0.0, energyErr = 0.0;
  std::size_t peak = 0, base = 0;
  std::vector<std::pair<std::string, double>> memory; // bytes per particle, by part
  double accounted = 0.0;
  double ghostFraction = 0.0, meanNeighbors = 0.0;
  std::uint64_t crossPairs = 0, rowEvaluations = 0;
};

// Mass, momentum and total energy against their initial values, relative.
template <int Dim> void Simulation<Dim>::conservationErrors(RunReport& r) const {
  const auto& t = last_;
  r.massErr = std::abs(t.mass - totals0_.mass) / totals0_.mass;
  double momScale = 0.0, momErr = 0.0;
  // The components no unbooked force acts along: in rz the sum of m v_r is no conserved quantity
  // (the hoop force is radial), and a rigid wall's force (its images' pairs, the hold) is not
  // booked, so the components along its normal are left out. None left: not judged (NaN).
  std::array<bool, 3> judged{deck_.run.geometry != Geometry::RZ, true, true};
  for (const auto& b : deck_.boundaries)
    if (b.type == BoundaryType::RigidWall)
      for (std::size_t d = 0; d < std::min<std::size_t>(3, b.normal.size()); ++d)
        if (b.normal[d] != 0.0) judged[d] = false;
  bool anyJudged = false;
  for (int d = deck_.run.geometry == Geometry::RZ ? 1 : 0; d < 3; ++d) {
    momScale = std::max(
        {momScale, std::abs(totals0_.momentum[d]), t.momentumScale[d], totals0_.momentumScale[d]});
    if (!judged[static_cast<std::size_t>(d)] || d >= Dim) continue;
    anyJudged = true;
    // Less the impulse of external forces (a confining pressure, damping, fixed bodies' supports).
    const double expected =
        totals0_.momentum[d] + method_->externalImpulse()[static_cast<std::size_t>(d)];
    momErr = std::max(momErr, std::abs(t.momentum[d] - expected));
  }
  r.momErr = !anyJudged       ? std::numeric_limits<double>::quiet_NaN()
             : momScale > 0.0 ? momErr / momScale
                              : 0.0;
  // What the total energy should be: the initial one plus the work of external forces (a
  // confining pressure, damping), judged against the larger of it and the final one.
  const double e0 = totals0_.total(), work = method_->externalWork();
  r.energyErr =
      std::abs(t.total() - e0 - work) / std::max({std::abs(e0), std::abs(t.total()), 1e-300});
}

// Collective: every rank calls it, in the same order of sums.
template <int Dim>
typename Simulation<Dim>::RunReport Simulation<Dim>::report(Clock::time_point wall0) {
  const auto& st = method_->stats();
  RunReport r;
  r.wall = std::chrono::duration<double>(Clock::now() - wall0).count();
  // The stepping rate of this job: checkpoint writing is reported on its own line.
  r.steps = step_ - startStep_;
  // With time bins a step is its substeps of the finest step: the rate counts those, so that
  // it compares with a single-step run's over the same time (the rows they evaluated are in
  // summary.json's time_bins).
  const double substeps =
      historyBins() > 0 ? static_cast<double>(st.substeps) : static_cast<double>(r.steps);
  const double pSteps = static_cast<double>(particles()) * substeps;
  const double stepping = r.wall - st.phases[methods::kCheckpoint];
  r.rate = stepping > 0.0 ? pSteps / stepping : 0.0;
  conservationErrors(r);
  r.peak = static_cast<std::size_t>(mpi_.sum(static_cast<double>(peakResidentBytes())));
  r.base = static_cast<std::size_t>(mpi_.sum(static_cast<double>(baselineRss_)));
  const double pairs = mpi_.sum(static_cast<double>(st.pairs));
  // Memory by part: the bytes allocated where they live, over all ranks, per particle (the
  // process's other memory, MPI's and HDF5's buffers among it, is in the RSS only).
  std::vector<MemoryPart> parts = {{"particle_fields", store_.fieldBytes()}};
  for (auto& part : method_->memoryParts()) parts.push_back(std::move(part));
  parts.push_back({"rescue_copy", rescue_.rows.size()});
  const double perParticle = 1.0 / std::max(1.0, static_cast<double>(particles()));
  for (const auto& part : parts) {
    const double b = mpi_.sum(static_cast<double>(part.bytes)) * perParticle;
    r.accounted += b;
    r.memory.emplace_back(part.name, b);
  }
  r.ghostFraction = mpi_.max(st.ghostFractionMax);
  r.rowEvaluations = mpi_.sum(st.rowEvaluations);
  r.crossPairs = mpi_.sum(st.crossPairs) / 2;
  r.meanNeighbors = st.evaluations > 0
                        ? pairs / (static_cast<double>(st.evaluations) *
                                   std::max<double>(1.0, static_cast<double>(particles())))
                        : 0.0;
  return r;
}

template <int Dim>
void Simulation<Dim>::finish(RunLog& log, const RunOptions& options, Clock::time_point wall0,
                             int stopSignal) {
  const RunReport r = report(wall0);
  log.summary(summaryLines(r, options, stopSignal));
  if (mpi_.root()) writeSummary(r, options, stopSignal);
}

// The lines a run ends with, on the terminal and in the log.
template <int Dim>
std::vector<std::string>
Simulation<Dim>::summaryLines(const RunReport& r, const RunOptions& options, int stopSignal) const {
  const auto& st = method_->stats();
  // The share of each stepping phase (checkpoints have their own line).
  std::string shares;
  for (int p = 0; p < methods::kCheckpoint; ++p)
    shares += fmt::format("{}{} {:.1f}%", p ? " " : "", methods::kPhaseNames[p],
                          100 * st.phases[static_cast<methods::Phase>(p)] / r.wall);
  std::string memoryLine;
  for (const auto& [name, b] : r.memory)
    memoryLine += fmt::format("{}{} {:.0f}", memoryLine.empty() ? "" : ", ", name, b);
  std::vector<std::string> lines = {
      fmt::format("{}: {} steps to t = {:.6g} s (step {}) in {:.2f} s wall | {:.3g} "
                  "particle-steps/s ({:.3g} per core)",
                  stopSignal ? "stopped" : "done", r.steps, time_, step_, r.wall, r.rate,
                  r.rate / cores()),
      fmt::format(
          "conservation: mass {:.1e} | momentum {} | total energy {:.1e} (relative)", r.massErr,
          std::isnan(r.momErr) ? std::string("n/a (rigid walls)") : fmt::format("{:.1e}", r.momErr),
          r.energyErr),
      "time: " + shares};
  if (st.listBuilds > 0)
    lines.push_back(fmt::format("neighbors: {:.1f} per particle, searched {} times in {} "
                                "evaluations (skin {:g})",
                                r.meanNeighbors, st.listBuilds, st.evaluations,
                                deck_.solver.neighbor_skin));
  if (historyBins() > 0 && st.substeps > 0)
    lines.push_back(fmt::format(
        "time bins: {} substeps in {} steps, {:.1f}% of the rows of one step for all evaluated; "
        "the last step's bins {}",
        st.substeps, r.steps,
        100.0 * static_cast<double>(r.rowEvaluations) /
            std::max(1.0, static_cast<double>(particles()) * static_cast<double>(st.substeps)),
        fmt::join(st.binPopulation, ":")));
  lines.push_back(fmt::format("memory: {:.0f} B/particle allocated ({})", r.accounted, memoryLine));
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
        kCurveNames(deck_.decomposition.curve), kPartitionerNames(deck_.decomposition.partitioner),
        mpi_.size(), st.rebalances, st.imbalance, 100.0 * r.ghostFraction, r.crossPairs,
        st.migratedTotal, st.maxRankDistance,
        st.metisEdgeCut >= 0 ? fmt::format(" | METIS edge cut {} pairs", st.metisEdgeCut) : ""));
  lines.push_back(
      fmt::format("output in {} (open snapshots/series.xmf in ParaView)", dir_.string()));
  return lines;
}

// What every summary.json starts with, a failed run's too.
template <int Dim> Json Simulation<Dim>::summaryHead(const RunOptions& options) const {
  Json j;
  j["deck"] = options.deckPath;
  j["title"] = deck_.run.title;
  j["spall_version"] = BuildInfo::version();
  j["git_revision"] = BuildInfo::gitRevision();
  j["command_line"] = options.commandLine;
  j["output"] = dir_.string();
  j["ranks"] = mpi_.size();
  j["threads_per_rank"] = threadCount();
  j["dimension"] = Dim;
  j["particles"] = particles();
  j["steps"] = step_;
  j["time"] = time_;
  return j;
}

// summary.json (rank 0), through nlohmann's writer: any title or path is valid JSON (UTF-8 kept;
// bytes that are not UTF-8 are replaced rather than refused).
template <int Dim> void Simulation<Dim>::writeSummaryFile(const Json& j) const {
  const fs::path tmp = dir_ / "summary.json.tmp";
  {
    std::ofstream out(tmp);
    out << j.dump(2, ' ', false, Json::error_handler_t::replace) << "\n";
    if (!out) throw RunError("cannot write " + tmp.string());
  }
  fs::rename(tmp, dir_ / "summary.json");
}

// A failed run's summary.json: its status and the failure's message, where it stopped.
template <int Dim>
void Simulation<Dim>::writeFailureSummary(const RunOptions& options,
                                          const std::string& message) const {
  Json j = summaryHead(options);
  j["status"] = "failed";
  j["failure"] = message;
  j["wall_seconds"] = round6(std::chrono::duration<double>(Clock::now() - runStart_).count());
  writeSummaryFile(j);
}

template <int Dim>
void Simulation<Dim>::writeSummary(const RunReport& r, const RunOptions& options,
                                   int stopSignal) const {
  const auto& st = method_->stats();
  const auto& phases = st.phases;
  Json memoryParts = Json::object();
  for (const auto& [name, b] : r.memory) memoryParts[name] = round1(b);
  memoryParts["accounted"] = round1(r.accounted);
  Json phaseSeconds = Json::object();
  for (int p = 0; p < methods::kPhaseCount; ++p)
    phaseSeconds[methods::kPhaseNames[p]] = round6(phases[static_cast<methods::Phase>(p)]);
  phaseSeconds["other"] = round6(std::max(0.0, r.wall - phases.total()));
  Json checkpoint;
  checkpoint["written"] = checkpointsWritten_;
  checkpoint["bytes"] = checkpointBytes_;
  checkpoint["bytes_per_particle"] =
      round1(static_cast<double>(checkpointBytes_) /
             std::max<double>(1.0, static_cast<double>(particles())));
  checkpoint["write_seconds"] = round6(checkpointWriteSeconds_);
  checkpoint["write_bytes"] = checkpointWriteBytes_;
  checkpoint["read_seconds"] = round6(checkpointReadSeconds_);
  checkpoint["read_bytes"] = checkpointReadBytes_;
  checkpoint["restarted_from"] = resumedFrom_;
  checkpoint["changed_on_restart"] = restartChanges_; // the bodies that had not joined yet
  checkpoint["ranks_written"] = checkpointRanks_;
  Json decomposition;
  decomposition["curve"] = std::string(kCurveNames(deck_.decomposition.curve));
  decomposition["partitioner"] = std::string(kPartitionerNames(deck_.decomposition.partitioner));
  decomposition["rebalances"] = st.rebalances;
  decomposition["imbalance"] = round6(st.imbalance);
  decomposition["ghost_fraction_max"] = round6(r.ghostFraction);
  decomposition["migrated"] = st.migratedTotal;
  decomposition["max_rank_distance"] = st.maxRankDistance;
  decomposition["pairs_across_ranks"] = r.crossPairs;
  decomposition["metis_edge_cut"] = st.metisEdgeCut;
  decomposition["reproducible"] = deck_.decomposition.reproducible;
  Json conservation;
  conservation["mass_relative"] = number(r.massErr);
  conservation["momentum_relative"] = number(r.momErr);
  conservation["energy_relative"] = number(r.energyErr);
  Json j = summaryHead(options);
  j["wall_seconds"] = round6(r.wall);
  j["particle_steps_per_second"] = number(r.rate);
  j["particle_steps_per_second_per_core"] = number(r.rate / cores());
  j["status"] = stopSignal ? "stopped" : "finished";
  j["steps_this_run"] = r.steps;
  j["mean_neighbors"] = number(std::round(r.meanNeighbors * 1e3) / 1e3);
  j["neighbor_searches"] = st.listBuilds;
  j["evaluations"] = st.evaluations;
  j["peak_rss_bytes"] = r.peak;
  j["baseline_rss_bytes"] = r.base;
  j["bytes_per_particle"] =
      round1(particles() > 0 ? static_cast<double>(r.peak - std::min(r.peak, r.base)) /
                                   static_cast<double>(particles())
                             : 0.0);
  j["memory_parts"] = memoryParts;
  j["phases"] = phaseSeconds;
  j["checkpoint"] = checkpoint;
  j["decomposition"] = decomposition;
  j["conservation"] = conservation;
  // The work against N x steps: rows whose rates were computed over particles times substeps.
  Json bins;
  bins["bins"] = deck_.solver.time_bins;
  bins["substeps"] = st.substeps;
  bins["row_evaluations"] = r.rowEvaluations;
  bins["particle_substeps"] = static_cast<double>(particles()) * static_cast<double>(st.substeps);
  bins["populations"] = st.binPopulation;
  j["time_bins"] = bins;
  writeSummaryFile(j);
}

template class Simulation<1>;
template class Simulation<2>;
template class Simulation<3>;

} // namespace spall::app
