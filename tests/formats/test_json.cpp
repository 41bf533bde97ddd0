// formats/json.hpp: the value tree of a document (numbers, strings with escapes, nesting, key
// order) and strict errors that name the file, with the file's bytes escaped.
#include <catch2/catch.hpp>

#include <string>
#include <string_view>

#include "formats/json.hpp"
#include "kernels/errors.hpp"

using namespace meshless;

namespace {

std::string message_of(std::string_view text) {
    try {
        (void)parse_json(text, "f.json");
    } catch (const FormatError& e) {
        return e.what();
    }
    return "(no FormatError)";
}

}  // namespace

TEST_CASE("json: values, escapes, nesting and key order", "[formats][json]") {
    const Json j = parse_json(R"( {"b": [1, -2.5e3, 18446744073709551615], "a": {"s": "x\"\u00e9\ud83d\ude00\n"},
                                  "t": true, "f": false, "n": null} )", "f.json");
    REQUIRE(j.is_object());
    REQUIRE(j.obj.size() == 5);
    CHECK(j.obj[0].key == "b");  // the document's order, not sorted
    CHECK(j.obj[1].key == "a");
    const Json* b = j.find("b");
    REQUIRE(b);
    REQUIRE(b->is_array());
    REQUIRE(b->arr.size() == 3);
    CHECK(b->arr[0].num == 1);
    CHECK(b->arr[1].num == -2500);
    CHECK(b->arr[2].num == 18446744073709551615.0);
    CHECK(j.find("a")->find("s")->str == "x\"\xc3\xa9\xf0\x9f\x98\x80\n");
    CHECK(j.find("t")->b);
    CHECK(j.find("f")->kind == Json::Kind::boolean);
    CHECK_FALSE(j.find("f")->b);
    CHECK(j.find("n")->is_null());
    CHECK(j.find("missing") == nullptr);
    CHECK(b->find("x") == nullptr);  // not an object
}

TEST_CASE("json: malformed documents fail with one clean line naming the file", "[formats][json]") {
    for (const char* bad : {"{\"a\": [0, 1,, 2]}", "{\"a\": 1,}", "[1, 2", "{\"a\" 1}", "{} x", "", "nul",
                            "\"\x1b[31m\"", "[1e999]", "\"\xff\xfe\""}) {
        INFO(bad);
        const std::string m = message_of(bad);
        CHECK_THAT(m, Catch::StartsWith("f.json: bad JSON"));
        for (const char c : m) CHECK(static_cast<unsigned char>(c) >= 0x20);  // file bytes escaped, one line
    }
    CHECK_THAT(message_of("{\"a\": [0, 1,, 2]}"), Catch::Contains("improper structure"));
    CHECK_THAT(message_of("[1e999]"), Catch::Contains("number"));
    // deep nesting is refused, not a stack overflow
    CHECK_THAT(message_of(std::string(100000, '[') + std::string(100000, ']')), Catch::Contains("deep"));
    // an empty view without storage (data() == nullptr, as an empty file gives): the same clean error, no
    // null pointer handed to memcpy (UBSan's nonnull-attribute check in the sanitizer tier; found by fuzz_vtkjs)
    CHECK_THAT(message_of(std::string_view()), Catch::StartsWith("f.json: bad JSON"));
}
