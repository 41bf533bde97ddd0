#include "stream/field_project_stage.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "kernels/multiblock_splat_radius.hpp"

namespace meshless {

namespace {

// The point of a converged projection: position, unit normal -grad / |grad| (towards decreasing
// values, VTK's convention; converged implies a non-zero gradient), the given radius, value = iso.
PointRecord projected_point(const Vec3& pos, const Vec3& grad, float radius, double iso) {
    const Vec3 nrm = grad * (-1.0 / norm(grad));
    PointRecord r;
    r.pos[0] = static_cast<float>(pos.x);
    r.pos[1] = static_cast<float>(pos.y);
    r.pos[2] = static_cast<float>(pos.z);
    r.normal[0] = static_cast<float>(nrm.x);
    r.normal[1] = static_cast<float>(nrm.y);
    r.normal[2] = static_cast<float>(nrm.z);
    r.radius = radius;
    r.value = static_cast<float>(iso);
    return r;
}

// A projected batch holds points now: no cell range or brick of its own.
void mark_point_batch(Batch& b) {
    b.kind = RecordKind::point;
    b.cells = {};
    b.brick = -1;
}

}  // namespace

void AtomicFieldNewtonStats::add(const FieldNewtonStats& s) {
    const std::int64_t x[8] = {s.input, s.converged, s.flat, s.too_far, s.not_converged, s.stalled, s.nonfinite, s.evaluations};
    for (int i = 0; i < 8; ++i) v_[i].fetch_add(x[i], std::memory_order_relaxed);
}

FieldNewtonStats AtomicFieldNewtonStats::load() const {
    FieldNewtonStats s;
    s.input = v_[0].load();
    s.converged = v_[1].load();
    s.flat = v_[2].load();
    s.too_far = v_[3].load();
    s.not_converged = v_[4].load();
    s.stalled = v_[5].load();
    s.nonfinite = v_[6].load();
    s.evaluations = v_[7].load();
    return s;
}

void FieldProjectStage::process(Batch& b) const {
    const auto t0 = std::chrono::steady_clock::now();
    struct Busy {
        std::atomic<std::int64_t>& ns;
        std::chrono::steady_clock::time_point t0;
        ~Busy() { ns += std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0).count(); }
    } busy{busy_ns_, t0};
    if (b.kind == RecordKind::seed) return process_seeds(b);
    const bool samples = b.kind == RecordKind::sample;
    const std::size_t n = samples ? b.samples.size() : b.points.size();
    std::vector<Vec3> seeds(n), pos(n), grad(n);
    std::vector<float> radius(n);
    std::vector<double> limit;
    std::vector<FieldNewtonStatus> status(n);
    for (std::size_t i = 0; i < n; ++i) {
        const float* p = samples ? b.samples[i].pos : b.points[i].pos;
        seeds[i] = {p[0], p[1], p[2]};
        radius[i] = samples ? b.samples[i].radius : b.points[i].radius;
    }
    if (samples && p_.limit_to_cell) {
        limit.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            const float* s = b.samples[i].cell_size;
            const double half_diagonal = 0.5 * std::sqrt(double(s[0]) * s[0] + double(s[1]) * s[1] + double(s[2]) * s[2]);
            limit[i] = std::isfinite(half_diagonal) && half_diagonal > 0 ? std::min(p_.newton.max_displacement, half_diagonal)
                                                                         : p_.newton.max_displacement;
        }
    }
    FieldNewtonStats st;
    project_onto_field(f_, iso_, seeds, p_.newton, limit, pos, grad, status, st);

    std::vector<PointRecord> out;
    out.reserve(static_cast<std::size_t>(st.converged));
    // points that carry block ids keep those of the points that converged
    const bool blocks = !samples && b.point_block.size() == n && n > 0;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (status[i] != FieldNewtonStatus::converged) continue;
        if (blocks) b.point_block[kept++] = b.point_block[i];
        out.push_back(projected_point(pos[i], grad[i], radius[i], iso_));
    }
    b.points = std::move(out);
    if (blocks) b.point_block.resize(kept);
    else b.point_block.clear();
    b.samples.clear();
    b.samples.shrink_to_fit();
    mark_point_batch(b);
    stats_.add(st);
}

void FieldProjectStage::process_seeds(Batch& b) const {
    const std::size_t n = b.seeds.size();
    std::vector<Vec3> seeds(n), pos(n), grad(n);
    std::vector<double> tolerance(n), limit;
    std::vector<FieldNewtonStatus> status(n);
    const bool limited = std::isfinite(p_.seed_max_travel);
    if (limited) limit.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const SeedRecord& s = b.seeds[i];
        seeds[i] = {s.pos[0], s.pos[1], s.pos[2]};
        tolerance[i] = p_.seed_tolerance * s.cell_diagonal;
        if (limited) limit[i] = p_.seed_max_travel * s.cell_diagonal;
    }
    FieldNewtonStats st;
    FieldNewtonParams np = p_.newton;
    np.final_step = p_.seed_final_step;
    project_onto_field(f_, iso_, seeds, np, limit, pos, grad, status, st, tolerance);

    std::vector<PointRecord>& out = b.points;  // a recycled batch brings its capacity
    std::vector<std::uint32_t>& block = b.point_block;
    out.clear();
    block.clear();
    out.reserve(static_cast<std::size_t>(st.converged));
    block.reserve(static_cast<std::size_t>(st.converged));
    for (std::size_t i = 0; i < n; ++i) {
        if (status[i] != FieldNewtonStatus::converged) continue;
        const SeedRecord& s = b.seeds[i];
        const double radius = multiblock_splat_radius(s.base_radius, norm(pos[i] - seeds[i]), s.cell_diagonal);
        out.push_back(projected_point(pos[i], grad[i], static_cast<float>(radius), iso_));
        block.push_back(s.block);
    }
    b.seeds.clear();
    b.seeds.shrink_to_fit();
    mark_point_batch(b);
    stats_.add(st);
}

}  // namespace meshless
