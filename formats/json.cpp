#include "formats/json.hpp"

#include <simdjson.h>

#include "formats/ply.hpp"
#include "kernels/errors.hpp"

namespace meshless {

const Json* Json::find(std::string_view key) const {
    if (kind != Kind::object) return nullptr;
    for (const auto& [k, v] : obj)
        if (k == key) return &v;
    return nullptr;
}

namespace {

constexpr int kMaxDepth = 256;

Json convert(simdjson::dom::element e, int depth, const std::string& path) {
    if (depth > kMaxDepth) throw FormatError(path + ": bad JSON: nesting deeper than " + std::to_string(kMaxDepth) + " levels");
    Json v;
    switch (e.type()) {
        case simdjson::dom::element_type::NULL_VALUE: break;
        case simdjson::dom::element_type::BOOL:
            v.kind = Json::Kind::boolean;
            v.b = bool(e);
            break;
        case simdjson::dom::element_type::INT64:
            v.kind = Json::Kind::number;
            v.num = static_cast<double>(std::int64_t(e));
            break;
        case simdjson::dom::element_type::UINT64:
            v.kind = Json::Kind::number;
            v.num = static_cast<double>(std::uint64_t(e));
            break;
        case simdjson::dom::element_type::DOUBLE:
            v.kind = Json::Kind::number;
            v.num = double(e);
            break;
        case simdjson::dom::element_type::STRING:
            v.kind = Json::Kind::string;
            v.str = std::string_view(e);
            break;
        case simdjson::dom::element_type::ARRAY: {
            v.kind = Json::Kind::array;
            const simdjson::dom::array a(e);
            v.arr.reserve(a.size());
            for (const simdjson::dom::element c : a) v.arr.push_back(convert(c, depth + 1, path));
            break;
        }
        case simdjson::dom::element_type::OBJECT: {
            v.kind = Json::Kind::object;
            const simdjson::dom::object o(e);
            v.obj.reserve(o.size());
            for (const simdjson::dom::key_value_pair f : o)
                v.obj.push_back(Json::Member{std::string(f.key), convert(f.value, depth + 1, path)});
            break;
        }
    }
    return v;
}

}  // namespace

Json parse_json(std::string_view text, const std::string& path) {
    simdjson::dom::parser parser;
    simdjson::dom::element root;
    // copies the text into a padded buffer (simdjson reads in SIMD-wide blocks); an empty view may
    // hold a null pointer, which simdjson would pass to memcpy (undefined even for 0 bytes)
    const char* bytes = text.empty() ? "" : text.data();
    if (const simdjson::error_code err = parser.parse(bytes, text.size()).get(root))
        throw FormatError(path + ": bad JSON: " + ply_escape(simdjson::error_message(err), 200));
    return convert(root, 0, path);
}

}  // namespace meshless
