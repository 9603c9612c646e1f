#include "spall/app/ParticleRecorder.hpp"

#include "spall/app/CheckpointFiles.hpp"
#include "spall/core/Error.hpp"

#include <fmt/format.h>
#include <mpi.h>

namespace spall::app {

namespace fs = std::filesystem;

namespace {

// A row: found, F (9, row by row), sigma (xx yy zz xy yz xz), density, energy, pressure,
// plastic strain, temperature, damage, the density and energy of the step's material update, the
// deviatoric stress S (a replay that starts mid-run starts from it, exactly), the particle's id
// (its flaws are drawn from it), then a damaged material's intact S, then the models' state
// fields (extras_).
constexpr std::size_t kRow = 1 + 9 + 6 + 6 + 2 + 6 + 1;
constexpr int kVoigt[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};

} // namespace

template <int Dim>
ParticleRecorder<Dim>::ParticleRecorder(const OutputConfig& output)
    : ids_(output.record_particles), where_(output.recordWhere) {}

template <int Dim>
ParticleRecorder<Dim>::ParticleRecorder(std::int64_t id, std::string stem)
    : ids_{id}, stem_(std::move(stem)) {}

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
                                 const ParticleStore& s, const ParticleFields<Dim>& f,
                                 const parallel::MpiContext& mpi) {
  // The state of the porous models: a cap's, P-alpha's (each field once).
  extras_.clear();
  const auto add = [&](Field<double> field) {
    for (const auto& e : extras_)
      if (e.index == field.index) return;
    if (field.valid()) extras_.push_back(field);
  };
  add(f.volumetricStrain), add(f.capPosition), add(f.porosity), add(f.porePressure);
  add(f.capOverstressI1);
  add(f.alpha), add(f.alphaPlastic);
  // Grady-Kipp flaws: the particle's own draw (from the seed, its id and volume), so that a
  // replay starts from the flaws the run gave it; the tensor model's damage and strain tensors.
  intact_ = f.Sintact.valid();
  counts_.clear();
  if (f.hasFlaws()) {
    add(f.flawScale), add(f.flawNext);
    counts_ = {f.flawCount, f.flawsActive};
  }
  tensors_.clear();
  if (f.damageTensor.valid())
    tensors_ = {{"damage_tensor", f.damageTensor}, {"strain_tensor", f.strainTensor}};
  if (f.capOverstress.valid()) tensors_.push_back({"cap_overstress", f.capOverstress});
  if (ids_.empty() || !mpi.root()) return;
  if (stem_.empty()) fs::create_directories(dir / "particles");
  std::string fHeader = "# t";
  for (int a = 1; a <= 3; ++a)
    for (int b = 1; b <= 3; ++b) fHeader += fmt::format(" F{}{}", a, b);
  std::string sHeader = "t,sxx,syy,szz,sxy,syz,sxz,density,specific_internal_energy,pressure,"
                        "plastic_strain,temperature,damage,update_density,"
                        "update_specific_internal_energy";
  for (const char* c : {"xx", "yy", "zz", "xy", "yz", "xz"}) sHeader += fmt::format(",S{}", c);
  sHeader += ",id";
  if (intact_)
    for (const char* c : {"xx", "yy", "zz", "xy", "yz", "xz"})
      sHeader += fmt::format(",intact_S{}", c);
  for (const auto& e : extras_) sHeader += "," + s.columns()[e.index]->info().name;
  for (const auto& c : counts_) sHeader += "," + s.columns()[c.index]->info().name;
  for (const auto& [name, field] : tensors_)
    for (int a = 1; a <= 3; ++a)
      for (int b = 1; b <= 3; ++b) sHeader += fmt::format(",{}_{}{}", name, a, b);
  for (const std::int64_t id : ids_) {
    const fs::path stem =
        stem_.empty() ? dir / "particles" / fmt::format("particle_{}", id) : dir / stem_;
    const fs::path table = stem.string() + ".ftable";
    const fs::path state = stem.string() + (stem_.empty() ? ".csv" : "_state.csv");
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
  const std::size_t first = kRow + (intact_ ? 6 : 0); // the first extra
  const std::size_t width = first + extras_.size() + counts_.size() + 9 * tensors_.size();
  std::vector<double> rows(ids_.size() * width, 0.0);
  const auto id = s[f.id];
  for (std::size_t i = 0; i < s.localCount(); ++i)
    for (std::size_t k = 0; k < ids_.size(); ++k) {
      if (id[i] != static_cast<ParticleId>(ids_[k])) continue;
      double* r = rows.data() + k * width;
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
      for (int c = 0; c < 6; ++c) r[24 + c] = s[f.S][i](kVoigt[c][0], kVoigt[c][1]);
      r[30] = static_cast<double>(id[i]);
      if (intact_)
        for (int c = 0; c < 6; ++c) r[kRow + c] = s[f.Sintact][i](kVoigt[c][0], kVoigt[c][1]);
      for (std::size_t c = 0; c < extras_.size(); ++c) r[first + c] = s[extras_[c]][i];
      for (std::size_t c = 0; c < counts_.size(); ++c)
        r[first + extras_.size() + c] = s[counts_[c]][i];
      double* t = r + first + extras_.size() + counts_.size();
      for (const auto& [name, field] : tensors_)
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) *t++ = s[field][i](a, b);
    }
  // One owner a particle: the sum is its row, exactly.
  MPI_Reduce(mpi.root() ? MPI_IN_PLACE : rows.data(), rows.data(), static_cast<int>(rows.size()),
             MPI_DOUBLE, MPI_SUM, 0, mpi.comm());
  if (!mpi.root()) return;
  for (std::size_t k = 0; k < ids_.size(); ++k) {
    const double* r = rows.data() + k * width;
    // A failed particle's last F may be non-finite or inverted: no F-table can hold it (and the
    // replay needs none: the state before is recorded), so that row is left out.
    if (!stem_.empty()) {
      Tensor<3> F;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) F(a, b) = r[1 + 3 * a + b];
      if (!F.allFinite() || !(F.determinant() > 0.0)) continue;
    }
    std::string table = fmt::format("{:.17g}", time), state = table;
    for (int c = 1; c < 10; ++c) table += fmt::format(" {:.17g}", r[c]);
    for (std::size_t c = 10; c < width; ++c) state += fmt::format(",{:.17g}", r[c]);
    tables_[k].row(table);
    states_[k].row(state);
  }
}

template class ParticleRecorder<1>;
template class ParticleRecorder<2>;
template class ParticleRecorder<3>;

} // namespace spall::app
