#include "spall/app/ParticleRecorder.hpp"

#include "spall/app/CheckpointFiles.hpp"
#include "spall/core/Error.hpp"

#include <fmt/format.h>
#include <mpi.h>

namespace spall::app {

namespace fs = std::filesystem;

namespace {

// A row: found, F (9, row by row), sigma (xx yy zz xy yz xz), density, energy, pressure,
// plastic strain, temperature, damage, the density and energy of the step's material update, and
// a cap material's plastic volumetric strain, cap position, porosity, pore pressure.
constexpr std::size_t kRow = 1 + 9 + 6 + 6 + 2 + 4;
constexpr int kVoigt[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};

} // namespace

template <int Dim>
ParticleRecorder<Dim>::ParticleRecorder(const OutputConfig& output)
    : ids_(output.record_particles), where_(output.recordWhere) {}

template <int Dim>
void ParticleRecorder<Dim>::check(const ParticleStore& s, const ParticleFields<Dim>& f,
                                  const parallel::MpiContext& mpi) const {
  if (ids_.empty()) return;
  const auto id = s[f.id];
  std::vector<std::uint64_t> found(ids_.size(), 0);
  for (std::size_t i = 0; i < s.localCount(); ++i)
    for (std::size_t k = 0; k < ids_.size(); ++k)
      found[k] += id[i] == static_cast<ParticleId>(ids_[k]);
  MPI_Allreduce(MPI_IN_PLACE, found.data(), static_cast<int>(found.size()), MPI_UINT64_T, MPI_SUM,
                mpi.comm());
  for (std::size_t k = 0; k < ids_.size(); ++k)
    if (found[k] != 1)
      throw DeckError(where_, fmt::format("'output.record_particles': no particle has id {} (ids "
                                          "run from 0 to the particle count - 1)",
                                          ids_[k]));
}

template <int Dim>
void ParticleRecorder<Dim>::open(const fs::path& dir, bool resumed, double time,
                                 const ParticleFields<Dim>& f, const parallel::MpiContext& mpi) {
  cap_ = f.hasCap();
  if (ids_.empty() || !mpi.root()) return;
  fs::create_directories(dir / "particles");
  std::string fHeader = "# t";
  for (int a = 1; a <= 3; ++a)
    for (int b = 1; b <= 3; ++b) fHeader += fmt::format(" F{}{}", a, b);
  std::string sHeader = "t,sxx,syy,szz,sxy,syz,sxz,density,specific_internal_energy,pressure,"
                        "plastic_strain,temperature,damage,update_density,"
                        "update_specific_internal_energy";
  if (cap_) sHeader += ",plastic_volumetric_strain,cap_position,porosity,pore_pressure";
  for (const std::int64_t id : ids_) {
    const fs::path table = dir / "particles" / fmt::format("particle_{}.ftable", id);
    const fs::path state = dir / "particles" / fmt::format("particle_{}.csv", id);
    if (resumed) {
      truncateProbes(table, time); // rows start with their time
      truncateProbes(state, time);
      tables_.push_back(io::CsvLog::append(table.string(), fHeader));
      states_.push_back(io::CsvLog::append(state.string(), sHeader));
    } else {
      tables_.emplace_back(table.string(), fHeader);
      states_.emplace_back(state.string(), sHeader);
    }
  }
}

template <int Dim>
void ParticleRecorder<Dim>::write(double time, const ParticleStore& s, const ParticleFields<Dim>& f,
                                  const parallel::MpiContext& mpi) {
  if (ids_.empty()) return;
  std::vector<double> rows(ids_.size() * kRow, 0.0);
  const auto id = s[f.id];
  for (std::size_t i = 0; i < s.localCount(); ++i)
    for (std::size_t k = 0; k < ids_.size(); ++k) {
      if (id[i] != static_cast<ParticleId>(ids_[k])) continue;
      double* r = rows.data() + k * kRow;
      r[0] = 1.0;
      const Tensor<3>& F = s[f.Fdef][i];
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) r[1 + 3 * a + b] = F(a, b);
      const Tensor<3> sigma = s[f.S][i] - s[f.p][i] * Tensor<3>::Identity();
      for (int c = 0; c < 6; ++c) r[10 + c] = sigma(kVoigt[c][0], kVoigt[c][1]);
      r[16] = s[f.rho][i];
      r[17] = s[f.e][i];
      r[18] = s[f.p][i];
      r[19] = s[f.plasticStrain][i];
      r[20] = s[f.temperature][i];
      r[21] = f.hasDamage() ? s[f.damage][i] : 0.0;
      r[22] = s[f.rhoUpdate][i];
      r[23] = s[f.eUpdate][i];
      if (cap_) {
        r[24] = s[f.volumetricStrain][i];
        r[25] = s[f.capPosition][i];
        r[26] = s[f.porosity][i];
        r[27] = s[f.porePressure][i];
      }
    }
  // One owner a particle: the sum is its row, exactly.
  MPI_Reduce(mpi.root() ? MPI_IN_PLACE : rows.data(), rows.data(), static_cast<int>(rows.size()),
             MPI_DOUBLE, MPI_SUM, 0, mpi.comm());
  if (!mpi.root()) return;
  for (std::size_t k = 0; k < ids_.size(); ++k) {
    const double* r = rows.data() + k * kRow;
    std::string table = fmt::format("{:.17g}", time), state = table;
    for (int c = 1; c < 10; ++c) table += fmt::format(" {:.17g}", r[c]);
    for (std::size_t c = 10; c < (cap_ ? kRow : kRow - 4); ++c)
      state += fmt::format(",{:.17g}", r[c]);
    tables_[k].row(table);
    states_[k].row(state);
  }
}

template class ParticleRecorder<1>;
template class ParticleRecorder<2>;
template class ParticleRecorder<3>;

} // namespace spall::app
