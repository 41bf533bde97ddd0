// The fitted state of a meshless field (dissertation sections 2.1.1, 4.3, 5.5) as named arrays of
// plain numbers: what evaluate() reads (merged points, coefficients, grid or octree, frame), so a
// field is fitted once, saved (formats/field_file.hpp writes the arrays as the sections of a .mlf)
// and loaded later evaluating bit-identically to the freshly built one.
//
// Saving: a field hands its arrays, one call each, to a FieldStateWriter (save_field_state).
// Loading: the reader fills a FieldState (arrays owned, typed, each with a "where" for messages),
// and load_field_state() moves them into a new field after validating them: array sizes against
// each other, every index in range, derived scalars recomputed and compared bit for bit, finite
// frame values. Anything else is FormatError, one line: "<prefix><where of the array>: <what>",
// e.g. "f.mlf: offset 4096: section 'runs': run 17 ends at point 1234, beyond the 1000 points".
// A state that passes evaluates safely (no index leaves its array); a hand-made one may evaluate
// to nonsense, never out of bounds.
// The three fields share the helpers below for their common parts (the frame world -> fitting
// coordinates, the local multiquadrics). Units: those of the fields. Thread-safety: a FieldState is
// a plain value (one user at a time); save_field_state is const on the field.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "kernels/field.hpp"
#include "kernels/field_params.hpp"
#include "kernels/multiquadric.hpp"

namespace meshless {

/// Element types of state arrays (the values are the .mlf's type codes).
enum class StateType : std::uint32_t { f64 = 1, i64 = 2, u32 = 3, i32 = 4 };
/// Bytes per element; 0 for an unknown code.
std::size_t state_type_size(std::uint32_t code);
const char* state_type_name(StateType t);

/// Receives a field's arrays (little-endian host layout; the span is valid during the call only).
class FieldStateWriter {
public:
    virtual ~FieldStateWriter() = default;
    virtual void put(std::string_view name, StateType type, const void* data, std::size_t count) = 0;
    void put(std::string_view name, std::span<const double> a) { put(name, StateType::f64, a.data(), a.size()); }
    void put(std::string_view name, std::span<const std::int64_t> a) { put(name, StateType::i64, a.data(), a.size()); }
    void put(std::string_view name, std::span<const std::uint32_t> a) { put(name, StateType::u32, a.data(), a.size()); }
    void put(std::string_view name, std::span<const std::int32_t> a) { put(name, StateType::i32, a.data(), a.size()); }
};

using StateArray = std::variant<std::vector<double>, std::vector<std::int64_t>, std::vector<std::uint32_t>,
                                std::vector<std::int32_t>>;

/// A field's arrays as read back, by name.
class FieldState {
public:
    /// prefix starts every message ("f.mlf: "); missing_where locates a missing array ("offset 123").
    explicit FieldState(std::string prefix = {}, std::string missing_where = "state") :
        prefix_(std::move(prefix)), missing_where_(std::move(missing_where)) {}
    /// Adds an array; where locates it ("offset 4096: section 'runs'"). A second array of one name is refused.
    void add(std::string name, StateArray array, std::string where);
    /// Moves array `name` out; FormatError when it is missing or of another type, or (expected > 0)
    /// when it does not hold exactly `expected` elements.
    std::vector<double> take_f64(std::string_view name, std::size_t expected = 0);
    std::vector<std::int64_t> take_i64(std::string_view name, std::size_t expected = 0);
    std::vector<std::uint32_t> take_u32(std::string_view name, std::size_t expected = 0);
    std::vector<std::int32_t> take_i32(std::string_view name, std::size_t expected = 0);
    /// FormatError "<prefix><where of name>: <what>".
    [[noreturn]] void fail(std::string_view name, const std::string& what) const;
    /// After a field took its arrays: FormatError naming the first array nobody took.
    void check_all_taken() const;
    std::size_t size() const { return entries_.size(); }
    /// How a field sizes the large arrays it rebuilds (the .mlf reader asks for huge pages, which
    /// saves most of the page faults of filling hundreds of MB); default std::vector::resize.
    using Resizer = void (*)(std::vector<double>& v, std::size_t n);
    void set_resizer(Resizer r) { resizer_ = r; }
    void resize(std::vector<double>& v, std::size_t n) const {
        if (resizer_) resizer_(v, n);
        else v.resize(n);
    }

private:
    struct Entry {
        std::string name, where;
        StateArray array;
        bool taken = false;
    };
    template <class T>
    std::vector<T> take(std::string_view name, std::size_t expected, StateType type);
    const Entry* find(std::string_view name) const;
    std::string prefix_, missing_where_;
    std::vector<Entry> entries_;
    Resizer resizer_ = nullptr;
};

// ---- Shared parts of the three fields.

/// The frame (world -> fitting coordinates: (world - origin) * scale) and the bounds: array "frame",
/// 12 doubles. take_frame checks finite values, scale > 0 and lo <= hi.
void put_frame(FieldStateWriter& w, const Vec3& origin, const Vec3& scale, const std::array<Vec3, 2>& bounds);
void take_frame(FieldState& s, Vec3& origin, Vec3& scale, std::array<Vec3, 2>& bounds);

/// Local multiquadrics: arrays "locals" (8 doubles each: origin, a0, a, c2) and "local_ranges"
/// (first, count). take_locals checks finite coefficients and c2 >= 0; the caller checks first and
/// count against its own arrays (check_local_ranges covers the common case).
void put_locals(FieldStateWriter& w, std::span<const MultiquadricLocal> locals);
std::vector<MultiquadricLocal> take_locals(FieldState& s);
/// Every local with count > 0 has first + count <= terms (the length of its lambda/centre arrays).
void check_local_ranges(const FieldState& s, std::span<const MultiquadricLocal> locals, std::size_t terms);

/// Centre coordinates that repeat (one point in several overlapping locals), stored once: arrays
/// "centres" (x, y, z of each distinct centre, in order of first use) and "centre_index" (u32 per
/// entry). take_centres rebuilds the three coordinate arrays bit for bit, checking every index.
void put_centres(FieldStateWriter& w, std::span<const double> px, std::span<const double> py, std::span<const double> pz);
void take_centres(FieldState& s, std::vector<double>& px, std::vector<double>& py, std::vector<double>& pz);

/// Writes the state of a field made by make_field() (RbfGridField, MpuField, GlobalRbfField);
/// InvalidArgument for any other Field.
void save_field_state(const Field& field, FieldStateWriter& w);
/// The kind of a field made by make_field(); InvalidArgument for any other Field.
FieldKind fitted_field_kind(const Field& field);
/// A field of `kind` from its state (validated, every array taken); FormatError as described above.
std::unique_ptr<Field> load_field_state(FieldKind kind, FieldState& state);

}  // namespace meshless
