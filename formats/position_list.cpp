#include "formats/position_list.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "formats/binary_file.hpp"
#include "formats/text_header.hpp"
#include "kernels/errors.hpp"

namespace meshless {

std::vector<Vec3> read_positions(const std::string& path) {
    std::error_code ec;
    if (path != "-" && std::filesystem::is_directory(path, ec)) throw IoError(path + ": is a directory, expected a file of positions");
    std::ifstream file;
    if (path != "-") {
        require_regular_file(path);
        file.open(path);
        if (!file) throw IoError(path + ": cannot open");
    }
    std::istream& in = path == "-" ? std::cin : file;
    std::vector<Vec3> out;
    std::string line;
    bool first_line = true;
    for (std::size_t n = 1; std::getline(in, line); ++n) {
        for (char& c : line)
            if (c == ',' || c == ';' || c == '\t') c = ' ';
        std::istringstream ls(line);
        std::string first;
        if (!(ls >> first) || first[0] == '#') continue;
        double v[3];
        std::istringstream all(line);
        if (!(all >> v[0] >> v[1] >> v[2])) {
            // a header: the first line (comments and blank lines aside) when it does not start
            // with a number ("x,y,z")
            double num;
            std::istringstream head(first);
            if (first_line && !(head >> num)) {
                first_line = false;
                continue;
            }
            throw FormatError(path + ":" + std::to_string(n) + ": expected x,y,z, got '" + escape_field(line) + "'");
        }
        if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
            throw FormatError(path + ":" + std::to_string(n) + ": non-finite position");
        first_line = false;
        out.push_back({v[0], v[1], v[2]});
    }
    if (in.bad()) throw IoError(path + ": read error");
    if (out.empty()) throw FormatError(path + ": no positions (expected lines of x,y,z)");
    return out;
}

}  // namespace meshless
