// Options shared by the scattered/multiblock point-set readers, and the builder they fill
// (dissertation chapters 4-5 input: samples without connectivity).
//
// PointSetBuilder applies the non-finite policy: a sample whose coordinate or value is NaN/Inf is
// dropped and counted (PointSet::dropped_nonfinite, the default), or, with `strict`, refused with
// a FormatError "PATH: line N: non-finite ..." (the location says line, record or grid point).
// Positions and values are kept in double precision (coordinates offset by 1e6 keep their
// sub-millimetre digits). Thread-safety: one builder per reader call; options are plain data.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "kernels/errors.hpp"
#include "kernels/point_set.hpp"

namespace meshless {

enum class ByteOrder { detect, little, big };

struct PointSetOptions {
    /// Text: "x,y,z,value" (or "x,y,z" for positions only); each entry a header name or a 0-based
    /// column index. Raw float32 records: "x,y,z" reads 12-byte records without a value.
    std::string columns;
    /// The scalar by name: text column, PLY property, VTK PointData array, PLOT3D q name
    /// (density|rho, rhou, rhov, rhow, energy|rhoe, speed|velocity-magnitude).
    std::string value_name;
    /// The scalar by index: text column (0-based), PLOT3D function-file variable.
    std::optional<int> value_index;
    /// PLOT3D q component 0..4 (rho, rho*u, rho*v, rho*w, rho*E) or 5 = |velocity| = |rho*u|/rho.
    int q_component = 0;
    /// PLOT3D q file (default: the sibling of the xyz file, e.g. combxyz.bin -> combq.bin).
    std::string q_file;
    /// PLOT3D function file (.f): values from it instead of the q file (variable value_index, default 0).
    std::string function_file;
    /// Byte order of binary files (raw records, PLOT3D): detected from plausible headers/values by default.
    ByteOrder byte_order = ByteOrder::detect;
    /// Accept (and note) bytes after the data that the header accounts for; refused by default.
    bool allow_trailing = false;
    /// One block holding every point instead of one per grid/piece/file.
    bool merge_blocks = false;
    /// Refuse NaN/Inf coordinates or values (with the line/record) instead of dropping them.
    bool strict = false;
    /// .mlh cluster trees (formats/cluster_tree_file.hpp): the level of detail read (dissertation
    /// section 6.4): level-based at depth lod_level, error-based at lod_error, or the refinement's
    /// first lod_count points (or lod_fraction x the samples, rounded, at least 1); none: the finest
    /// (every leaf). A level beyond the depth, an error below the reached one or more points than
    /// leaves gives the finest.
    std::optional<std::uint32_t> lod_level;
    std::optional<double> lod_error;
    std::optional<std::uint64_t> lod_count;
    std::optional<double> lod_fraction;
};

/// Accumulates samples and blocks for one reader call.
class PointSetBuilder {
public:
    PointSetBuilder(std::string path, const PointSetOptions& o) : path_(std::move(path)), strict_(o.strict) {}

    /// Starts a block; the previous one (if any) is closed.
    void begin_block(std::string name, std::array<std::int64_t, 3> dims) {
        close_block();
        PointSetBlock b;
        b.name = std::move(name);
        b.dims = dims;
        b.first = ps_.pos.size();
        ps_.blocks.push_back(std::move(b));
        open_ = true;
    }
    void reserve(std::size_t n) {
        ps_.pos.reserve(n);
        ps_.value.reserve(n);
    }
    /// `where` and `index` locate the sample in messages ("line", 12) -> "line 12".
    void add(double x, double y, double z, double v, const char* where, std::uint64_t index) {
        if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || !std::isfinite(v)) {
            if (strict_)
                throw FormatError(path_ + ": " + where + " " + std::to_string(index) + ": non-finite " +
                                  (std::isfinite(x) && std::isfinite(y) && std::isfinite(z) ? "value" : "coordinate") +
                                  " (NaN/Inf are refused in strict mode)");
            ++ps_.dropped_nonfinite;
            return;
        }
        ps_.pos.push_back(Vec3{x, y, z});
        ps_.value.push_back(v);
    }
    void add_blanked() { ++ps_.dropped_blanked; }
    PointSet& set() { return ps_; }

    /// Closes the last block; names the value; a positions-only set gets has_values = false.
    PointSet finish(std::string value_name, bool has_values) {
        close_block();
        if (ps_.blocks.empty()) {
            ps_.blocks.push_back(PointSetBlock{"points", {static_cast<std::int64_t>(ps_.pos.size()), 1, 1}, 0, ps_.pos.size()});
        }
        ps_.value_name = std::move(value_name);
        ps_.has_values = has_values;
        return std::move(ps_);
    }

private:
    void close_block() {
        if (!open_) return;
        auto& b = ps_.blocks.back();
        b.count = ps_.pos.size() - b.first;
        if (b.dims[1] == 1 && b.dims[2] == 1 && b.dims[0] < 0) b.dims[0] = static_cast<std::int64_t>(b.count);
        open_ = false;
    }
    std::string path_;
    bool strict_ = false;
    bool open_ = false;
    PointSet ps_;
};

}  // namespace meshless
