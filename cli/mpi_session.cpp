// The MPI implementation of cli/mpi_session.hpp (only file that includes mpi.h).
#ifdef MESHLESS_HAVE_MPI
#include "cli/mpi_session.hpp"

#include <mpi.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "kernels/errors.hpp"

namespace meshless::cli {

int launched_world_size() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
        if (const char* s = std::getenv(v)) return std::max(1, std::atoi(s));
    return 1;
}

bool mpi_built() { return true; }

MpiSession::MpiSession(int* argc, char*** argv) {
    int inited = 0;
    MPI_Initialized(&inited);
    if (!inited) MPI_Init(argc, argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Finalize();
}

std::vector<std::byte> MpiSession::gather_to_root(const void* data, std::size_t bytes) {
    // sizes first, then point-to-point in chunks below INT_MAX bytes, in rank order
    const std::uint64_t mine = bytes;
    std::vector<std::uint64_t> sizes(static_cast<std::size_t>(size_));
    MPI_Gather(&mine, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
    constexpr std::size_t kChunk = std::size_t{1} << 30;
    std::vector<std::byte> all;
    if (rank_ == 0) {
        std::uint64_t total = 0;
        for (auto s : sizes) total += s;
        all.resize(total);
        std::memcpy(all.data(), data, bytes);
        std::size_t at = bytes;
        for (int r = 1; r < size_; ++r) {
            for (std::uint64_t done = 0; done < sizes[r];) {
                const std::size_t n = std::min<std::uint64_t>(kChunk, sizes[r] - done);
                MPI_Recv(all.data() + at, static_cast<int>(n), MPI_BYTE, r, 7, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
                at += n;
                done += n;
            }
        }
    } else {
        const auto* p = static_cast<const std::byte*>(data);
        for (std::size_t done = 0; done < bytes;) {
            const std::size_t n = std::min(kChunk, bytes - done);
            MPI_Send(const_cast<std::byte*>(p + done), static_cast<int>(n), MPI_BYTE, 0, 7, MPI_COMM_WORLD);
            done += n;
        }
    }
    return all;
}

std::vector<std::int64_t> MpiSession::sum_to_root(const std::vector<std::int64_t>& v) {
    std::vector<std::int64_t> out(v.size(), 0);
    MPI_Reduce(v.data(), out.data(), static_cast<int>(v.size()), MPI_INT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
    return out;
}

void MpiSession::abort(int code) {
    MPI_Abort(MPI_COMM_WORLD, code);
    std::exit(code);
}

}  // namespace meshless::cli
#endif
