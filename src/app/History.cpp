#include "spall/app/History.hpp"

#include "spall/core/Error.hpp"
#include "spall/io/FTable.hpp"
#include "spall/io/Snapshot.hpp"

#include <algorithm>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/os.h>
#include <fstream>

namespace spall::app {

namespace fs = std::filesystem;

namespace {

// The rows from the snapshots that hold the particle's deformation gradient, in time order.
std::vector<io::FTableRow> fromSnapshots(const fs::path& dir, std::uint64_t particle) {
  std::vector<fs::path> snaps;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir / "snapshots", ec))
    if (e.path().extension() == ".h5" && e.path().filename().string().rfind("snap_", 0) == 0)
      snaps.push_back(e.path());
  std::sort(snaps.begin(), snaps.end());
  std::vector<io::FTableRow> rows;
  for (const auto& path : snaps) {
    const io::SnapshotData d = io::readSnapshot(path.string());
    const auto F = d.fields.find("deformation_gradient");
    if (F == d.fields.end()) continue;
    const auto it = std::find(d.id.begin(), d.id.end(), particle);
    if (it == d.id.end()) continue;
    const std::size_t i = static_cast<std::size_t>(it - d.id.begin());
    io::FTableRow row;
    row.t = d.time;
    // The reader gives tensors row-major: F(a, b) at 3 a + b.
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) row.F(a, b) = F->second[9 * i + 3 * a + b];
    rows.push_back(row);
  }
  return rows;
}

} // namespace

void writeHistory(const HistoryOptions& o) {
  const fs::path dir(o.outputDir);
  if (!fs::is_directory(dir)) throw UsageError(o.outputDir + " is not a run's output directory");
  if (o.output != "-" && fs::exists(o.output) && !o.overwrite)
    throw UsageError(o.output + " exists; --overwrite replaces it");
  const fs::path recorded = dir / "particles" / fmt::format("particle_{}.ftable", o.particle);
  std::vector<io::FTableRow> rows;
  std::string source;
  if (fs::exists(recorded)) {
    rows = io::readFTable(recorded.string()).rows;
    source = "recorded every step";
  } else {
    rows = fromSnapshots(dir, o.particle);
    source = "from the snapshots";
  }
  if (rows.size() < 2)
    throw UsageError(fmt::format(
        "particle {} has no deformation history in {}: list it in [output] record_particles "
        "(every step), or add deformation_gradient to output.fields (every snapshot)",
        o.particle, o.outputDir));
  std::string text = fmt::format("# particle {} of {}, {}\n# t F11 F12 F13 F21 F22 F23 F31 F32 "
                                 "F33\n",
                                 o.particle, o.outputDir, source);
  for (const auto& r : rows) {
    text += fmt::format("{:.17g}", r.t);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) text += fmt::format(" {:.17g}", r.F(a, b));
    text += "\n";
  }
  if (o.output == "-") {
    fmt::print("{}", text);
    return;
  }
  std::ofstream(o.output) << text;
}

} // namespace spall::app
