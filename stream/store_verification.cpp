#include "stream/store_verification.hpp"

#include "formats/file_names.hpp"
#include "formats/terminal_safe.hpp"
#include "formats/point_store.hpp"
#include "kernels/errors.hpp"
#include "ooc/sample_store.hpp"
#include "ooc/verify_brick_store.hpp"
#include "ooc/verify_point_store.hpp"

namespace meshless {

StoreKind verified_store_kind(const std::string& path) {
    if (is_point_store(path) || lower_extension(path) == ".mlc") return StoreKind::point;
    if (is_sample_store(path)) return StoreKind::sample;
    return StoreKind::brick;
}

StoreVerdict verify_store(const std::string& path, StoreKind kind, std::uint64_t budget_bytes,
                          const std::function<void(std::uint64_t, std::uint64_t)>& progress) {
    switch (kind) {
        case StoreKind::point: {
            const PointStoreVerifyReport r = verify_point_store(path, progress);
            return {r.ok ? 0 : 2, r.message};
        }
        case StoreKind::sample:
            try {
                const auto store = SampleStore::open(path);
                store->verify();
                return {0, "ok: " + std::to_string(store->info().bucket_count) + " buckets, " +
                               std::to_string(store->info().key_count) + " cell rows"};
            } catch (const FormatError& e) {
                return {2, e.what()};
            } catch (const IoError& e) {
                return {2, e.what()};
            }
        case StoreKind::brick: break;
    }
    const VerifyReport r = verify_brick_store(path, budget_bytes, progress);
    return {r.ok ? 0 : r.over_budget ? 1 : 2, r.message};
}

void print_store_verdict(std::FILE* out, std::FILE* err, const std::string& path, const StoreVerdict& v, bool several) {
    if (v.status == 0) {
        if (several) std::fprintf(out, "%s: %s\n", terminal_safe(path).c_str(), terminal_safe(v.message).c_str());
        else std::fprintf(out, "%s\n", terminal_safe(v.message).c_str());
    } else {
        std::fflush(out);  // the results so far before this error, in a log of both streams
        std::fprintf(err, "meshless verify: %s\n", terminal_safe(v.message).c_str());
    }
}

}  // namespace meshless
