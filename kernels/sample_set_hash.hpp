// A 64-bit fingerprint of a set of samples (positions and values), whatever their order: the sum,
// modulo 2^64, of a 64-bit mix (splitmix64's finaliser) of each sample's bit patterns chained. A
// cluster tree records it (formats/cluster_tree_file.hpp) so that its certificates are only ever
// checked against its own samples: other values at the same positions, or the same values moved,
// change it with probability 1 - 2^-64 for unrelated sets. Not a cryptographic hash. Dissertation:
// none (a guard around chapter 6's certified levels of detail). Pure; throws nothing.
#pragma once
#include <cstdint>
#include <span>

#include "kernels/vec3.hpp"

namespace meshless {

/// The fingerprint of the samples (pos[i], value[i]) for every i where all four are finite (the
/// samples a cluster tree keeps); 0 is never returned (a set hashing to 0 gets 1), so 0 can mean
/// "not recorded".
std::uint64_t sample_set_hash(std::span<const Vec3> pos, std::span<const double> value);

}  // namespace meshless
