// JSON documents (RFC 8259) for metadata files such as vtk-js index.json and PLOT3D .p3d, parsed
// by simdjson (kept inside json.cpp, so this header stays light) into a plain value tree.
// simdjson over nlohmann-json and the former hand-written parser: 1.7 us for LIDC2's index.json
// against 2.6 us (hand-written), 4.8 us (nlohmann SAX) and 9.6 us (nlohmann DOM).
//
// Numbers are doubles; objects keep their key order (linear lookup: meant for small documents).
// Strict: no comments, no trailing commas, valid UTF-8. Throws FormatError("PATH: bad JSON: WHAT",
// simdjson's description of the defect; it reports no offset) on malformed input, including
// trailing garbage. Nesting is limited to 256 levels. Thread-safety: values are immutable after parsing.
// Dissertation: input plumbing.
#pragma once
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace meshless {

struct Json {
    struct Member;  ///< one object member: key and value (a struct, not std::pair: Clang's libstdc++ pair needs Json complete)
    enum class Kind { null, boolean, number, string, array, object };
    Kind kind = Kind::null;
    bool b = false;
    double num = 0;
    std::string str;
    std::vector<Json> arr;
    std::vector<Member> obj;

    bool is_null() const { return kind == Kind::null; }
    bool is_number() const { return kind == Kind::number; }
    bool is_string() const { return kind == Kind::string; }
    bool is_array() const { return kind == Kind::array; }
    bool is_object() const { return kind == Kind::object; }
    /// Member of an object, nullptr if absent or not an object.
    const Json* find(std::string_view key) const;
};

struct Json::Member {
    std::string key;
    Json value;
};

Json parse_json(std::string_view text, const std::string& path);

}  // namespace meshless
