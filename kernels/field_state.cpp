#include "kernels/field_state.hpp"

#include <bit>
#include <cmath>
#include <string>
#include <unordered_map>

#include "kernels/errors.hpp"
#include "kernels/global_rbf_field.hpp"
#include "kernels/mpu_field.hpp"
#include "kernels/rbf_grid_field.hpp"

namespace meshless {

std::size_t state_type_size(std::uint32_t code) {
    switch (code) {
        case static_cast<std::uint32_t>(StateType::f64): return 8;
        case static_cast<std::uint32_t>(StateType::i64): return 8;
        case static_cast<std::uint32_t>(StateType::u32): return 4;
        case static_cast<std::uint32_t>(StateType::i32): return 4;
    }
    return 0;
}

const char* state_type_name(StateType t) {
    switch (t) {
        case StateType::f64: return "f64";
        case StateType::i64: return "i64";
        case StateType::u32: return "u32";
        case StateType::i32: return "i32";
    }
    return "?";
}

namespace {

template <class T>
constexpr StateType type_of();
template <>
constexpr StateType type_of<double>() { return StateType::f64; }
template <>
constexpr StateType type_of<std::int64_t>() { return StateType::i64; }
template <>
constexpr StateType type_of<std::uint32_t>() { return StateType::u32; }
template <>
constexpr StateType type_of<std::int32_t>() { return StateType::i32; }

StateType type_of_array(const StateArray& a) {
    return std::visit([](const auto& v) { return type_of<typename std::decay_t<decltype(v)>::value_type>(); }, a);
}

std::size_t size_of_array(const StateArray& a) {
    return std::visit([](const auto& v) { return v.size(); }, a);
}

}  // namespace

void FieldState::add(std::string name, StateArray array, std::string where) {
    if (find(name)) throw FormatError(prefix_ + where + ": a second array '" + name + "'");
    entries_.push_back(Entry{std::move(name), std::move(where), std::move(array), false});
}

const FieldState::Entry* FieldState::find(std::string_view name) const {
    for (const Entry& e : entries_)
        if (e.name == name) return &e;
    return nullptr;
}

void FieldState::fail(std::string_view name, const std::string& what) const {
    const Entry* e = find(name);
    throw FormatError(prefix_ + (e ? e->where : missing_where_) + ": " + what);
}

template <class T>
std::vector<T> FieldState::take(std::string_view name, std::size_t expected, StateType type) {
    Entry* e = const_cast<Entry*>(find(name));
    if (!e) throw FormatError(prefix_ + missing_where_ + ": no array '" + std::string(name) + "'");
    if (e->taken) fail(name, "array '" + std::string(name) + "' used twice");
    if (type_of_array(e->array) != type)
        fail(name, std::string("array '") + std::string(name) + "' holds " + state_type_name(type_of_array(e->array)) +
                       ", expected " + state_type_name(type));
    if (expected > 0 && size_of_array(e->array) != expected)
        fail(name, "array '" + std::string(name) + "' holds " + std::to_string(size_of_array(e->array)) +
                       " elements, expected " + std::to_string(expected));
    e->taken = true;
    return std::move(std::get<std::vector<T>>(e->array));
}

std::vector<double> FieldState::take_f64(std::string_view name, std::size_t expected) {
    return take<double>(name, expected, StateType::f64);
}
std::vector<std::int64_t> FieldState::take_i64(std::string_view name, std::size_t expected) {
    return take<std::int64_t>(name, expected, StateType::i64);
}
std::vector<std::uint32_t> FieldState::take_u32(std::string_view name, std::size_t expected) {
    return take<std::uint32_t>(name, expected, StateType::u32);
}
std::vector<std::int32_t> FieldState::take_i32(std::string_view name, std::size_t expected) {
    return take<std::int32_t>(name, expected, StateType::i32);
}

void FieldState::check_all_taken() const {
    for (const Entry& e : entries_)
        if (!e.taken) throw FormatError(prefix_ + e.where + ": array '" + e.name + "' is not part of this field");
}

void put_frame(FieldStateWriter& w, const Vec3& origin, const Vec3& scale, const std::array<Vec3, 2>& bounds) {
    const double f[12] = {origin.x,    origin.y,    origin.z,    scale.x,     scale.y,     scale.z,
                          bounds[0].x, bounds[0].y, bounds[0].z, bounds[1].x, bounds[1].y, bounds[1].z};
    w.put("frame", std::span<const double>(f, 12));
}

void take_frame(FieldState& s, Vec3& origin, Vec3& scale, std::array<Vec3, 2>& bounds) {
    const std::vector<double> f = s.take_f64("frame", 12);
    for (double v : f)
        if (!std::isfinite(v)) s.fail("frame", "non-finite frame value");
    origin = {f[0], f[1], f[2]};
    scale = {f[3], f[4], f[5]};
    bounds = {Vec3{f[6], f[7], f[8]}, Vec3{f[9], f[10], f[11]}};
    if (!(scale.x > 0 && scale.y > 0 && scale.z > 0)) s.fail("frame", "axis scale not > 0");
    for (int a = 0; a < 3; ++a)
        if (!(bounds[0][a] <= bounds[1][a])) s.fail("frame", "bounds with lo > hi");
}

void put_locals(FieldStateWriter& w, std::span<const MultiquadricLocal> locals) {
    std::vector<double> f;
    std::vector<std::uint32_t> r;
    f.reserve(locals.size() * 8);
    r.reserve(locals.size() * 2);
    for (const MultiquadricLocal& h : locals) {
        f.insert(f.end(), {h.origin.x, h.origin.y, h.origin.z, h.a0, h.a.x, h.a.y, h.a.z, h.c2});
        r.insert(r.end(), {h.first, h.count});
    }
    w.put("locals", std::span<const double>(f));
    w.put("local_ranges", std::span<const std::uint32_t>(r));
}

std::vector<MultiquadricLocal> take_locals(FieldState& s) {
    const std::vector<double> f = s.take_f64("locals");
    if (f.size() % 8 != 0) s.fail("locals", "array 'locals' holds " + std::to_string(f.size()) + " values, not 8 per local");
    const std::size_t n = f.size() / 8;
    const std::vector<std::uint32_t> r = s.take_u32("local_ranges", n == 0 ? 0 : 2 * n);
    if (r.size() != 2 * n) s.fail("local_ranges", "array 'local_ranges' holds " + std::to_string(r.size()) + " values, expected " + std::to_string(2 * n));
    std::vector<MultiquadricLocal> out(n);
    for (std::size_t l = 0; l < n; ++l) {
        const double* v = f.data() + 8 * l;
        for (int k = 0; k < 8; ++k)
            if (!std::isfinite(v[k])) s.fail("locals", "local " + std::to_string(l) + ": non-finite coefficient");
        if (!(v[7] >= 0)) s.fail("locals", "local " + std::to_string(l) + ": c^2 < 0");
        MultiquadricLocal& h = out[l];
        h.origin = {v[0], v[1], v[2]};
        h.a0 = v[3];
        h.a = {v[4], v[5], v[6]};
        h.c2 = v[7];
        h.first = r[2 * l];
        h.count = r[2 * l + 1];
    }
    return out;
}

void check_local_ranges(const FieldState& s, std::span<const MultiquadricLocal> locals, std::size_t terms) {
    for (std::size_t l = 0; l < locals.size(); ++l) {
        const MultiquadricLocal& h = locals[l];
        if (h.count > 0 && static_cast<std::uint64_t>(h.first) + h.count > terms)
            s.fail("local_ranges", "local " + std::to_string(l) + " reads terms " + std::to_string(h.first) + ".." +
                                       std::to_string(static_cast<std::uint64_t>(h.first) + h.count) + ", beyond the " +
                                       std::to_string(terms) + " stored");
    }
}

namespace {

struct CentreKey {
    std::uint64_t x, y, z;
    bool operator==(const CentreKey&) const = default;
};
struct CentreHash {
    std::size_t operator()(const CentreKey& k) const {
        std::uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
        h = (h ^ (h >> 29) ^ k.y) * 0xBF58476D1CE4E5B9ull;
        h = (h ^ (h >> 31) ^ k.z) * 0x94D049BB133111EBull;
        return static_cast<std::size_t>(h ^ (h >> 32));
    }
};

}  // namespace

void put_centres(FieldStateWriter& w, std::span<const double> px, std::span<const double> py, std::span<const double> pz) {
    std::unordered_map<CentreKey, std::uint32_t, CentreHash> seen;
    seen.reserve(px.size() / 4 + 16);
    std::vector<double> centres;
    std::vector<std::uint32_t> index(px.size());
    for (std::size_t i = 0; i < px.size(); ++i) {
        const CentreKey k{std::bit_cast<std::uint64_t>(px[i]), std::bit_cast<std::uint64_t>(py[i]), std::bit_cast<std::uint64_t>(pz[i])};
        const auto [it, fresh] = seen.try_emplace(k, static_cast<std::uint32_t>(centres.size() / 3));
        if (fresh) centres.insert(centres.end(), {px[i], py[i], pz[i]});
        index[i] = it->second;
    }
    w.put("centres", std::span<const double>(centres));
    w.put("centre_index", std::span<const std::uint32_t>(index));
}

void take_centres(FieldState& s, std::vector<double>& px, std::vector<double>& py, std::vector<double>& pz) {
    const std::vector<double> c = s.take_f64("centres");
    if (c.size() % 3 != 0) s.fail("centres", "array 'centres' does not hold 3 values per centre");
    const std::vector<std::uint32_t> index = s.take_u32("centre_index");
    const std::size_t nc = c.size() / 3, n = index.size();
    s.resize(px, n);
    s.resize(py, n);
    s.resize(pz, n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t k = index[i];
        if (k >= nc) s.fail("centre_index", "entry " + std::to_string(i) + " names centre " + std::to_string(k) + " of " + std::to_string(nc));
        px[i] = c[3 * k];
        py[i] = c[3 * k + 1];
        pz[i] = c[3 * k + 2];
    }
}

FieldKind fitted_field_kind(const Field& field) {
    if (dynamic_cast<const RbfGridField*>(&field)) return FieldKind::rbf_grid;
    if (dynamic_cast<const MpuField*>(&field)) return FieldKind::mpu;
    if (dynamic_cast<const GlobalRbfField*>(&field)) return FieldKind::global_rbf;
    throw InvalidArgument("a " + field.name() + " field has no saved form (only rbf-grid, mpu and global-rbf)");
}

void save_field_state(const Field& field, FieldStateWriter& w) {
    if (auto* f = dynamic_cast<const RbfGridField*>(&field)) return f->save_state(w);
    if (auto* f = dynamic_cast<const MpuField*>(&field)) return f->save_state(w);
    if (auto* f = dynamic_cast<const GlobalRbfField*>(&field)) return f->save_state(w);
    throw InvalidArgument("a " + field.name() + " field has no saved form (only rbf-grid, mpu and global-rbf)");
}

std::unique_ptr<Field> load_field_state(FieldKind kind, FieldState& state) {
    std::unique_ptr<Field> f;
    switch (kind) {
        case FieldKind::rbf_grid: f = RbfGridField::load_state(state); break;
        case FieldKind::mpu: f = MpuField::load_state(state); break;
        case FieldKind::global_rbf: f = GlobalRbfField::load_state(state); break;
    }
    if (!f) throw InvalidArgument("load_field_state: unknown field kind");
    state.check_all_taken();
    return f;
}

}  // namespace meshless
