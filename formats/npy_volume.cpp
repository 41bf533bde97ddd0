#include "formats/npy_volume.hpp"

#include "formats/binary_file.hpp"
#include "formats/npy_header.hpp"
#include "kernels/checked_size.hpp"

namespace meshless {

PayloadPlan plan_npy(const std::string& path, const RawOptions& raw) {
    regular_file_size(path);  // IoError for a missing file or a directory
    const NpyHeader h = read_npy_header(path);
    if (h.shape.size() != 3)
        throw FormatError(path + ": .npy shape " + npy_shape_text(h.shape) + " is not a volume (a 3-D array, shape (nz, ny, nx), " +
                          "is; (N, 3) and (N, k) arrays are point sets)");
    for (std::int64_t s : h.shape)
        if (s < 1) throw FormatError(path + ": .npy shape " + npy_shape_text(h.shape) + " has an empty axis");
    PayloadPlan plan;
    plan.format = "npy";
    plan.files = {path};
    plan.type = h.type;
    plan.big_endian = h.big_endian;
    plan.file_offset = h.data_offset;
    plan.exact_size = true;
    // C order (nz, ny, nx) and Fortran order (nx, ny, nz) both keep x fastest
    plan.grid.dims = h.fortran_order ? std::array<std::int64_t, 3>{h.shape[0], h.shape[1], h.shape[2]}
                                     : std::array<std::int64_t, 3>{h.shape[2], h.shape[1], h.shape[0]};
    const std::string ctx = path + ": .npy shape " + npy_shape_text(h.shape);
    (void)checked_mul(checked_mul(checked_mul(static_cast<std::uint64_t>(h.shape[0]), static_cast<std::uint64_t>(h.shape[1]), ctx),
                                  static_cast<std::uint64_t>(h.shape[2]), ctx),
                      stored_size(h.type), ctx);
    if (raw.spacing) {
        for (int a = 0; a < 3; ++a)
            if (!((*raw.spacing)[a] > 0)) throw InvalidArgument(path + ": spacing must be > 0");
        plan.grid.spacing = *raw.spacing;
        validate_given_spacing(plan.grid, path);  // a spacing given, not read: the caller's fault
    }
    return plan;
}

}  // namespace meshless
