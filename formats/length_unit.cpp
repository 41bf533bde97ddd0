#include "formats/length_unit.hpp"

#include <array>
#include <cctype>

#include "formats/text_header.hpp"

namespace meshless {

namespace {
struct UnitName {
    const char* spelling;
    const char* unit;
};
constexpr std::array<UnitName, 17> kNames{{{"m", "m"},
                                           {"meter", "m"},
                                           {"metre", "m"},
                                           {"cm", "cm"},
                                           {"centimeter", "cm"},
                                           {"centimetre", "cm"},
                                           {"mm", "mm"},
                                           {"millimeter", "mm"},
                                           {"millimetre", "mm"},
                                           {"um", "um"},
                                           {"\xc2\xb5m", "um"},
                                           {"micrometer", "um"},
                                           {"micrometre", "um"},
                                           {"micron", "um"},
                                           {"nm", "nm"},
                                           {"nanometer", "nm"},
                                           {"nanometre", "nm"}}};
constexpr std::array<const char*, 6> kCodes{"", "m", "mm", "um", "nm", "cm"};
}  // namespace

std::string length_unit_from_name(std::string_view name) {
    while (!name.empty() && (std::isspace(static_cast<unsigned char>(name.front())) || name.front() == '"')) name.remove_prefix(1);
    while (!name.empty() && (std::isspace(static_cast<unsigned char>(name.back())) || name.back() == '"')) name.remove_suffix(1);
    std::string lower(name);
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    for (const UnitName& n : kNames)
        if (lower == n.spelling) return n.unit;
    return {};
}

std::uint32_t length_unit_code(const std::string& unit) {
    for (std::uint32_t c = 1; c < kCodes.size(); ++c)
        if (unit == kCodes[c]) return c;
    return 0;
}

std::string length_unit_of_code(std::uint32_t code) { return code < kCodes.size() ? kCodes[code] : ""; }

std::string value_unit_text(std::string_view written) {
    while (!written.empty() && (std::isspace(static_cast<unsigned char>(written.front())) || written.front() == '"')) written.remove_prefix(1);
    while (!written.empty() && (std::isspace(static_cast<unsigned char>(written.back())) || written.back() == '"')) written.remove_suffix(1);
    std::string text = escape_field(std::string(written));
    return text.size() <= 16 ? text : std::string();
}

std::string nifti_length_unit(std::uint8_t xyzt_units) {
    switch (xyzt_units & 7) {
        case 1: return "m";
        case 2: return "mm";
        case 3: return "um";
        default: return {};
    }
}

}  // namespace meshless
