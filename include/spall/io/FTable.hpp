#pragma once
// An F-table (docs/reference.md, "Single-element driver"): one row per time, whitespace-separated,
// `#` comments: t, the nine components of the deformation gradient row by row, and optionally a
// superimposed rotation (angle in degrees about an axis). What `spall element` drives a material
// with, and what `spall history` will write for a particle of a run.
#include "spall/core/Types.hpp"

#include <string>
#include <vector>

namespace spall::io {

struct FTableRow {
  double t = 0.0;
  Tensor<3> F = Tensor<3>::Identity();
  double thetaDeg = 0.0;               // the superimposed rotation's angle
  Vec<3> axis = Vec<3>(0.0, 0.0, 1.0); // and its axis (unit length)
  int line = 0;                        // where the row is in its file
};

struct FTable {
  std::string path;
  std::vector<FTableRow> rows;
  bool rotation = false; // rows carry the four rotation columns
};

// Reads and checks a table: at least two rows, times strictly increasing, 10 or 14 numbers on
// every row (the same count on all), det F > 0, a non-zero axis. A bad table is a DeckError at
// its file:line:column (exit 2).
FTable readFTable(const std::string& path);

} // namespace spall::io
