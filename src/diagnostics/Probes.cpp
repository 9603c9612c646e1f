#include "spall/diagnostics/Probes.hpp"

#include "spall/diagnostics/OrderFreeSums.hpp"
#include "spall/kernels/Kernels.hpp"
#include "spall/solvers/Axisymmetric.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <span>

namespace spall::diagnostics {

namespace {
const char* kAxes = "xyz";

template <int Dim>
double fieldValue(const ProbeField& pf, const ParticleStore& s, const ParticleFields<Dim>& f,
                  std::size_t i) {
  switch (pf.kind) {
  case ProbeField::Kind::Position:
    return s[f.x][i][pf.a];
  case ProbeField::Kind::Velocity:
    return s[f.v][i][pf.a];
  // Cauchy stress sigma = -p I + S; S = 0 on the hydro path.
  case ProbeField::Kind::Stress:
    return (pf.a == pf.b ? -s[f.p][i] : 0.0) + (f.hasStrength() ? s[f.S][i](pf.a, pf.b) : 0.0);
  case ProbeField::Kind::HoopStress:
    return -s[f.p][i] + (f.hasStrength() ? s[f.S][i](2, 2) : 0.0);
  case ProbeField::Kind::Pressure:
    return s[f.p][i];
  case ProbeField::Kind::Density:
    return s[f.rho][i];
  case ProbeField::Kind::Energy:
    return s[f.e][i];
  case ProbeField::Kind::SoundSpeed:
    return s[f.cs][i];
  case ProbeField::Kind::Mass:
    return s[f.m][i];
  case ProbeField::Kind::SmoothingLength:
    return s[f.h][i];
  case ProbeField::Kind::Column: {
    // b: the component's place in the particle's stored row (columnProbeNames).
    const ColumnBase& c = *s.columns()[static_cast<std::size_t>(pf.a)];
    if (c.info().scalar == ScalarType::I32) return static_cast<const std::int32_t*>(c.raw())[i];
    if (c.info().scalar == ScalarType::I64)
      return static_cast<double>(static_cast<const std::int64_t*>(c.raw())[i]);
    return static_cast<const double*>(
        c.raw())[i * c.info().scalarsPerParticle() + static_cast<std::size_t>(pf.b)];
  }
  }
  return 0.0;
}

// A snapshot field of the store: a scalar (double, int32, int64), or a vector or tensor of
// doubles, whose components are probed as name_x and name_xy = T(x, y) (a tensor is stored
// column-major: the snapshot array's [n, y, x]).
bool probeableColumn(const ColumnBase& c) {
  const FieldInfo& info = c.info();
  if ((info.flags & kOutput) == 0 || info.scalar == ScalarType::U64) return false;
  return info.shape.empty() || (info.scalar == ScalarType::F64 && info.shape.size() <= 2);
}

// A column's probe names: its own for a scalar, else one per component.
std::vector<std::string> columnProbeNames(const FieldInfo& info) {
  if (info.shape.empty()) return {info.name};
  // In storage order (T(a, b) at b rows + a), so that a name's place is its component's.
  std::vector<std::string> names;
  const int rows = info.shape[0], cols = info.shape.size() > 1 ? info.shape[1] : 1;
  for (int b = 0; b < cols; ++b)
    for (int a = 0; a < rows; ++a)
      names.push_back(info.shape.size() > 1 ? fmt::format("{}_{}{}", info.name, kAxes[a], kAxes[b])
                                            : fmt::format("{}_{}", info.name, kAxes[a]));
  return names;
}
} // namespace

std::vector<std::string> probeFieldNames(int dim, const ParticleStore* store) {
  std::vector<std::string> names;
  for (int a = 0; a < dim; ++a) names.push_back(fmt::format("position_{}", kAxes[a]));
  for (int a = 0; a < dim; ++a) names.push_back(fmt::format("velocity_{}", kAxes[a]));
  for (int a = 0; a < dim; ++a)
    for (int b = 0; b < dim; ++b) names.push_back(fmt::format("stress_{}{}", kAxes[a], kAxes[b]));
  if (dim == 2) names.emplace_back("stress_hoop");
  for (const char* n : {"pressure", "density", "specific_internal_energy", "sound_speed", "mass",
                        "smoothing_length"})
    names.emplace_back(n);
  if (store)
    for (const auto& c : store->columns())
      if (probeableColumn(*c))
        for (auto& n : columnProbeNames(c->info()))
          if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
  return names;
}

ProbeField resolveProbeField(const std::string& name, int dim, const SourceLocation& where,
                             const ParticleStore* store) {
  using K = ProbeField::Kind;
  auto axis = [&](char c) -> int {
    for (int a = 0; a < dim; ++a)
      if (kAxes[a] == c) return a;
    return -1;
  };
  if (name.rfind("position_", 0) == 0 && name.size() == 10 && axis(name[9]) >= 0)
    return {K::Position, axis(name[9]), 0, name};
  if (name.rfind("velocity_", 0) == 0 && name.size() == 10 && axis(name[9]) >= 0)
    return {K::Velocity, axis(name[9]), 0, name};
  if (name.rfind("stress_", 0) == 0 && name.size() == 9 && axis(name[7]) >= 0 && axis(name[8]) >= 0)
    return {K::Stress, axis(name[7]), axis(name[8]), name};
  if (name == "stress_hoop" && dim == 2) return {K::HoopStress, 0, 0, name};
  if (name == "pressure") return {K::Pressure, 0, 0, name};
  if (name == "density") return {K::Density, 0, 0, name};
  if (name == "specific_internal_energy") return {K::Energy, 0, 0, name};
  if (name == "sound_speed") return {K::SoundSpeed, 0, 0, name};
  if (name == "mass") return {K::Mass, 0, 0, name};
  if (name == "smoothing_length") return {K::SmoothingLength, 0, 0, name};
  if (store)
    for (std::size_t c = 0; c < store->columns().size(); ++c) {
      if (!probeableColumn(*store->columns()[c])) continue;
      const auto names = columnProbeNames(store->columns()[c]->info());
      const auto k = std::find(names.begin(), names.end(), name);
      if (k != names.end())
        return {K::Column, static_cast<int>(c), static_cast<int>(k - names.begin()), name};
    }
  std::string list;
  for (const auto& n : probeFieldNames(dim, store)) list += (list.empty() ? "" : ", ") + n;
  throw DeckError(where,
                  fmt::format("unknown probe field '{}' in {}D (available: {})", name, dim, list));
}

template <int Dim>
Probes<Dim>::Probes(const std::vector<ProbeConfig>& config, const ParticleStore& store,
                    bool axisymmetric)
    : axisymmetric_(axisymmetric) {
  for (const auto& c : config) {
    Probe p{c, {}, 0, 0};
    for (const auto& name : c.fields)
      p.fields.push_back(resolveProbeField(name, Dim, c.where, &store));
    probes_.push_back(std::move(p));
  }
}

template <int Dim>
void Probes<Dim>::attach(const ParticleStore& s, const ParticleFields<Dim>& f,
                         const parallel::MpiContext& mpi) {
  const auto x = s[f.x];
  const auto id = s[f.id];
  for (auto& p : probes_) {
    if (p.config.track != ProbeTrack::Material) continue;
    Vec<Dim> at;
    for (int d = 0; d < Dim; ++d) at[d] = p.config.position[d];
    double best = std::numeric_limits<double>::infinity();
    ParticleId bestId = std::numeric_limits<ParticleId>::max();
    for (std::size_t i = 0; i < s.localCount(); ++i) {
      const double d = (x[i] - at).squaredNorm();
      if (d < best || (d == best && id[i] < bestId)) best = d, bestId = id[i];
    }
    const double global = mpi.min(best);
    ParticleId candidate = best == global ? bestId : std::numeric_limits<ParticleId>::max();
    ParticleId chosen;
    MPI_Allreduce(&candidate, &chosen, 1, MPI_UINT64_T, MPI_MIN, mpi.comm());
    p.particle = chosen;
  }
}

template <int Dim>
std::vector<ProbeSample> Probes<Dim>::sample(const ParticleStore& s, const ParticleFields<Dim>& f,
                                             const parallel::MpiContext& mpi, double support) {
  std::vector<ProbeSample> out;
  const auto id = s[f.id];
  const auto x = s[f.x];
  for (auto& p : probes_) {
    // The particles that hold the probe's value here and their weights: the one a material probe
    // follows (weight 1), or those whose support covers a space probe's point.
    who_.clear(), weight_.clear();
    if (p.config.track == ProbeTrack::Material) {
      std::size_t i = p.cachedIndex;
      if (i >= s.localCount() || id[i] != p.particle) {
        i = s.localCount();
        for (std::size_t k = 0; k < s.localCount(); ++k)
          if (id[k] == p.particle) {
            i = k;
            break;
          }
      }
      if (i < s.localCount()) {
        p.cachedIndex = i;
        who_.push_back(i), weight_.push_back(1.0);
      }
    } else {
      Vec<Dim> at;
      for (int d = 0; d < Dim; ++d) at[d] = p.config.position[d];
      using W = kernels::Kernel<kernels::CubicSpline<Dim>, Dim>;
      const auto h = s[f.h];
      const auto m = s[f.m];
      const auto rho = s[f.rho];
      for (std::size_t i = 0; i < s.localCount(); ++i) {
        const double r = (x[i] - at).norm();
        if (r >= support * h[i]) continue;
        // The kernel average over volumes: in rz the particle's area in the r-z plane.
        const double mass =
            axisymmetric_ ? solvers::rz::areaMass(m[i], solvers::rz::radius(x[i][0], h[i])) : m[i];
        who_.push_back(i), weight_.push_back(mass / rho[i] * W::W(r, h[i]));
      }
    }
    // [w value..., w] summed independently of the ranks and the particles' order: the same bits
    // on any rank count (a material probe's one term exactly).
    const std::size_t nf = p.fields.size();
    const auto acc = orderFreeSums(
        who_.size(), nf + 1,
        [&](std::size_t k, std::span<double> t) {
          for (std::size_t q = 0; q < nf; ++q)
            t[q] = weight_[k] * fieldValue(p.fields[q], s, f, who_[k]);
          t[nf] = weight_[k];
        },
        mpi.comm());
    const double weight = acc.back();
    for (std::size_t k = 0; k < p.fields.size(); ++k) {
      const double value =
          weight > 0.0 ? acc[k] / weight : std::numeric_limits<double>::quiet_NaN();
      out.push_back({p.config.name, p.fields[k].name, value});
    }
  }
  return out;
}

template class Probes<1>;
template class Probes<2>;
template class Probes<3>;

} // namespace spall::diagnostics
