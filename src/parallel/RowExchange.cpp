#include "spall/parallel/RowExchange.hpp"

#include <numeric>

namespace spall::parallel {

namespace {

std::size_t rowBytes(const ParticleStore& s, std::span<const std::size_t> columns) {
  std::size_t b = 0;
  for (std::size_t c : columns) b += s.columns()[c]->bytesPerParticle();
  return b;
}

} // namespace

ExchangeResult sendRows(MPI_Comm comm, const ParticleStore& s, std::span<const std::size_t> columns,
                        const std::vector<std::vector<std::uint32_t>>& rows) {
  const std::size_t bytes = rowBytes(s, columns);
  std::vector<std::size_t> bytesTo(rows.size());
  std::size_t total = 0;
  for (std::size_t r = 0; r < rows.size(); ++r) total += bytesTo[r] = rows[r].size() * bytes;
  std::vector<std::byte> buffer(total);
  std::size_t at = 0;
  for (const auto& block : rows) {
    for (std::size_t c : columns) {
      const ColumnBase& col = *s.columns()[c];
      col.pack(block, buffer.data() + at);
      at += block.size() * col.bytesPerParticle();
    }
  }
  return exchangeBytes(comm, buffer, bytesTo);
}

std::size_t receiveRows(ParticleStore& s, std::span<const std::size_t> columns,
                        const ExchangeResult& in, std::size_t first) {
  const std::size_t bytes = rowBytes(s, columns);
  if (bytes == 0) return 0;
  std::size_t row = first;
  for (std::size_t r = 0; r < in.countFrom.size(); ++r) {
    const std::size_t count = in.countFrom[r] / bytes;
    const std::byte* p = in.data.data() + in.offsetFrom[r];
    for (std::size_t c : columns) {
      ColumnBase& col = *s.columns()[c];
      col.unpack(p, row, count);
      p += count * col.bytesPerParticle();
    }
    row += count;
  }
  return row - first;
}

std::vector<std::size_t> allColumns(const ParticleStore& s) {
  std::vector<std::size_t> all(s.columns().size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  return all;
}

} // namespace spall::parallel
