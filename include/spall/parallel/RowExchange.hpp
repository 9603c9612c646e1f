#pragma once
// Ships rows of the particle store between ranks, column by column, through the generic
// pack/unpack of its columns: the one path by which migration moves whole particles and the halo
// copies the fields a computation reads. Physics-free.
#include "spall/core/ParticleStore.hpp"
#include "spall/parallel/Exchange.hpp"

#include <span>
#include <vector>

namespace spall::parallel {

// Sends rows[r] of the listed columns to rank r (collective).
ExchangeResult sendRows(MPI_Comm comm, const ParticleStore& s, std::span<const std::size_t> columns,
                        const std::vector<std::vector<std::uint32_t>>& rows);

// Writes what sendRows delivered into rows first, first + 1, ... (in source-rank order; the
// caller has made room) and returns how many rows that was.
std::size_t receiveRows(ParticleStore& s, std::span<const std::size_t> columns,
                        const ExchangeResult& in, std::size_t first);

// Every column of the store, for moving whole particles.
std::vector<std::size_t> allColumns(const ParticleStore& s);

} // namespace spall::parallel
