#include "spall/parallel/Mpi.hpp"

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace spall::parallel {

void broadcast(std::string& s, int root, MPI_Comm comm) {
  unsigned long long length = s.size();
  MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, root, comm);
  s.resize(static_cast<std::size_t>(length));
  if (length > 0) MPI_Bcast(s.data(), static_cast<int>(length), MPI_CHAR, root, comm);
}

MpiContext::MpiContext(MPI_Comm comm) : comm_(comm) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
}

double MpiContext::min(double v) const {
  double r;
  MPI_Allreduce(&v, &r, 1, MPI_DOUBLE, MPI_MIN, comm_);
  return r;
}
double MpiContext::max(double v) const {
  double r;
  MPI_Allreduce(&v, &r, 1, MPI_DOUBLE, MPI_MAX, comm_);
  return r;
}
double MpiContext::sum(double v) const {
  sumInRankOrder({&v, 1});
  return v;
}
std::uint64_t MpiContext::sum(std::uint64_t v) const {
  std::uint64_t r;
  MPI_Allreduce(&v, &r, 1, MPI_UINT64_T, MPI_SUM, comm_);
  return r;
}

void MpiContext::sumInRankOrder(std::span<double> values) const {
  if (size_ == 1) return;
  const int n = static_cast<int>(values.size());
  std::vector<double> all(static_cast<std::size_t>(n) * static_cast<std::size_t>(size_));
  MPI_Allgather(values.data(), n, MPI_DOUBLE, all.data(), n, MPI_DOUBLE, comm_);
  for (int k = 0; k < n; ++k) {
    double s = 0.0;
    for (int r = 0; r < size_; ++r) s += all[static_cast<std::size_t>(r * n + k)];
    values[static_cast<std::size_t>(k)] = s;
  }
}

namespace {

// A singleton talks to no other process, yet Open MPI's default choice of point-to-point layer
// first tries the cm layer (libfabric's providers) and UCX: 0.2 s of a 0.25 s start on a machine
// with neither (and ob1 is then what it picks). A singleton asks for ob1 at once, unless the user
// chose a layer.
bool pmlChosenHere = false;

// The session directory of a singleton (include/spall/parallel/Mpi.hpp); "" when none is set.
std::string preparePrivateSingleton() {
  for (const char* launched : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(launched)) return {};
  for (const char* given : {"OMPI_MCA_ess_singleton_isolated", "OMPI_MCA_orte_tmpdir_base"})
    if (std::getenv(given)) return {};
  const char* tmp = std::getenv("TMPDIR");
  std::string name = std::string(tmp && *tmp ? tmp : "/tmp") + "/spall-mpi-XXXXXX";
  if (!::mkdtemp(name.data())) return {}; // an ordinary singleton then
  ::setenv("OMPI_MCA_orte_tmpdir_base", name.c_str(), 1);
  ::setenv("OMPI_MCA_ess_singleton_isolated", "1", 1);
  if (!std::getenv("OMPI_MCA_pml")) {
    ::setenv("OMPI_MCA_pml", "ob1", 1);
    pmlChosenHere = true;
  }
  return name;
}

// A child process (a test's `spall run`, an mpirun) makes its own choices.
void singletonStarted(const std::string& dir) {
  if (dir.empty()) return;
  ::unsetenv("OMPI_MCA_orte_tmpdir_base");
  ::unsetenv("OMPI_MCA_ess_singleton_isolated");
  if (pmlChosenHere) ::unsetenv("OMPI_MCA_pml");
}

void removeSessionBase(const std::string& dir) {
  if (dir.empty()) return;
  std::error_code ec; // what Open MPI left (it removes its own tree at MPI_Finalize)
  std::filesystem::remove_all(dir, ec);
}

} // namespace

MpiSession::MpiSession(int& argc, char**& argv) : sessionBase_(preparePrivateSingleton()) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  singletonStarted(sessionBase_);
}
MpiSession::MpiSession() : sessionBase_(preparePrivateSingleton()) {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  singletonStarted(sessionBase_);
}
MpiSession::~MpiSession() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
  removeSessionBase(sessionBase_);
}

} // namespace spall::parallel
