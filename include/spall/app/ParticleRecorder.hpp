#pragma once
// Particles recorded every step ([output] record_particles): for each, an F-table of its
// deformation gradient (particles/particle_ID.ftable, what `spall element` replays and `spall
// history` hands out) and its stress and state (particles/particle_ID.csv, what the replay is
// compared with). The owner rank fills a row, one reduction brings every row to rank 0, which
// writes them; a restart drops the rows after its checkpoint.
#include "spall/core/ParticleFields.hpp"
#include "spall/io/CsvLog.hpp"
#include "spall/io/Deck.hpp"
#include "spall/parallel/Mpi.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace spall::app {

template <int Dim> class ParticleRecorder {
public:
  explicit ParticleRecorder(const OutputConfig& output);
  // One particle recorded under other names in the output directory (a failed run's replay):
  // STEM.ftable and STEM_state.csv, without rows whose F is non-finite or inverted.
  ParticleRecorder(std::int64_t id, std::string stem);
  bool empty() const { return ids_.empty(); }
  // Collective: every id names a particle of the run (else a DeckError at the deck key).
  void check(const ParticleStore& s, const ParticleFields<Dim>& f,
             const parallel::MpiContext& mpi) const;
  // Collective: the files, new, or continued after a restart at `time` (rank 0 writes). The
  // porous models' state (a cap's plastic volumetric strain, cap position, porosity and pore
  // pressure; P-alpha's distension) is recorded when the store has it.
  void open(const std::filesystem::path& dir, bool resumed, double time, const ParticleStore& s,
            const ParticleFields<Dim>& f, const parallel::MpiContext& mpi);
  // Collective: the recorded particles' rows at `time`.
  void write(double time, const ParticleStore& s, const ParticleFields<Dim>& f,
             const parallel::MpiContext& mpi);

private:
  std::vector<std::int64_t> ids_;
  bool intact_ = false; // a damaged material's intact deviatoric stress is recorded
  std::vector<Field<double>> extras_;
  std::vector<Field<std::int32_t>> counts_; // integer state (flaw counts), written as numbers
  std::vector<std::pair<std::string, Field<Tensor<3>>>> tensors_; // 9 columns each
  SourceLocation where_;
  std::string stem_; // empty: particles/particle_ID
  std::vector<io::CsvLog> tables_, states_;
};

} // namespace spall::app
