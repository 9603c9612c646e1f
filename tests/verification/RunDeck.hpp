#pragma once
// Runs the spall executable on a deck, as a user would, and reads what it wrote.
#include "spall/io/Snapshot.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace spall::verification {

// strtod, unlike std::stod, accepts subnormal values (a probe can read 1e-320).
inline double parseDouble(const std::string& s) {
  return std::strtod(s.c_str(), nullptr);
}

inline std::string deckPath(const std::string& name) {
  return std::string(SPALL_SOURCE_DIR) + "/decks/" + name;
}

// Runs `spall run DECK --set ...` into a fresh directory under the system temp dir; returns it.
inline std::filesystem::path runSpall(const std::string& deck,
                                      const std::vector<std::string>& overrides,
                                      const std::string& tag, int* exitCode = nullptr) {
  // The process id keeps concurrent test runs (two build trees, ctest -j) apart.
  const auto dir = std::filesystem::temp_directory_path() /
                   ("spall_verify_" + tag + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::string cmd =
      std::string(SPALL_BINARY) + " run " + deck + " --quiet --output " + dir.string();
  for (const auto& o : overrides) cmd += " --set '" + o + "'";
  const int rc = std::system(cmd.c_str());
  if (exitCode) *exitCode = WEXITSTATUS(rc);
  return dir;
}

inline std::string lastSnapshot(const std::filesystem::path& dir) {
  std::string best;
  for (const auto& e : std::filesystem::directory_iterator(dir / "snapshots"))
    if (e.path().extension() == ".h5" && e.path().string() > best) best = e.path().string();
  return best;
}

// The snapshot whose time is closest to t.
inline std::string snapshotAt(const std::filesystem::path& dir, double t) {
  std::string best;
  double bestDt = 1e300;
  for (const auto& e : std::filesystem::directory_iterator(dir / "snapshots")) {
    if (e.path().extension() != ".h5") continue;
    const auto s = io::readSnapshot(e.path().string());
    if (std::abs(s.time - t) < bestDt) bestDt = std::abs(s.time - t), best = e.path().string();
  }
  return best;
}

struct ProbeSeries {
  std::vector<double> t, value;
};

// probes.csv as {probe: {field: series}}.
inline std::map<std::string, std::map<std::string, ProbeSeries>>
readProbes(const std::filesystem::path& dir) {
  std::map<std::string, std::map<std::string, ProbeSeries>> out;
  std::ifstream in(dir / "probes.csv");
  std::string line;
  std::getline(in, line); // header
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string t, probe, field, value;
    std::getline(ss, t, ',');
    std::getline(ss, probe, ',');
    std::getline(ss, field, ',');
    std::getline(ss, value, ',');
    auto& s = out[probe][field];
    s.t.push_back(parseDouble(t));
    s.value.push_back(parseDouble(value));
  }
  return out;
}

// history.csv as named columns.
inline std::map<std::string, std::vector<double>> readHistory(const std::filesystem::path& dir) {
  std::map<std::string, std::vector<double>> out;
  std::ifstream in(dir / "history.csv");
  std::string line, cell;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream hs(line);
  while (std::getline(hs, cell, ',')) names.push_back(cell);
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    for (std::size_t k = 0; k < names.size() && std::getline(ss, cell, ','); ++k)
      out[names[k]].push_back(parseDouble(cell));
  }
  return out;
}

// A number of summary.json by its key ("momentum_relative"); -1 where the key is absent or null.
inline double summaryNumber(const std::filesystem::path& dir, const std::string& key) {
  std::ifstream in(dir / "summary.json");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string quoted = "\"" + key + "\": ";
  const auto at = text.find(quoted);
  if (at == std::string::npos || text.compare(at + quoted.size(), 4, "null") == 0) return -1.0;
  return std::stod(text.substr(at + quoted.size()));
}

} // namespace spall::verification
