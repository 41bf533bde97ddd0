#include "formats/points_text.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdlib>

#include "formats/binary_file.hpp"
#include "formats/text_header.hpp"

namespace meshless {

namespace {

bool parse_number(std::string_view t, double& out) {
    if (t.empty()) return false;
    if (t.front() == '+') t.remove_prefix(1);
    const char* b = t.data();
    const char* e = b + t.size();
    auto r = std::from_chars(b, e, out);
    if (r.ec == std::errc() && r.ptr == e) return true;
    if (r.ec == std::errc::result_out_of_range && r.ptr == e) {  // denormals/overflow: let strtod decide
        out = std::strtod(std::string(t).c_str(), nullptr);
        return true;
    }
    return false;
}

bool is_number(std::string_view t) {
    double d;
    return parse_number(t, d);
}

std::string unquote(std::string s) {
    s = trim(s);
    if (s.size() >= 2 && (s.front() == '"' || s.front() == '\'') && s.back() == s.front()) s = s.substr(1, s.size() - 2);
    return s;
}

enum class Delim { comma, semicolon, space };

void split_fields(std::string_view line, Delim d, std::vector<std::string_view>& out) {
    out.clear();
    if (d == Delim::space) {
        std::size_t i = 0;
        while (i < line.size()) {
            while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
            std::size_t j = i;
            while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
            if (j > i) out.push_back(line.substr(i, j - i));
            i = j;
        }
        return;
    }
    const char c = d == Delim::comma ? ',' : ';';
    std::size_t i = 0;
    for (;;) {
        const std::size_t j = line.find(c, i);
        std::string_view f = line.substr(i, j == std::string_view::npos ? std::string_view::npos : j - i);
        while (!f.empty() && std::isspace(static_cast<unsigned char>(f.front()))) f.remove_prefix(1);
        while (!f.empty() && std::isspace(static_cast<unsigned char>(f.back()))) f.remove_suffix(1);
        out.push_back(f);
        if (j == std::string_view::npos) break;
        i = j + 1;
    }
}

bool is_comment(std::string_view l) {
    std::size_t i = 0;
    while (i < l.size() && std::isspace(static_cast<unsigned char>(l[i]))) ++i;
    if (i == l.size()) return true;  // blank
    return l[i] == '#' || l[i] == '%' || (l[i] == '/' && i + 1 < l.size() && l[i + 1] == '/');
}

struct Line {
    std::string_view text;
    std::uint64_t number;  // 1-based
};

}  // namespace

PointSet read_points_text(const std::string& path, const PointSetOptions& o, std::vector<std::string>* notes) {
    const auto bytes = read_file_bytes(path);
    const std::string_view doc(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    if (doc.find('\0') != std::string_view::npos) throw FormatError(path + ": not a text file (NUL bytes)");
    std::vector<Line> lines;
    {
        std::size_t i = 0;
        std::uint64_t n = 0;
        while (i < doc.size()) {
            std::size_t j = doc.find('\n', i);
            if (j == std::string_view::npos) j = doc.size();
            std::string_view l = doc.substr(i, j - i);
            if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
            ++n;
            if (!is_comment(l)) lines.push_back({l, n});
            i = j + 1;
        }
    }
    if (lines.empty()) throw FormatError(path + ": empty file (no points)");

    std::vector<std::string_view> f;
    const std::string_view first = lines.front().text;
    const Delim delim = first.find(',') != std::string_view::npos ? Delim::comma
                        : first.find(';') != std::string_view::npos ? Delim::semicolon
                                                                     : Delim::space;
    split_fields(first, delim, f);
    std::size_t data_begin = 0;
    std::optional<std::uint64_t> declared_count;
    std::vector<std::string> header;
    bool tagged = false;
    const bool all_numeric = std::all_of(f.begin(), f.end(), [](std::string_view t) { return is_number(t); });
    const bool none_numeric = std::none_of(f.begin(), f.end(), [](std::string_view t) { return is_number(t); });
    if (f.size() == 1 && all_numeric && lines.size() >= 1) {
        double c = 0;
        parse_number(f[0], c);
        // a count is a whole number a file can hold (below 2^53: exact as a double, and no overflow converting it)
        if (!(c >= 0) || c != std::floor(c) || c > 9007199254740992.0)
            throw FormatError(path + ": line " + std::to_string(lines[0].number) + ": bad point count " + escape_field(f[0]));
        declared_count = static_cast<std::uint64_t>(c);
        data_begin = 1;
    } else if (f.size() >= 2 && !is_number(f[0]) && f[0].size() == 1 && std::isalpha(static_cast<unsigned char>(f[0][0])) &&
               std::all_of(f.begin() + 1, f.end(), [](std::string_view t) { return is_number(t); })) {
        tagged = true;
    } else if (!all_numeric) {
        if (!none_numeric)
            throw FormatError(path + ": line " + std::to_string(lines[0].number) +
                              ": malformed header (mixes names and numbers): '" + std::string(first) + "'");
        for (auto t : f) {
            std::string name = unquote(std::string(t));
            if (name.empty())
                throw FormatError(path + ": line " + std::to_string(lines[0].number) + ": malformed header (empty column name)");
            if (std::find(header.begin(), header.end(), name) != header.end())
                throw FormatError(path + ": line " + std::to_string(lines[0].number) + ": malformed header (column '" + name +
                                  "' twice)");
            header.push_back(std::move(name));
        }
        data_begin = 1;
    }
    if (data_begin >= lines.size()) throw FormatError(path + ": no data lines after the header (no points)");

    // number of fields of the data rows
    split_fields(lines[data_begin].text, delim, f);
    std::size_t nfields = tagged ? 0 : f.size();
    if (!header.empty() && nfields != header.size())
        throw FormatError(path + ": line " + std::to_string(lines[data_begin].number) + ": " + std::to_string(nfields) +
                          " fields, the header names " + std::to_string(header.size()));
    const std::size_t ncols = tagged ? f.size() - 1 : nfields;

    auto header_list = [&] {
        std::string s;
        for (const auto& h : header) s += (s.empty() ? "" : ", ") + h;
        return s.empty() ? std::to_string(ncols) + " unnamed columns" : "columns: " + s;
    };
    auto find_col = [&](const std::string& key, bool required) -> int {
        double d;
        if (parse_number(key, d)) {
            if (d < 0 || d != std::floor(d) || d >= static_cast<double>(ncols)) {
                if (!required) return -1;
                throw FormatError(path + ": missing column " + key + " (" + header_list() + ")");
            }
            return static_cast<int>(d);
        }
        for (std::size_t i = 0; i < header.size(); ++i)
            if (to_lower(header[i]) == to_lower(key)) return static_cast<int>(i);
        if (required) throw FormatError(path + ": missing column '" + key + "' (" + header_list() + ")");
        return -1;
    };
    int cx = -1, cy = -1, cz = -1, cv = -1;
    if (!o.columns.empty()) {
        std::vector<std::string> keys;
        std::size_t i = 0;
        for (;;) {
            const std::size_t j = o.columns.find(',', i);
            keys.push_back(trim(o.columns.substr(i, j == std::string::npos ? std::string::npos : j - i)));
            if (j == std::string::npos) break;
            i = j + 1;
        }
        if (keys.size() != 3 && keys.size() != 4)
            throw FormatError(path + ": --columns '" + o.columns + "' must name 3 or 4 columns (x,y,z[,value])");
        cx = find_col(keys[0], true);
        cy = find_col(keys[1], true);
        cz = find_col(keys[2], true);
        if (keys.size() == 4) cv = find_col(keys[3], true);
    } else {
        if (!header.empty()) {
            cx = find_col("x", false);
            cy = find_col("y", false);
            cz = find_col("z", false);
            const int named = (cx >= 0) + (cy >= 0) + (cz >= 0);
            if (named > 0 && named < 3)  // the header names coordinates, but not all of them
                throw FormatError(path + ": missing column " + std::string(cx < 0 ? "x" : cy < 0 ? "y" : "z") + " (" +
                                  header_list() + "; give --columns to choose others)");
            if (named == 0) {  // other names (lon, lat, elev, ...): the first three columns, in order
                if (ncols < 3) throw FormatError(path + ": need 3 coordinate columns (" + header_list() + ")");
                cx = 0, cy = 1, cz = 2;
            }
        } else {
            if (ncols < 3) throw FormatError(path + ": line " + std::to_string(lines[data_begin].number) + ": " +
                                             std::to_string(ncols) + " columns, need at least 3 (x y z)");
            cx = 0, cy = 1, cz = 2;
        }
        if (!o.value_name.empty())
            cv = find_col(o.value_name, true);
        else if (o.value_index)
            cv = find_col(std::to_string(*o.value_index), true);
        else if (!header.empty()) {
            for (std::size_t i = 0; i < ncols && cv < 0; ++i)
                if (static_cast<int>(i) != cx && static_cast<int>(i) != cy && static_cast<int>(i) != cz) cv = static_cast<int>(i);
        } else if (!tagged && ncols >= 4) {
            cv = 3;
        }
    }
    std::string value_name;
    if (cv >= 0) value_name = header.empty() ? "column " + std::to_string(cv) : header[cv];

    PointSetBuilder b(path, o);
    b.reserve(lines.size() - data_begin);
    std::uint64_t rows = 0;
    const int cols[4] = {cx, cy, cz, cv};
    for (std::size_t li = data_begin; li < lines.size(); ++li) {
        const Line& L = lines[li];
        split_fields(L.text, delim, f);
        std::size_t off = 0;
        if (tagged) {
            if (f.empty() || (f[0] != "p" && f[0] != "v")) continue;
            off = 1;
        }
        if (f.size() - off != ncols)
            throw FormatError(path + ": line " + std::to_string(L.number) + ": " + std::to_string(f.size() - off) +
                              " fields, expected " + std::to_string(ncols));
        double v[4] = {0, 0, 0, 0};
        for (int k = 0; k < 4; ++k) {
            if (cols[k] < 0) continue;
            const std::string_view t = f[off + cols[k]];
            if (!parse_number(t, v[k]))
                throw FormatError(path + ": line " + std::to_string(L.number) + ": bad number '" + std::string(t) + "' in column " +
                                  std::to_string(cols[k]));
        }
        ++rows;
        b.add(v[0], v[1], v[2], v[3], "line", L.number);
    }
    if (declared_count && *declared_count != rows)
        throw FormatError(path + ": the first line says " + std::to_string(*declared_count) + " points, the file has " +
                          std::to_string(rows));
    if (notes && declared_count) notes->push_back("point count line: " + std::to_string(*declared_count));
    return b.finish(value_name, cv >= 0);
}

}  // namespace meshless
