// formats/hdf5_dataset.hpp in a build configured without libhdf5 (MESHLESS_WITH_HDF5=OFF): an HDF5
// input is refused in one line saying so. CMake compiles this file instead of hdf5_library.cpp.
#include "formats/hdf5_dataset.hpp"

#include "kernels/errors.hpp"

namespace meshless {

namespace {
[[noreturn]] void no_reader(const std::string& file) {
    throw FormatError(file + ": this build has no HDF5 reader (configured without libhdf5: install libhdf5-dev and "
                             "configure with -DMESHLESS_WITH_HDF5=ON)");
}
}  // namespace

struct Hdf5Dataset::Handles {};

bool hdf5_reader_available() { return false; }

std::vector<Hdf5Listing> hdf5_volume_datasets(const std::string& file, std::size_t, bool&) { no_reader(file); }

Hdf5Dataset::Hdf5Dataset(const std::string& file, const std::string&) { no_reader(file); }
Hdf5Dataset::Hdf5Dataset(const std::string& file, const std::string&, Parsed) { no_reader(file); }
Hdf5Dataset::~Hdf5Dataset() = default;
Hdf5Dataset::Hdf5Dataset(Hdf5Dataset&&) noexcept = default;
Hdf5Dataset& Hdf5Dataset::operator=(Hdf5Dataset&&) noexcept = default;

bool Hdf5Dataset::read_chunk(std::int64_t, std::int64_t, std::int64_t, std::uint64_t, std::vector<std::byte>&, unsigned&) {
    no_reader("HDF5 dataset");
}

void Hdf5Dataset::read_slices(std::int64_t, std::int64_t, SampleType, std::byte*) { no_reader("HDF5 dataset"); }

}  // namespace meshless
