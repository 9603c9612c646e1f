#include "spall/app/CheckpointFiles.hpp"

#include "spall/core/Error.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fmt/format.h>
#include <fstream>
#include <sstream>

namespace spall::app {

namespace fs = std::filesystem;

namespace {

// Step number of "ckpt_NNNNNN.h5", or -1 for any other name.
std::int64_t stepOf(const std::string& name) {
  if (name.size() < 9 || name.rfind("ckpt_", 0) != 0 || name.substr(name.size() - 3) != ".h5")
    return -1;
  const std::string digits = name.substr(5, name.size() - 8);
  if (digits.empty() || !std::all_of(digits.begin(), digits.end(), ::isdigit)) return -1;
  return std::strtoll(digits.c_str(), nullptr, 10);
}

// Complete checkpoints in `dir`, newest (highest step) first.
std::vector<fs::path> checkpointsNewestFirst(const fs::path& dir) {
  std::vector<std::pair<std::int64_t, fs::path>> found;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (const auto s = stepOf(e.path().filename().string()); s >= 0 && e.is_regular_file())
      found.emplace_back(s, e.path());
  std::sort(found.begin(), found.end(),
            [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<fs::path> out;
  for (auto& f : found) out.push_back(f.second);
  return out;
}

void syncFile(const fs::path& p, bool directory) {
  const int fd = ::open(p.c_str(), directory ? O_RDONLY | O_DIRECTORY : O_RDONLY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

// Writes `text` to `file` through a temporary and a rename.
void replaceFile(const fs::path& file, const std::string& text) {
  const fs::path tmp = file.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    if (!out)
      throw RunError(fmt::format("cannot write {}: {}", tmp.string(), std::strerror(errno)));
  }
  syncFile(tmp, false);
  std::error_code ec;
  fs::rename(tmp, file, ec);
  if (ec)
    throw RunError(
        fmt::format("cannot rename {} to {}: {}", tmp.string(), file.string(), ec.message()));
  syncFile(file.parent_path().empty() ? fs::path(".") : file.parent_path(), true);
}

std::string latestTarget(const fs::path& checkpointDir) {
  std::ifstream in(checkpointDir / "latest");
  std::string name;
  if (in) std::getline(in, name);
  while (!name.empty() && (name.back() == '\r' || name.back() == ' ')) name.pop_back();
  return name;
}

// Keeps the header and the rows whose first column passes `keep`.
template <class Keep> void truncateCsv(const fs::path& file, Keep keep) {
  std::ifstream in(file);
  if (!in) return;
  std::string line, out;
  bool header = true;
  while (std::getline(in, line)) {
    if (header || (!line.empty() && keep(line.substr(0, line.find(','))))) out += line + "\n";
    header = false;
  }
  in.close();
  replaceFile(file, out);
}

} // namespace

std::string checkpointFileName(std::int64_t step) {
  return fmt::format("ckpt_{:06d}.h5", step);
}

void publishLatest(const fs::path& checkpointDir, const std::string& fileName) {
  replaceFile(checkpointDir / "latest", fileName + "\n");
}

void pruneCheckpoints(const fs::path& checkpointDir, int keep) {
  const std::string latest = latestTarget(checkpointDir);
  const auto all = checkpointsNewestFirst(checkpointDir);
  std::error_code ec;
  for (std::size_t k = static_cast<std::size_t>(std::max(keep, 1)); k < all.size(); ++k)
    if (all[k].filename().string() != latest) fs::remove(all[k], ec);
}

void removeStaleTemporaries(const fs::path& checkpointDir) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(checkpointDir, ec))
    if (e.path().extension() == ".tmp") fs::remove(e.path(), ec);
}

RestartCandidates restartCandidates(const fs::path& outputDir, const std::string& restart) {
  RestartCandidates c;
  if (restart != "latest") {
    c.files.push_back(restart);
    return c;
  }
  c.fallback = true;
  const fs::path dir = outputDir / "checkpoints";
  const fs::path pointer = dir / "latest";
  const std::string target = latestTarget(dir);
  if (!fs::exists(pointer))
    c.problem = fmt::format("{} does not exist", pointer.string());
  else if (target.empty())
    c.problem = fmt::format("{} is empty", pointer.string());
  else if (!fs::exists(dir / target))
    c.problem = fmt::format("{} names {}, which does not exist", pointer.string(), target);
  if (c.problem.empty()) c.files.push_back(dir / target);
  for (const auto& p : checkpointsNewestFirst(dir))
    if (c.files.empty() || p != c.files.front()) c.files.push_back(p);
  return c;
}

void truncateHistory(const fs::path& file, std::int64_t step) {
  truncateCsv(file, [step](const std::string& first) {
    char* end = nullptr;
    const long long s = std::strtoll(first.c_str(), &end, 10);
    return end != first.c_str() && s <= step;
  });
}

void truncateProbes(const fs::path& file, double time) {
  // Times are written with 17 significant digits, which read back exactly.
  truncateCsv(file, [time](const std::string& first) {
    char* end = nullptr;
    const double t = std::strtod(first.c_str(), &end);
    return end != first.c_str() && t <= time;
  });
}

void removeSnapshotsFrom(const fs::path& snapshotDir, int first) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(snapshotDir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("snap_", 0) != 0) continue;
    // snap_NNNNNN.h5, .xmf, _grid.xmf (and their .tmp)
    std::size_t end = 5;
    while (end < name.size() && std::isdigit(static_cast<unsigned char>(name[end]))) ++end;
    const std::string digits = name.substr(5, end - 5);
    if (digits.empty() || (end < name.size() && name[end] != '.' && name[end] != '_')) continue;
    if (std::atoi(digits.c_str()) >= first || name.ends_with(".tmp")) fs::remove(e.path(), ec);
  }
}

} // namespace spall::app
