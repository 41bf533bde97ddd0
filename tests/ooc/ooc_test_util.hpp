// Helpers for the out-of-core tests: random volumes of every sample type, reassembly of a brick
// store into a volume, file byte surgery.
#pragma once
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "kernels/grid.hpp"
#include "ooc/brick_converter.hpp"
#include "ooc/brick_store.hpp"
#include "ooc/slice_source.hpp"

namespace meshless::test {

/// Random samples (fixed seed) spanning the type's range; f32 gets a few NaNs and infinities.
inline Volume random_volume(std::array<std::int64_t, 3> dims, SampleType t, unsigned seed = 7) {
    GridSpec g;
    g.dims = dims;
    g.origin = {1.5, -2.0, 0.25};
    g.spacing = {0.5, 1.25, 2.0};
    Volume v(g, t);
    std::mt19937 rng(seed);
    const std::int64_t n = g.voxel_count();
    for (std::int64_t i = 0; i < n; ++i) {
        const std::uint32_t r = rng();
        switch (t) {
            case SampleType::u8: reinterpret_cast<std::uint8_t*>(v.bytes.data())[i] = static_cast<std::uint8_t>(r); break;
            case SampleType::i16: reinterpret_cast<std::int16_t*>(v.bytes.data())[i] = static_cast<std::int16_t>(r); break;
            case SampleType::u16: reinterpret_cast<std::uint16_t*>(v.bytes.data())[i] = static_cast<std::uint16_t>(r); break;
            case SampleType::f32: {
                float f = static_cast<float>(static_cast<std::int32_t>(r)) * 1e-3f;
                if (r % 97 == 0) f = std::numeric_limits<float>::quiet_NaN();
                if (r % 101 == 0) f = -std::numeric_limits<float>::infinity();
                reinterpret_cast<float*>(v.bytes.data())[i] = f;
                break;
            }
        }
    }
    return v;
}

inline std::string read_bytes(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

inline void write_bytes(const std::filesystem::path& p, const std::string& b) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(b.data(), static_cast<std::streamsize>(b.size()));
}

/// Converts an in-memory volume into a store at `path`.
inline ConvertStats convert_volume(const Volume& v, const std::string& path, std::uint32_t brick, int threads = 1,
                                   int level = 1) {
    auto src = make_volume_source(v, "memory");
    ConvertParams p;
    p.brick_edge = brick;
    p.threads = threads;
    p.zstd_level = level;
    return convert_to_brick_store(*src, path, p);
}

/// Reads every brick and writes its voxels into a volume; every voxel a brick holds must agree
/// with what earlier bricks wrote there (ghost layers). `covered` counts the bricks holding each voxel.
inline Volume reassemble(const BrickStore& s, std::vector<int>* covered = nullptr) {
    const BrickStoreInfo& in = s.info();
    Volume v(in.grid, in.type);
    const std::size_t ss = sample_size(in.type);
    std::vector<int> seen(static_cast<std::size_t>(in.grid.voxel_count()), 0);
    std::vector<std::byte> buf;
    for (std::size_t b = 0; b < s.bricks().size(); ++b) {
        s.read_brick(b, buf);
        const GridSpec bg = s.brick_grid(b);
        const auto f = s.brick_first_voxel(b);
        for (std::int64_t k = 0; k < bg.dims[2]; ++k)
            for (std::int64_t j = 0; j < bg.dims[1]; ++j)
                for (std::int64_t i = 0; i < bg.dims[0]; ++i) {
                    const std::int64_t dst = in.grid.index(f[0] + i, f[1] + j, f[2] + k);
                    const std::byte* src = buf.data() + static_cast<std::size_t>(bg.index(i, j, k)) * ss;
                    std::byte* out = v.bytes.data() + static_cast<std::size_t>(dst) * ss;
                    if (seen[static_cast<std::size_t>(dst)] && std::memcmp(out, src, ss) != 0)
                        throw std::runtime_error("ghost voxel disagrees between bricks");
                    std::memcpy(out, src, ss);
                    ++seen[static_cast<std::size_t>(dst)];
                }
    }
    if (covered) *covered = std::move(seen);
    return v;
}

}  // namespace meshless::test
