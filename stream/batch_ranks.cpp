#include "stream/batch_ranks.hpp"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>

#include "kernels/errors.hpp"
#include "stream/batch_archive.hpp"
#include "stream/batch_shard.hpp"
#include "stream/unit_deal.hpp"

namespace meshless {

namespace {

void put_u64(std::vector<std::byte>& out, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) out.push_back(static_cast<std::byte>(v >> (8 * i)));
}

void put_text(std::vector<std::byte>& out, const std::string& s) {
    put_u64(out, s.size());
    for (char c : s) out.push_back(static_cast<std::byte>(c));
}

struct Reader {
    std::span<const std::byte> in;
    std::size_t at = 0;
    std::uint64_t u64() {
        if (in.size() - at < 8) throw std::logic_error("batch ranks: a rank's results end early");
        std::uint64_t v = 0;
        for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(in[at + static_cast<std::size_t>(i)]) << (8 * i);
        at += 8;
        return v;
    }
    std::string text() {
        const std::uint64_t n = u64();
        if (in.size() - at < n) throw std::logic_error("batch ranks: a rank's results end early");
        std::string s(reinterpret_cast<const char*>(in.data() + at), static_cast<std::size_t>(n));
        at += static_cast<std::size_t>(n);
        return s;
    }
};

/// A rank's results as bytes: a length (so ranks can be told apart in the gathered bytes), the
/// run's time, then each volume.
std::vector<std::byte> encode(const BatchRun& run) {
    std::vector<std::byte> body;
    std::uint64_t ms;
    static_assert(sizeof(double) == sizeof(ms));
    std::memcpy(&ms, &run.seconds, sizeof ms);
    put_u64(body, ms);
    put_u64(body, run.items.size());
    for (const BatchItemResult& r : run.items) {
        put_text(body, r.name);
        put_u64(body, static_cast<std::uint64_t>(r.status));
        put_u64(body, static_cast<std::uint64_t>(r.written));
        put_u64(body, static_cast<std::uint64_t>(r.current));
        put_u64(body, static_cast<std::uint64_t>(r.empty));
        double seconds = r.seconds;
        std::uint64_t bits;
        std::memcpy(&bits, &seconds, sizeof bits);
        put_u64(body, bits);
        put_text(body, r.message);
        put_text(body, r.stops_run);
    }
    std::vector<std::byte> out;
    put_u64(out, body.size());
    out.insert(out.end(), body.begin(), body.end());
    return out;
}

double as_double(std::uint64_t bits) {
    double d;
    std::memcpy(&d, &bits, sizeof d);
    return d;
}

}  // namespace

BatchRun run_batch_ranks(const std::string& archive, BatchSettings s, const BatchCallbacks& cb, MpiSession& mpi,
                         std::function<void(std::exception_ptr)> on_deal_error) {
    if (s.shards != 1) throw InvalidArgument("batch under mpirun deals the volumes to the ranks itself: --shard is for runs without mpirun");
    s.shard = static_cast<std::uint32_t>(mpi.rank());
    s.shards = static_cast<std::uint32_t>(mpi.size());
    std::error_code ec;
    const auto listing = [&] {
        return std::filesystem::is_directory(archive, ec) ? list_archive_dir(archive, s.recursive, s.out_dir)
                                                          : read_manifest(archive, cb.parse_raw);
    };
    MpiChannel channel(mpi);
    std::optional<UnitDealer> dealer;
    std::optional<UnitDealService> service;
    std::vector<double> dealt_bytes;  // rank 0: the archive's bytes in the first k volumes of the size order, k = 0..
    if (mpi.rank() == 0) {
        // the first deal, after run_batch checked the archive and swept the temporaries, lists the
        // archive by size and starts answering the other ranks
        s.deal = [&]() -> std::optional<std::size_t> {
            if (!service) {
                std::vector<std::uint64_t> bytes;
                const std::vector<BatchItem> items = listing();
                dealt_bytes.assign(1, 0.0);
                for (const std::size_t i : size_order(items, &bytes)) dealt_bytes.push_back(dealt_bytes.back() + static_cast<double>(bytes[i]));
                dealer.emplace(items.size(), mpi.size());
                service.emplace(channel, *dealer, mpi.size(), on_deal_error);
            }
            return dealer->take(0);
        };
        s.dealt_share = [&] {
            if (!dealer || dealt_bytes.back() <= 0) return 0.0;
            std::size_t k = 0;
            for (const std::size_t n : dealer->dealt_per_rank()) k += n;
            return dealt_bytes[std::min(k, dealt_bytes.size() - 1)] / dealt_bytes.back();
        };
    } else {
        s.deal = [&] { return channel.request_unit(); };
    }
    BatchRun mine = run_batch(archive, s, cb);
    if (service) service->finish();
    const std::vector<std::byte> all = mpi.allgather(encode(mine));
    if (mpi.rank() != 0) return mine;
    BatchRun run;
    run.archive_count = mine.archive_count;
    Reader r{all};
    for (int rank = 0; rank < mpi.size(); ++rank) {
        const std::uint64_t n = r.u64();
        Reader one{std::span<const std::byte>(all).subspan(r.at, static_cast<std::size_t>(n))};
        r.at += static_cast<std::size_t>(n);
        run.seconds = std::max(run.seconds, as_double(one.u64()));
        const std::uint64_t items = one.u64();
        for (std::uint64_t i = 0; i < items; ++i) {
            BatchItemResult x;
            x.name = one.text();
            x.status = static_cast<BatchStatus>(one.u64());
            x.written = static_cast<int>(one.u64());
            x.current = static_cast<int>(one.u64());
            x.empty = static_cast<int>(one.u64());
            x.seconds = as_double(one.u64());
            x.message = one.text();
            x.stops_run = one.text();
            run.items.push_back(std::move(x));
        }
    }
    // archive order, as one process lists it (names are distinct: they are the outputs' names)
    const std::vector<BatchItem> listed = listing();
    std::map<std::string, std::size_t> order;
    for (std::size_t i = 0; i < listed.size(); ++i) order.emplace(listed[i].name, i);
    std::stable_sort(run.items.begin(), run.items.end(), [&](const BatchItemResult& a, const BatchItemResult& b) {
        const auto ia = order.find(a.name), ib = order.find(b.name);
        return (ia == order.end() ? listed.size() : ia->second) < (ib == order.end() ? listed.size() : ib->second);
    });
    return run;
}

}  // namespace meshless
