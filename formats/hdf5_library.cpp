// formats/hdf5_dataset.hpp through libhdf5: the only file that includes hdf5.h.
#include <fcntl.h>
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <system_error>

#include "formats/hdf5_dataset.hpp"
#include "formats/text_header.hpp"
#include "kernels/checked_size.hpp"
#include "kernels/errors.hpp"

/// The sanitizers' hook (absent from other builds): the preflight child turns off the report of a
/// crash it is there to catch.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace meshless {

namespace {

/// A libhdf5 identifier closed by `close` when it goes out of scope.
class Id {
public:
    Id() = default;
    Id(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
    ~Id() { reset(); }
    Id(Id&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = H5I_INVALID_HID; }
    Id& operator=(Id&& o) noexcept {
        if (this != &o) {
            reset();
            id_ = o.id_;
            close_ = o.close_;
            o.id_ = H5I_INVALID_HID;
        }
        return *this;
    }
    Id(const Id&) = delete;
    Id& operator=(const Id&) = delete;
    hid_t get() const { return id_; }
    bool valid() const { return id_ >= 0; }

private:
    void reset() {
        if (id_ >= 0 && close_) close_(id_);
        id_ = H5I_INVALID_HID;
    }
    hid_t id_ = H5I_INVALID_HID;
    herr_t (*close_)(hid_t) = nullptr;
};

/// libhdf5's innermost message of the current error stack (escaped), and the stack cleared.
std::string library_message() {
    std::string message;
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD,
             [](unsigned n, const H5E_error2_t* e, void* out) -> herr_t {
                 if (n == 0 && e && e->desc) *static_cast<std::string*>(out) = e->desc;
                 return 0;
             },
             &message);
    H5Eclear2(H5E_DEFAULT);
    return message.empty() ? "no reason given" : escape_field(message, 120);
}

/// Turns off libhdf5's printing of its error stack on stderr for this thread's calls (our messages
/// quote it instead).
void quiet() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

[[noreturn]] void fail(const std::string& where, const std::string& what) {
    throw FormatError(where + ": " + what + " (libhdf5: " + library_message() + ")");
}

Id open_file(const std::string& file) {
    quiet();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) throw IoError(file + ": cannot open: not a regular file");
    // the file only: no driver that reaches elsewhere, external links refused below
    Id f(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!f.valid()) fail(file, "libhdf5 cannot open it");
    return f;
}

/// Every link on `path` is one of the file's own (hard or soft), never an external one.
void check_links(hid_t file, const std::string& path, const std::string& where) {
    if (path.empty() || path[0] != '/') throw FormatError(where + ": the dataset path must start with '/'");
    std::string prefix;
    std::size_t i = 1;
    while (i <= path.size()) {
        const std::size_t j = std::min(path.find('/', i), path.size());
        if (j > i) {
            prefix += "/" + path.substr(i, j - i);
            const htri_t exists = H5Lexists(file, prefix.c_str(), H5P_DEFAULT);
            if (exists <= 0) {
                H5Eclear2(H5E_DEFAULT);
                throw FormatError(where + ": no object named '" + escape_field(prefix, 120) + "' in the file");
            }
            H5L_info_t info{};
            if (H5Lget_info(file, prefix.c_str(), &info, H5P_DEFAULT) < 0) fail(where, "cannot read the link '" + escape_field(prefix, 120) + "'");
            if (info.type != H5L_TYPE_HARD && info.type != H5L_TYPE_SOFT)
                throw FormatError(where + ": '" + escape_field(prefix, 120) +
                                  "' is an external or user-defined link to another file: refused (only the file's own objects are read)");
        }
        i = j + 1;
    }
}

std::vector<std::int64_t> extent(hid_t space, const std::string& where, std::vector<std::int64_t>* max_shape = nullptr) {
    const int rank = H5Sget_simple_extent_ndims(space);
    if (rank < 0) fail(where, "cannot read the dataspace");
    if (rank > H5S_MAX_RANK) throw FormatError(where + ": " + std::to_string(rank) + " dimensions");
    hsize_t dims[H5S_MAX_RANK] = {}, max[H5S_MAX_RANK] = {};
    if (rank > 0 && H5Sget_simple_extent_dims(space, dims, max) < 0) fail(where, "cannot read the dimensions");
    if (max_shape)
        for (int d = 0; d < rank; ++d)
            max_shape->push_back(max[d] == H5S_UNLIMITED || max[d] > static_cast<hsize_t>(std::numeric_limits<std::int64_t>::max())
                                     ? -1
                                     : static_cast<std::int64_t>(max[d]));
    std::vector<std::int64_t> shape;
    for (int d = 0; d < rank; ++d) {
        if (dims[d] > static_cast<hsize_t>(std::numeric_limits<std::int32_t>::max()))
            throw FormatError(where + ": dimension " + std::to_string(d) + " of " + std::to_string(dims[d]) + " samples, more than 2^31 - 1");
        shape.push_back(static_cast<std::int64_t>(dims[d]));
    }
    return shape;
}

/// The stored type of a numeric HDF5 type, or nullopt (text says which).
std::optional<StoredType> stored_type(hid_t type, std::string& text) {
    const H5T_class_t cls = H5Tget_class(type);
    const std::size_t size = H5Tget_size(type);
    const H5T_order_t order = H5Tget_order(type);
    const std::string endian = order == H5T_ORDER_BE ? " big-endian" : order == H5T_ORDER_LE ? " little-endian" : "";
    if (cls == H5T_INTEGER) {
        const bool is_signed = H5Tget_sign(type) == H5T_SGN_2;
        text = std::string(is_signed ? "int" : "uint") + std::to_string(8 * size) + endian;
        switch (size) {
            case 1: return is_signed ? StoredType::i8 : StoredType::u8;
            case 2: return is_signed ? StoredType::i16 : StoredType::u16;
            case 4: return is_signed ? StoredType::i32 : StoredType::u32;
            case 8: return is_signed ? StoredType::i64 : StoredType::u64;
            default: return std::nullopt;
        }
    }
    if (cls == H5T_FLOAT) {
        text = "float" + std::to_string(8 * size) + endian;
        // the IEEE layouts only (a float of 4 or 8 bytes with another mantissa is not one)
        if (size == 4 && H5Tequal(type, H5T_IEEE_F32LE) + H5Tequal(type, H5T_IEEE_F32BE) > 0) return StoredType::f32;
        if (size == 8 && H5Tequal(type, H5T_IEEE_F64LE) + H5Tequal(type, H5T_IEEE_F64BE) > 0) return StoredType::f64;
        if (size == 4 || size == 8) text += " (not IEEE)";
        return std::nullopt;
    }
    switch (cls) {
        case H5T_STRING: text = "string"; break;
        case H5T_COMPOUND: text = "compound"; break;
        case H5T_ENUM: text = "enum"; break;
        case H5T_ARRAY: text = "array"; break;
        case H5T_VLEN: text = "variable-length"; break;
        case H5T_BITFIELD: text = "bitfield"; break;
        case H5T_OPAQUE: text = "opaque"; break;
        case H5T_REFERENCE: text = "reference"; break;
        default: text = "unknown class"; break;
    }
    return std::nullopt;
}

/// A numeric attribute of three values on `object`, or nullopt when it is absent; FormatError when
/// present and not three finite numbers.
std::optional<std::array<double, 3>> triple_attribute(hid_t object, const char* name, const std::string& where) {
    const htri_t exists = H5Aexists(object, name);
    if (exists < 0) fail(where, std::string("cannot look up the attribute '") + name + "'");
    if (exists == 0) return std::nullopt;
    Id a(H5Aopen(object, name, H5P_DEFAULT), H5Aclose);
    if (!a.valid()) fail(where, std::string("cannot open the attribute '") + name + "'");
    Id type(H5Aget_type(a.get()), H5Tclose);
    Id space(H5Aget_space(a.get()), H5Sclose);
    if (!type.valid() || !space.valid()) fail(where, std::string("cannot read the attribute '") + name + "'");
    const H5T_class_t cls = H5Tget_class(type.get());
    const hssize_t n = H5Sget_simple_extent_npoints(space.get());
    if ((cls != H5T_INTEGER && cls != H5T_FLOAT) || n != 3)
        throw FormatError(where + ": attribute '" + name + "': expected 3 numbers, got " +
                          (cls != H5T_INTEGER && cls != H5T_FLOAT ? std::string("a non-numeric value") : std::to_string(n) + " values"));
    std::array<double, 3> v{};
    if (H5Aread(a.get(), H5T_NATIVE_DOUBLE, v.data()) < 0) fail(where, std::string("cannot read the attribute '") + name + "'");
    for (double x : v)
        if (!std::isfinite(x)) throw FormatError(where + ": attribute '" + name + "': " + number_text(x) + " is not a finite number");
    return v;
}

std::string filter_list(hid_t dcpl, const std::string& where, std::vector<int>& ids) {
    const int n = H5Pget_nfilters(dcpl);
    if (n < 0) fail(where, "cannot read the filter pipeline");
    if (n == 0) return "none";
    std::string text;
    for (int i = 0; i < n; ++i) {
        unsigned flags = 0, config = 0;
        std::size_t nvalues = 8;
        unsigned values[8] = {};
        char name[64] = {};
        const H5Z_filter_t id = H5Pget_filter2(dcpl, static_cast<unsigned>(i), &flags, &nvalues, values, sizeof name, name, &config);
        if (id < 0) fail(where, "cannot read filter " + std::to_string(i));
        std::string one;
        switch (id) {
            case H5Z_FILTER_DEFLATE: one = "deflate" + (nvalues > 0 ? " " + std::to_string(values[0]) : std::string()); break;
            case H5Z_FILTER_SHUFFLE: one = "shuffle"; break;
            case H5Z_FILTER_FLETCHER32: one = "fletcher32"; break;
            case H5Z_FILTER_SZIP: one = "szip"; break;
            case H5Z_FILTER_NBIT: one = "nbit"; break;
            case H5Z_FILTER_SCALEOFFSET: one = "scaleoffset"; break;
            default: one = "filter " + std::to_string(id) + (name[0] ? " (" + escape_field(name, 40) + ")" : std::string()); break;
        }
        if (H5Zfilter_avail(id) <= 0) {
            H5Eclear2(H5E_DEFAULT);
            throw FormatError(where + ": compressed with " + one + ", which this build's libhdf5 cannot decode (rewrite "
                                      "the dataset with deflate, e.g. h5repack -f GZIP=4)");
        }
        ids.push_back(static_cast<int>(id));
        text += (text.empty() ? "" : ", ") + one;
    }
    return text;
}

}  // namespace

struct Hdf5Dataset::Handles {
    Id file, dataset, space, type;
    std::string where;
    std::size_t leading = 0;  ///< dimensions of size 1 before the last three
};

bool hdf5_reader_available() { return true; }

namespace {

std::vector<Hdf5Listing> list_datasets(const std::string& file, std::size_t limit, bool& more) {
    const Id f = open_file(file);
    struct Walk {
        std::vector<Hdf5Listing> found;
        std::size_t limit;
        bool more = false;
        std::size_t visited = 0;
    } walk{{}, limit};
    const herr_t r = H5Ovisit2(
        f.get(), H5_INDEX_NAME, H5_ITER_INC,
        [](hid_t root, const char* name, const H5O_info_t* info, void* data) -> herr_t {
            auto& w = *static_cast<Walk*>(data);
            if (++w.visited > 100000) {  // a file of more objects is not a volume archive: stop looking
                w.more = true;
                return 1;
            }
            if (info->type != H5O_TYPE_DATASET) return 0;
            Id d(H5Dopen2(root, name, H5P_DEFAULT), H5Dclose);
            if (!d.valid()) return H5Eclear2(H5E_DEFAULT), 0;
            Id space(H5Dget_space(d.get()), H5Sclose);
            Id type(H5Dget_type(d.get()), H5Tclose);
            if (!space.valid() || !type.valid()) return H5Eclear2(H5E_DEFAULT), 0;
            const int rank = H5Sget_simple_extent_ndims(space.get());
            hsize_t dims[H5S_MAX_RANK] = {};
            if (rank < 3 || rank > H5S_MAX_RANK || H5Sget_simple_extent_dims(space.get(), dims, nullptr) < 0) return H5Eclear2(H5E_DEFAULT), 0;
            for (int k = 0; k + 3 < rank; ++k)
                if (dims[k] != 1) return 0;
            const H5T_class_t cls = H5Tget_class(type.get());
            if (cls != H5T_INTEGER && cls != H5T_FLOAT) return 0;
            if (w.found.size() == w.limit) {
                w.more = true;
                return 1;
            }
            std::string text;
            stored_type(type.get(), text);
            w.found.push_back(Hdf5Listing{std::string("/") + name, text});
            return 0;
        },
        &walk, H5O_INFO_BASIC);
    if (r < 0) fail(file, "cannot list the datasets");
    more = walk.more;
    return walk.found;
}

/// libhdf5 1.10 parses a file's structure (superblock, object headers, symbol tables, B-trees) with
/// checks of its own, and a corrupt file can make it dereference a failed allocation (the fuzzer
/// found one in H5Ovisit). So every file is first opened, listed and its dataset's header read in a
/// child process: when libhdf5 crashes there (or the child runs past 60 s), the file is refused
/// with one line and this process never parses it. The child does nothing but that and exits.
void preflight(const std::string& file, const std::string& dataset) {
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid < 0) return;  // no child to be had: parsed in this process, as libhdf5 does everywhere
    if (pid == 0) {
        // the child's crash is the parent's finding: no sanitizer report hook, no core of our own
        if (__sanitizer_set_death_callback) __sanitizer_set_death_callback(nullptr);
        for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(sig, SIG_DFL);
        ::alarm(60);
        const int quiet_fd = ::open("/dev/null", O_WRONLY);
        if (quiet_fd >= 0) ::dup2(quiet_fd, STDERR_FILENO);  // (sanitizer reports of libhdf5's faults)
        int code = 0;
        try {
            bool more = false;
            (void)list_datasets(file, 64, more);
            if (!dataset.empty()) Hdf5Dataset(file, dataset, Hdf5Dataset::Parsed::here);
        } catch (...) {
            code = 42;  // refused with a message: the parent gives it by parsing again
        }
        ::_exit(code);
    }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (WIFEXITED(status) && (WEXITSTATUS(status) == 0 || WEXITSTATUS(status) == 42)) return;
    const std::string why = WIFSIGNALED(status) ? (WTERMSIG(status) == SIGALRM ? std::string("ran past 60 s")
                                                                              : "crashed (signal " + std::to_string(WTERMSIG(status)) + ")")
                                                : "failed (exit status " + std::to_string(WEXITSTATUS(status)) + ")";
    throw FormatError(file + ": libhdf5 " + why + " parsing the file's structure: a corrupt HDF5 file, refused");
}

}  // namespace

std::vector<Hdf5Listing> hdf5_volume_datasets(const std::string& file, std::size_t limit, bool& more) {
    preflight(file, "");
    return list_datasets(file, limit, more);
}

Hdf5Dataset::Hdf5Dataset(const std::string& file, const std::string& dataset) : Hdf5Dataset(file, dataset, Parsed::in_a_child_first) {}

Hdf5Dataset::Hdf5Dataset(const std::string& file, const std::string& dataset, Parsed parsed) : h_(std::make_unique<Handles>()) {
    if (parsed == Parsed::in_a_child_first) preflight(file, dataset);
    h_->where = file + ":" + escape_field(dataset, 120);
    const std::string& where = h_->where;
    h_->file = open_file(file);
    check_links(h_->file.get(), dataset, where);
    H5O_info_t oinfo{};
    if (H5Oget_info_by_name2(h_->file.get(), dataset.c_str(), &oinfo, H5O_INFO_BASIC, H5P_DEFAULT) < 0) fail(where, "cannot look up the object");
    if (oinfo.type != H5O_TYPE_DATASET)
        throw FormatError(where + ": is a " + (oinfo.type == H5O_TYPE_GROUP ? "group" : "named type or another object") + ", not a dataset");
    h_->dataset = Id(H5Dopen2(h_->file.get(), dataset.c_str(), H5P_DEFAULT), H5Dclose);
    if (!h_->dataset.valid()) fail(where, "cannot open the dataset");
    h_->space = Id(H5Dget_space(h_->dataset.get()), H5Sclose);
    if (!h_->space.valid()) fail(where, "cannot read the dataspace");
    header_.shape = extent(h_->space.get(), where, &header_.max_shape);
    h_->type = Id(H5Dget_type(h_->dataset.get()), H5Tclose);
    if (!h_->type.valid()) fail(where, "cannot read the datatype");
    header_.type = stored_type(h_->type.get(), header_.type_text);
    header_.big_endian = H5Tget_order(h_->type.get()) == H5T_ORDER_BE;
    Id dcpl(H5Dget_create_plist(h_->dataset.get()), H5Pclose);
    if (!dcpl.valid()) fail(where, "cannot read the creation properties");
    const H5D_layout_t layout = H5Pget_layout(dcpl.get());
    if (layout == H5D_VIRTUAL)
        throw FormatError(where + ": a virtual dataset (its data are in other files): refused (only the file's own data are read)");
    if (layout == H5D_CHUNKED) {
        header_.layout = "chunked";
        hsize_t chunk[H5S_MAX_RANK] = {};
        const int rank = H5Pget_chunk(dcpl.get(), H5S_MAX_RANK, chunk);
        if (rank != static_cast<int>(header_.shape.size())) fail(where, "chunk rank differs from the dataset's");
        for (int d = 0; d < rank; ++d) header_.chunk.push_back(static_cast<std::int64_t>(chunk[d]));
    } else {
        header_.layout = layout == H5D_COMPACT ? "compact" : "contiguous";
    }
    const int external = H5Pget_external_count(dcpl.get());
    if (external != 0)
        throw FormatError(where + ": its raw data are in " + (external > 0 ? std::to_string(external) : std::string("some")) +
                          " external file(s): refused (only the file's own data are read)");
    header_.filters = filter_list(dcpl.get(), where, header_.filters_ids);
    if (header_.type) {  // the fill value in the stored type (the default: zeros)
        header_.fill.assign(stored_size(*header_.type), std::byte{0});
        H5D_fill_value_t defined = H5D_FILL_VALUE_UNDEFINED;
        if (H5Pfill_value_defined(dcpl.get(), &defined) >= 0 && defined != H5D_FILL_VALUE_UNDEFINED &&
            H5Pget_fill_value(dcpl.get(), h_->type.get(), header_.fill.data()) < 0)
            fail(where, "cannot read the fill value");
        H5Eclear2(H5E_DEFAULT);
    }
    header_.storage_bytes = H5Dget_storage_size(h_->dataset.get());
    if (layout == H5D_CONTIGUOUS) {
        const haddr_t at = H5Dget_offset(h_->dataset.get());
        if (at != HADDR_UNDEF) header_.data_offset = static_cast<std::uint64_t>(at);
        H5Eclear2(H5E_DEFAULT);
    }
    header_.spacing = triple_attribute(h_->dataset.get(), "spacing", where);
    header_.origin = triple_attribute(h_->dataset.get(), "origin", where);
    header_.element_size_um = triple_attribute(h_->dataset.get(), "element_size_um", where);
    h_->leading = header_.shape.size() >= 3 ? header_.shape.size() - 3 : 0;
}

Hdf5Dataset::~Hdf5Dataset() = default;
Hdf5Dataset::Hdf5Dataset(Hdf5Dataset&&) noexcept = default;
Hdf5Dataset& Hdf5Dataset::operator=(Hdf5Dataset&&) noexcept = default;

bool Hdf5Dataset::read_chunk(std::int64_t z, std::int64_t y, std::int64_t x, std::uint64_t max_bytes, std::vector<std::byte>& raw,
                             unsigned& mask) {
    const std::size_t rank = header_.shape.size();
    hsize_t offset[H5S_MAX_RANK] = {};
    offset[rank - 3] = static_cast<hsize_t>(z);
    offset[rank - 2] = static_cast<hsize_t>(y);
    offset[rank - 1] = static_cast<hsize_t>(x);
    const std::string at = h_->where + ": chunk at (" + std::to_string(z) + ", " + std::to_string(y) + ", " + std::to_string(x) + ")";
    quiet();
    hsize_t bytes = 0;
    if (H5Dget_chunk_storage_size(h_->dataset.get(), offset, &bytes) < 0 || bytes == 0) {
        H5Eclear2(H5E_DEFAULT);  // never written: the fill value
        return false;
    }
    if (bytes > max_bytes)
        throw FormatError(at + ": " + std::to_string(bytes) + " stored bytes, more than it can hold (" + std::to_string(max_bytes) + ")");
    raw.resize(static_cast<std::size_t>(bytes));
    std::uint32_t filters = 0;
    if (H5Dread_chunk(h_->dataset.get(), H5P_DEFAULT, offset, &filters, raw.data()) < 0) fail(at, "cannot read its stored bytes");
    mask = filters;
    return true;
}

void Hdf5Dataset::read_slices(std::int64_t z0, std::int64_t count, SampleType as, std::byte* out) {
    const std::size_t rank = header_.shape.size();
    if (rank < 3) throw FormatError(h_->where + ": not a 3-D dataset");
    hsize_t start[H5S_MAX_RANK] = {}, block[H5S_MAX_RANK] = {};
    for (std::size_t d = 0; d < rank; ++d) block[d] = 1;
    start[rank - 3] = static_cast<hsize_t>(z0);
    block[rank - 3] = static_cast<hsize_t>(count);
    block[rank - 2] = static_cast<hsize_t>(header_.shape[rank - 2]);
    block[rank - 1] = static_cast<hsize_t>(header_.shape[rank - 1]);
    Id file_space(H5Scopy(h_->space.get()), H5Sclose);
    if (!file_space.valid() || H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, block, nullptr) < 0)
        fail(h_->where, "cannot select slices " + std::to_string(z0) + ".." + std::to_string(z0 + count - 1));
    const hsize_t n = block[rank - 3] * block[rank - 2] * block[rank - 1];
    Id memory(H5Screate_simple(1, &n, nullptr), H5Sclose);
    hid_t type = H5T_NATIVE_UCHAR;
    switch (as) {
        case SampleType::u8: type = H5T_NATIVE_UCHAR; break;
        case SampleType::i16: type = H5T_NATIVE_SHORT; break;
        case SampleType::u16: type = H5T_NATIVE_USHORT; break;
        case SampleType::f32: type = H5T_NATIVE_FLOAT; break;
    }
    quiet();
    if (!memory.valid() || H5Dread(h_->dataset.get(), type, memory.get(), file_space.get(), H5P_DEFAULT, out) < 0)
        fail(h_->where, "cannot read slices " + std::to_string(z0) + ".." + std::to_string(z0 + count - 1) +
                            " (a truncated or corrupt file, or a chunk that does not decode)");
}

}  // namespace meshless

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MESHLESS_HDF5_UNDER_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(MESHLESS_HDF5_UNDER_ASAN)
// The sanitizer tier: LeakSanitizer's suppressions for this process. libhdf5 1.10 (Debian's build, not
// ours) leaks a few hundred bytes inside H5Fopen when it refuses a corrupt file; every handle this
// file opens is closed by its Id, so the leaks reported with libhdf5 on their allocation stack are
// libhdf5's own.
extern "C" const char* __lsan_default_suppressions() { return "leak:libhdf5_serial.so\n"; }
#endif
