#include "spall/app/SystemInfo.hpp"
#include "spall/io/Deck.hpp"
#include "spall/io/DeckKeys.hpp"

#include <Eigen/Core>
#include <fmt/format.h>
#include <fstream>
#include <hdf5.h>
#include <metis.h>
#include <mpi.h>
#include <toml++/toml.h>
#include <unistd.h>

namespace spall::app {

namespace {
std::size_t statusKiB(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::string k = std::string(key) + ":";
  while (std::getline(in, line)) {
    if (line.rfind(k, 0) == 0) return std::stoull(line.substr(k.size())) * 1024;
  }
  return 0;
}
} // namespace

std::size_t residentBytes() {
  return statusKiB("VmRSS");
}
std::size_t peakResidentBytes() {
  return statusKiB("VmHWM");
}
std::size_t availableMemoryBytes() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  std::size_t kib = 0;
  while (in >> key >> kib) {
    if (key == "MemAvailable:") return kib * 1024;
    in.ignore(256, '\n');
  }
  return static_cast<std::size_t>(sysconf(_SC_PHYS_PAGES)) *
         static_cast<std::size_t>(sysconf(_SC_PAGE_SIZE));
}

namespace {

// "a, b, c" of an enum's names, without `skip` (a name that is no model, e.g. "none").
std::string joinNames(const std::vector<std::string_view>& all, std::string_view skip) {
  std::string out;
  for (auto n : all)
    if (n != skip) out += (out.empty() ? "" : ", ") + std::string(n);
  return out;
}

template <class E, std::size_t N>
std::string names(const NameTable<E, N>& table, std::string_view skip = "none") {
  return joinNames(table.names(), skip);
}

// The types of a typed table, from its key tables (io/keys/).
std::string types(std::string_view path) {
  return joinNames(io::deckTypeNames(path), "none");
}

// What this build runs, from the name tables the deck reader parses with: a new model is
// listed where it is registered.
std::string featureList() {
  return fmt::format(
      "dimensions 1/2/3, axisymmetric rz; solvers: {} ({}; {}); kernels: {}; EOS: {}; "
      "porosity: {}; strength: {}; damage: {}; erosion: {}; boundaries: {} (with [damping]); "
      "MPI decomposition, checkpoint/restart; output: HDF5 + XDMF, CSV, penetration.csv; "
      "spall element, spall history, spall keys; bodies that join at insert_time, [[jet]] "
      "files",
      names(kSolverMethodNames), names(kMpmShapeNames), names(kMpmTransferNames),
      names(kKernelNames), types("material.eos"), types("material.porosity"),
      types("material.strength"), types("material.damage"), names(materials::kErosionNames),
      names(kBoundaryTypeNames));
}

// `text` in lines of at most 100 characters, the first after `head`, the others indented as far.
std::string wrapped(const std::string& head, const std::string& text) {
  const std::string indent(head.size(), ' ');
  std::string out = head, line;
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t end = text.find(' ', at);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(at, end - at);
    if (!line.empty() && head.size() + line.size() + 1 + word.size() > 100) {
      out += line + "\n" + indent;
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
    at = end + 1;
  }
  return out + line + "\n";
}

} // namespace

std::string infoText() {
  char mpiVersion[MPI_MAX_LIBRARY_VERSION_STRING];
  int len = 0;
  MPI_Get_library_version(mpiVersion, &len);
  std::string mpi(mpiVersion, static_cast<std::size_t>(len));
  if (auto nl = mpi.find('\n'); nl != std::string::npos) mpi.resize(nl);
  unsigned maj, min, rel;
  H5get_libversion(&maj, &min, &rel);
  std::string s;
  s += fmt::format("spall {} (git {})\n", BuildInfo::version(), BuildInfo::gitRevision());
  s += fmt::format("compiler   {} ({}), C++{}\n", BuildInfo::compiler(), BuildInfo::buildType(),
                   __cplusplus / 100 % 100);
  s += fmt::format("MPI        {}\n", mpi);
  s += fmt::format("HDF5       {}.{}.{} (parallel{})\n", maj, min, rel,
                   H5_HAVE_PARALLEL ? "" : ": NO");
  s += fmt::format("METIS      {}.{}.{}\n", METIS_VER_MAJOR, METIS_VER_MINOR, METIS_VER_SUBMINOR);
  s += fmt::format("Eigen      {}.{}.{}\n", EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION,
                   EIGEN_MINOR_VERSION);
  s += fmt::format("toml++     {}.{}.{}\n", TOML_LIB_MAJOR, TOML_LIB_MINOR, TOML_LIB_PATCH);
  s += wrapped("features   ", featureList());
  return s;
}

} // namespace spall::app
