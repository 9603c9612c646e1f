#include "spall/app/SystemInfo.hpp"

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
  s += "features   dimensions 1/2/3, axisymmetric rz; solvers: sph, asph, mpm (linear, gimp,\n"
       "           cpgimp, cpdi; flip, apic); kernels: cubic_spline, wendland_c2, wendland_c4;\n"
       "           EOS: ideal_gas, linear, mie_gruneisen, tillotson, p_alpha porosity; strength:\n"
       "           elastic, von_mises, johnson_cook, zerilli_armstrong, cap; damage: grady_kipp,\n"
       "           johnson_cook; boundaries: rigid_wall, periodic, pressure (with [damping]);\n"
       "           MPI decomposition, checkpoint/restart; output: HDF5 + XDMF, CSV,\n"
       "           penetration.csv; spall element, spall history; bodies that join at\n"
       "           insert_time, [[jet]] files\n";
  return s;
}

} // namespace spall::app
