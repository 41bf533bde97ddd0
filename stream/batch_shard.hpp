// The share of an archive one job of a scheduler's job array converts (`meshless batch --shard K/N`,
// Slurm's SLURM_ARRAY_TASK_ID and a count): the archive's volumes ordered by input size, largest
// first (ties in archive order), dealt round-robin to the N shards, so that every shard starts with
// a big scan and the shards' bytes come out near equal; each volume belongs to exactly one shard,
// whatever N. A folder input (a DICOM series, a Zarr store) counts the bytes of the files in it.
// Nothing is thrown: an input that cannot be sized counts as one byte (it is reported when read).
#pragma once
#include <cstdint>
#include <vector>

#include "stream/batch_archive.hpp"

namespace meshless {

/// The positions of `items` ordered by input size, largest first (ties in archive order): the order
/// in which shards and the dynamic deal of an MPI launch take them. `bytes` (when given) gets each
/// item's input bytes (1 for an item with an error), indexed like `items`.
std::vector<std::size_t> size_order(const std::vector<BatchItem>& items, std::vector<std::uint64_t>* bytes = nullptr);

/// The items of shard `k` (0-based) of `n` (n >= 1, k < n), in archive order.
std::vector<BatchItem> shard_items(const std::vector<BatchItem>& items, std::uint32_t k, std::uint32_t n);

/// The bytes of an input: a file's size, a folder's files summed (1 when it cannot be sized).
std::uint64_t input_bytes(const std::string& path);

}  // namespace meshless
