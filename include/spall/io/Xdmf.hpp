#pragma once
// XDMF 2 descriptions of the snapshot HDF5 files, so ParaView and VisIt open them directly:
// one .xmf per snapshot (the particles as a polyvertex grid, every field a node attribute) and
// a temporal collection that includes them all. Serial: call on one rank.
#include "spall/core/ParticleStore.hpp"

#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace spall::io {

// A group of h5FileName's rows as a point set: `fields` its datasets, one of them "position".
struct XdmfPoints {
  std::string group; // "particles", "grid"
  std::size_t globalCount = 0;
  std::span<const FieldInfo> fields;
};

// h5FileName is a path relative to the .xmf. One set is a grid of its own; several are a
// spatial collection (ParaView: a multiblock, a block per set) at the snapshot's time, so the
// series still sees one grid per time. Written atomically (tmp file, then rename).
void writeSnapshotXdmf(const std::string& xmfPath, const std::string& h5FileName, double time,
                       int dimension, std::span<const XdmfPoints> sets);
// The particles alone.
void writeSnapshotXdmf(const std::string& xmfPath, const std::string& h5FileName, double time,
                       std::size_t globalCount, int dimension, std::span<const FieldInfo> fields);

// A temporal collection of (time, snapshot .xmf relative to seriesPath), in time order.
// Written atomically, so a viewer polling the file never sees half of it.
void writeSeriesXdmf(const std::string& seriesPath,
                     const std::vector<std::pair<double, std::string>>& snapshots);

} // namespace spall::io
