#include "Simulation.hpp"

#include "spall/app/Setup.hpp"
#include "spall/app/StopSignals.hpp"
#include "spall/app/SystemInfo.hpp"
#include "spall/io/FieldUnits.hpp"
#include "spall/io/Snapshot.hpp"
#include "spall/io/Xdmf.hpp"

#include <array>
#include <cmath>
#include <cstring>
#include <fmt/format.h>
#include <fstream>

// What a run writes as it goes: snapshots, history.csv, probes.csv, fragments and penetration,
// and the banner (the closing summary: RunSummary.cpp).
namespace spall::app {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFragmentsHeader = "time,fragment,particles,mass,x,y,z,vx,vy,vz";
constexpr const char* kPenetrationHeader = "time,depth,rate,tip_velocity";

struct HistoryRow {
  std::int64_t step = 0;
  double time = 0.0, dt = 0.0;
  std::uint64_t particles = 0;
  diagnostics::Totals totals;
  double wall = 0.0, imbalance = 1.0;
  std::uint64_t ghosts = 0, migrated = 0;
  double externalWork = 0.0; // by a confining pressure and damping, since t = 0
  // The step's work (solver.time_bins): its substeps, the rows whose rates they computed (N a
  // substep without bins), and each bin's particles at its start (columns bin_K with bins only).
  std::uint64_t substeps = 0, evaluatedRows = 0;
  std::vector<std::uint64_t> bins;
};

// The columns of history.csv, in order: the header and every row read this one list.
std::vector<std::pair<const char*, std::string>> historyColumns(const HistoryRow& r) {
  const auto g = [](double v) { return fmt::format("{:.17g}", v); };
  const auto& t = r.totals;
  std::vector<std::pair<const char*, std::string>> columns{
      {"step", fmt::format("{}", r.step)},
      {"time", g(r.time)},
      {"dt", g(r.dt)},
      {"particles", fmt::format("{}", r.particles)},
      {"mass", g(t.mass)},
      {"momentum_x", g(t.momentum[0])},
      {"momentum_y", g(t.momentum[1])},
      {"momentum_z", g(t.momentum[2])},
      {"kinetic_energy", g(t.kinetic)},
      {"internal_energy", g(t.internal)},
      {"total_energy", g(t.total())},
      {"wall_seconds", fmt::format("{:.3f}", r.wall)},
      {"imbalance", fmt::format("{:.4f}", r.imbalance)},
      {"ghosts", fmt::format("{}", r.ghosts)},
      {"migrated", fmt::format("{}", r.migrated)},
      {"external_work", g(r.externalWork)},
      {"substeps", fmt::format("{}", r.substeps)},
      {"evaluated_rows", fmt::format("{}", r.evaluatedRows)}};
  static constexpr std::array<const char*, 12> kBinNames{"bin_0", "bin_1", "bin_2",  "bin_3",
                                                         "bin_4", "bin_5", "bin_6",  "bin_7",
                                                         "bin_8", "bin_9", "bin_10", "bin_11"};
  for (std::size_t k = 0; k < r.bins.size() && k < kBinNames.size(); ++k)
    columns.emplace_back(kBinNames[k], fmt::format("{}", r.bins[k]));
  return columns;
}

} // namespace

// history.csv's bin_K columns: one a bin with solver.time_bins above 1 (methods/TimeBins.hpp).
template <int Dim> std::size_t Simulation<Dim>::historyBins() const {
  const int bins = deck_.solver.time_bins; // (MPM refuses bins: io/DeckSolver.cpp)
  return bins > 1 ? static_cast<std::size_t>(bins) : 0;
}

// Creates the output directory's files, or continues them after a restart (whatever a crashed
// run wrote after its checkpoint goes).
template <int Dim> void Simulation<Dim>::openLogs(const fs::path& dir, bool resumed, RunLog& log) {
  if (resumed) {
    // A chain restarted from a checkpoint in another directory lacks the earlier snapshots
    // here: series.xmf lists only what this directory holds.
    std::vector<char> keep(series_.size(), 1);
    if (mpi_.root())
      for (std::size_t k = 0; k < series_.size(); ++k)
        keep[k] = fs::exists(dir / "snapshots" / series_[k].second) ? 1 : 0;
    MPI_Bcast(keep.data(), static_cast<int>(keep.size()), MPI_CHAR, 0, mpi_.comm());
    std::size_t kept = 0;
    for (std::size_t k = 0; k < series_.size(); ++k)
      if (keep[k]) series_[kept++] = series_[k];
    if (kept < series_.size())
      log.note(fmt::format("{} earlier snapshot{} of this chain are not in {}: series.xmf "
                           "lists the ones that are",
                           series_.size() - kept, series_.size() - kept > 1 ? "s" : "",
                           (dir / "snapshots").string()));
    series_.resize(kept);
  }
  if (mpi_.root()) {
    fs::create_directories(dir / "snapshots");
    fs::create_directories(dir / "checkpoints");
    log.attach((dir / "run.log").string());
    std::ofstream(dir / "deck.toml") << deckAsRun(deck_, dir.string());
    std::string historyHeader;
    HistoryRow names;
    names.bins.resize(historyBins());
    for (const auto& [name, value] : historyColumns(names))
      historyHeader += (historyHeader.empty() ? "" : ",") + std::string(name);
    if (resumed) {
      // Whatever a crashed run wrote after its checkpoint goes; the rest continues.
      truncateHistory(dir / "history.csv", step_);
      truncateProbes(dir / "probes.csv", time_);
      truncateProbes(dir / "fragments.csv", time_); // rows start with the time too
      truncateProbes(dir / "penetration.csv", time_);
      removeSnapshotsFrom(dir / "snapshots", snapshotIndex_);
      writeSeries(dir / "snapshots");
      removeStaleTemporaries(dir / "checkpoints");
      history_ = io::CsvLog::append((dir / "history.csv").string(), historyHeader);
      if (!probes_->empty())
        probesCsv_ = io::CsvLog::append((dir / "probes.csv").string(), "time,probe,field,value");
      if (deck_.fragments)
        fragmentsCsv_ = io::CsvLog::append((dir / "fragments.csv").string(), kFragmentsHeader);
      if (penetration_)
        penetrationCsv_ =
            io::CsvLog::append((dir / "penetration.csv").string(), kPenetrationHeader);
    } else {
      history_ = io::CsvLog((dir / "history.csv").string(), historyHeader);
      if (!probes_->empty())
        probesCsv_ = io::CsvLog((dir / "probes.csv").string(), "time,probe,field,value");
      if (deck_.fragments)
        fragmentsCsv_ = io::CsvLog((dir / "fragments.csv").string(), kFragmentsHeader);
      if (penetration_)
        penetrationCsv_ = io::CsvLog((dir / "penetration.csv").string(), kPenetrationHeader);
    }
  }
  MPI_Barrier(mpi_.comm());
}

// ---- output ---------------------------------------------------------------------------------
template <int Dim> void Simulation<Dim>::resolveOutputFields() {
  std::vector<std::string> available;
  for (const auto& c : store_.columns())
    if (c->info().flags & kOutput) available.push_back(c->info().name);
  available.push_back("smoothing");
  available.push_back("stress");
  if (Dim == 2) available.push_back("stress_hoop");
  if (f_.damageTensor.valid()) available.push_back("damage_tensor");
  if (deck_.output.fields.empty()) {
    outputFields_ = available;
    return;
  }
  for (const auto& name : deck_.output.fields) {
    if (std::find(available.begin(), available.end(), name) == available.end()) {
      std::string list;
      for (const auto& a : available) list += (list.empty() ? "" : ", ") + a;
      throw DeckError(deck_.output.where,
                      fmt::format("output field '{}' does not exist (available: {})", name, list));
    }
  }
  outputFields_ = deck_.output.fields;
  // Ids and positions are always written: without them a snapshot cannot be read.
  for (const char* must : {"position", "id"})
    if (std::find(outputFields_.begin(), outputFields_.end(), must) == outputFields_.end())
      outputFields_.insert(outputFields_.begin(), must);
}

namespace {
// The /grid datasets: each node's lattice index, place, mass, centre-of-mass velocity, the
// stress's force and its count of velocity fields (solvers/GridNodes.hpp).
template <int Dim>
std::vector<io::SnapshotField> gridSnapshotFields(const solvers::GridNodes<Dim>& g) {
  const std::vector<int> vec{Dim};
  return {{{"index", ScalarType::I64, vec, kOutput}, g.index.data()},
          {{"position", ScalarType::F64, vec, kOutput}, g.x.data()},
          {{"mass", ScalarType::F64, {}, kOutput}, g.mass.data()},
          {{"velocity", ScalarType::F64, vec, kOutput}, g.velocity.data()},
          {{"force", ScalarType::F64, vec, kOutput}, g.force.data()},
          {{"fields", ScalarType::I32, {}, kOutput}, g.fields.data()}};
}
} // namespace

template <int Dim> bool Simulation<Dim>::snapshotDue() const {
  if (deck_.output.every_steps > 0 && step_ % deck_.output.every_steps == 0) return true;
  return deck_.output.every > 0.0 && time_ >= nextSnapshotTime_ * (1.0 - 1e-12);
}

template <int Dim> void Simulation<Dim>::writeSnapshot(bool write) {
  method_->stats().phases.time(methods::kOutput, [&] {
    if (!write) return advanceSnapshotClock(fmt::format("snap_{:06d}", snapshotIndex_));
    if (deck_.fragments) writeFragments();
    if (penetration_) writePenetration();
    // MPM's grid (output.grid) first: its ghosts may grow the store, and the particle fields
    // below point into it.
    solvers::GridNodes<Dim> grid;
    if (deck_.output.grid) grid = method_->gridNodes();
    const std::size_t n = store_.localCount();
    std::vector<io::SnapshotField> fields;
    std::vector<FieldInfo> infos;
    for (const auto& name : outputFields_) {
      const FieldInfo tensor{name, ScalarType::F64, {Dim, Dim}, kOutput};
      if (name == "smoothing") {
        // H = I/h for SPH, the full tensor for ASPH (docs/reference.md: the H tensor).
        const auto h = store_[f_.h];
        const auto Hs = f_.anisotropic() ? store_[f_.H] : std::span<const Tensor<Dim>>{};
        // The rows buffer has no alignment guarantee for fixed-size Eigen types: write doubles.
        fields.push_back({tensor, nullptr, [h, Hs, n](void* rows) {
                            auto* out = static_cast<double*>(rows);
                            for (std::size_t i = 0; i < n; ++i) {
                              const Tensor<Dim> H =
                                  Hs.empty() ? (Tensor<Dim>::Identity() / h[i]).eval() : Hs[i];
                              std::memcpy(out + i * Dim * Dim, H.data(), sizeof(H));
                            }
                          }});
      } else if (name == "stress") {
        // Full Cauchy stress -p I + S (the Dim x Dim block); S = 0 on the hydro path.
        const auto p = store_[f_.p];
        const auto S = f_.hasStrength() ? store_[f_.S] : std::span<const Tensor<3>>{};
        fields.push_back({tensor, nullptr, [p, S, n](void* rows) {
                            auto* sigma = static_cast<Tensor<Dim>*>(rows);
                            for (std::size_t i = 0; i < n; ++i) {
                              sigma[i] = -p[i] * Tensor<Dim>::Identity();
                              if (!S.empty()) sigma[i] += S[i].template topLeftCorner<Dim, Dim>();
                            }
                          }});
      } else if (name == "stress_hoop") {
        // sigma_tt = S_tt - p: rz's hoop stress (plane strain's out-of-plane stress).
        const auto p = store_[f_.p];
        const auto S = f_.hasStrength() ? store_[f_.S] : std::span<const Tensor<3>>{};
        fields.push_back(
            {FieldInfo{name, ScalarType::F64, {}, kOutput}, nullptr, [p, S, n](void* rows) {
               auto* out = static_cast<double*>(rows);
               for (std::size_t i = 0; i < n; ++i) out[i] = -p[i] + (S.empty() ? 0.0 : S[i](2, 2));
             }});
      } else if (name == "damage_tensor") {
        // Owen's damage tensor, the Dim x Dim block of the 3x3 the material update keeps.
        const auto D = store_[f_.damageTensor];
        fields.push_back({tensor, nullptr, [D, n](void* rows) {
                            auto* out = static_cast<double*>(rows);
                            for (std::size_t i = 0; i < n; ++i) {
                              const Tensor<Dim> block = D[i].template topLeftCorner<Dim, Dim>();
                              std::memcpy(out + i * Dim * Dim, block.data(), sizeof(block));
                            }
                          }});
      } else {
        const ColumnBase* c = store_.find(name);
        fields.push_back({c->info(), c->raw()});
      }
      infos.push_back(fields.back().info);
    }
    const bool rz = deck_.run.geometry == Geometry::RZ;
    for (auto& f : fields) f.unit = io::fieldUnit(f.info.name, Dim, rz);
    std::vector<io::SnapshotGroup> groups{{"particles", n, fields}};
    const io::XdmfPoints particles{"particles", mpi_.sum(static_cast<std::uint64_t>(n)), infos};
    // The grid's nodes as a second group of rows.
    std::vector<io::SnapshotField> gridFields;
    std::vector<FieldInfo> gridInfos;
    if (deck_.output.grid) {
      gridFields = gridSnapshotFields(grid);
      for (auto& g : gridFields) {
        g.unit = io::fieldUnit(g.info.name, Dim, rz);
        gridInfos.push_back(g.info);
      }
      groups.push_back({"grid", grid.size(), gridFields});
    }
    io::SnapshotAttributes attrs{
        time_, step_, Dim, BuildInfo::version(), io::geometryName(Dim, rz), io::axesName(Dim, rz),
        {},    {}};
    for (const auto& m : deck_.materials) attrs.materialNames.push_back(m.name);
    for (const auto& b : deck_.bodies) attrs.bodyNames.push_back(b.name);
    const std::string base = fmt::format("snap_{:06d}", snapshotIndex_);
    const fs::path snapDir = dir_ / "snapshots";
    io::writeSnapshot(mpi_.comm(), (snapDir / (base + ".h5")).string(), attrs, groups);
    const std::uint64_t nodes =
        deck_.output.grid ? mpi_.sum(static_cast<std::uint64_t>(grid.size())) : 0; // collective
    if (mpi_.root()) {
      io::writeSnapshotXdmf((snapDir / (base + ".xmf")).string(), base + ".h5", Dim, particles);
      if (deck_.output.grid)
        io::writeSnapshotXdmf((snapDir / (base + "_grid.xmf")).string(), base + ".h5", Dim,
                              {"grid", nodes, gridInfos});
    }
    advanceSnapshotClock(base);
    if (mpi_.root()) writeSeries(snapDir);
  });
}

// series.xmf (the particles) and, with output.grid, series_grid.xmf (the nodes) over the
// snapshots this directory holds.
template <int Dim> void Simulation<Dim>::writeSeries(const fs::path& snapDir) const {
  io::writeSeriesXdmf((snapDir / "series.xmf").string(), series_);
  if (!deck_.output.grid) return;
  auto nodes = series_;
  for (auto& [t, file] : nodes) file.replace(file.size() - 4, 4, "_grid.xmf");
  std::erase_if(nodes, [&](const auto& s) { return !fs::exists(snapDir / s.second); });
  io::writeSeriesXdmf((snapDir / "series_grid.xmf").string(), nodes);
}

// Friends of friends now: the `fragment` field of the snapshot about to be written, and the
// catalogue's rows in fragments.csv (rank 0), largest fragment first.
template <int Dim> void Simulation<Dim>::writeFragments() {
  const diagnostics::FragmentCatalogue cat =
      method_->findFragments(deck_.fragments->link_length, deck_.fragments->damage_threshold);
  if (!fragmentsCsv_.open()) return;
  for (std::size_t k = 0; k < cat.fragments.size(); ++k) {
    const auto& f = cat.fragments[k];
    fragmentsCsv_.row(
        fmt::format("{:.17g},{},{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}", time_,
                    k, f.particles, f.mass, f.x[0], f.x[1], f.x[2], f.v[0], f.v[1], f.v[2]));
  }
  fragmentsCsv_.flush();
}

// A row of penetration.csv at every history row and snapshot (once per time).
template <int Dim> void Simulation<Dim>::writePenetration() {
  if (time_ == lastPenetrationTime_) return;
  lastPenetrationTime_ = time_;
  const auto row = penetration_->measure(time_, store_, f_, mpi_);
  if (!row || !penetrationCsv_.open()) return;
  penetrationCsv_.row(fmt::format("{:.17g},{:.17g},{:.17g},{:.17g}", row->time, row->depth,
                                  row->rate, row->tipVelocity));
}

// The bookkeeping of a snapshot (kept on every rank alike: it is part of the checkpointed state).
// A replay (RunFailure.cpp) does it without writing the files again: the snapshot times set the
// steps, so the replay's steps stay the run's.
template <int Dim> void Simulation<Dim>::advanceSnapshotClock(const std::string& base) {
  series_.emplace_back(time_, base + ".xmf");
  ++snapshotIndex_;
  lastSnapshotStep_ = step_;
  // The next k every after now, as a product (a running sum drifts by ulps: the 24th of every
  // 2.5e-4 fell at 0.0060000000000000036, and a chain ending at 0.006 then left the longer run's
  // steps).
  const double every = deck_.output.every;
  if (every > 0.0) {
    double k = std::floor(time_ / every);
    while (k * every <= time_ * (1.0 + 1e-12)) k += 1.0;
    nextSnapshotTime_ = k * every;
  }
}

template <int Dim>
void Simulation<Dim>::record(double dt, std::int64_t step, Clock::time_point wall0) {
  method_->stats().phases.time(methods::kOutput, [&] {
    if (recorder_) recorder_->write(time_, store_, f_, mpi_); // every step
    if (step % deck_.output.history_every_steps != 0 && time_ < deck_.run.end_time) return;
    const auto t = diagnostics::computeTotals(store_, f_, mpi_);
    last_ = t;
    energyDue_ = true;
    const auto& stats = method_->stats();
    HistoryRow row{step, time_, dt, mpi_.sum(static_cast<std::uint64_t>(store_.localCount())), t,
                   // Wall seconds of the whole chain, so a restarted run's history reads on.
                   wallOffset_ + std::chrono::duration<double>(Clock::now() - wall0).count(),
                   stats.imbalance, mpi_.sum(static_cast<std::uint64_t>(stats.ghosts)),
                   stats.migrated, method_->externalWork(), stats.stepSubsteps,
                   mpi_.sum(stats.stepRowEvaluations), stats.binPopulation};
    row.bins.resize(historyBins()); // (step 0: none counted yet)
    if (history_.open()) {
      std::string line;
      for (const auto& [name, value] : historyColumns(row))
        line += (line.empty() ? "" : ",") + value;
      history_.row(line);
    }
    if (penetration_) writePenetration();
    if (!probes_->empty()) {
      const auto samples = probes_->sample(store_, f_, mpi_, method_->support());
      if (probesCsv_.open())
        for (const auto& s : samples)
          probesCsv_.row(fmt::format("{:.17g},{},{},{:.17g}", time_, s.probe, s.field, s.value));
    }
  });
}

template <int Dim> void Simulation<Dim>::banner(RunLog& log, const fs::path& dir) {
  std::vector<std::string> lines;
  lines.push_back(fmt::format("spall {} (git {}): {}", BuildInfo::version(),
                              BuildInfo::gitRevision(),
                              deck_.run.title.empty() ? deck_.path : deck_.run.title));
  lines.push_back(fmt::format("deck {} | {}D | {} | {} rank{} x {} thread{}", deck_.path, Dim,
                              methodSummary(deck_), mpi_.size(), mpi_.size() > 1 ? "s" : "",
                              threadCount(), threadCount() > 1 ? "s" : ""));
  for (std::size_t k = 0; k < bodies_.size(); ++k) {
    const auto& b = bodies_[k];
    lines.push_back(
        fmt::format("  body {:<16} {:>10} particles  mass {:.6g} kg  spacing {:.4g} m{}", b.name,
                    b.particles, b.mass, b.spacing, gradedText(deck_, k)));
  }
  lines.push_back(fmt::format("particles {} | memory ~{:.1f} MB | end time {:.6g} s | output {}",
                              particles(), memoryEstimate() / 1048576.0, deck_.run.end_time,
                              dir.string()));
  log.banner(lines);
}

template class Simulation<1>;
template class Simulation<2>;
template class Simulation<3>;

} // namespace spall::app
