// DICOM test series, written at test time by tests/formats/make_dicom_series.py with Debian's
// python3-pydicom (nothing is copied from shared data). A test without pydicom is skipped with a
// warning saying so; any other failure of the generator fails the test.
#pragma once
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "test_paths.hpp"

namespace meshless::test {

/// Writes CASE (see make_dicom_series.py) as dir/CASE (and dir/CASE.nrrd for "ct" and "flipped");
/// nullopt when pydicom is absent.
inline std::optional<std::filesystem::path> make_dicom_case(const std::string& name, const TempDir& dir) {
    const std::filesystem::path out = dir / name;
    const std::string cmd = "/usr/bin/python3 '" MESHLESS_SOURCE_DIR "/tests/formats/make_dicom_series.py' " + name + " '" +
                            out.string() + "' '" + shared_data().string() + "' 2>'" + (dir / "generator.err").string() + "'";
    const int status = std::system(cmd.c_str());
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
    if (code == 3) {
        WARN("python3-pydicom is not installed: skipping this DICOM test (apt-get install python3-pydicom)");
        return std::nullopt;
    }
    INFO("make_dicom_series.py " << name << " exited " << code);
    REQUIRE(code == 0);
    return out;
}

}  // namespace meshless::test
