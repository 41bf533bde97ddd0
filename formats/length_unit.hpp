// The units a volume's file states, for pictures' labels: the values' (value_unit_text) and the
// length unit of its world coordinates, where its file says it: NIfTI xyzt_units,
// NRRD `space units`, OME-Zarr axes' `unit`, DICOM (millimetres by the standard). One short name
// each ("mm", "um", ...), the empty string when the file says nothing (raw, VTK, MetaImage, HDF5,
// plain Zarr: their numbers are the data's own units, whatever those are). Pictures print it on the
// scale bar and draw the axes by default only when it is known. Brick stores record it as a code.
// Dissertation: none (file metadata). Pure; throws nothing but std::bad_alloc.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>

namespace meshless {

/// The short name of a unit a file spells (case-insensitive; quotes and spaces around it ignored):
/// "m"/"meter"/"metre", "cm"/"centimeter", "mm"/"millimeter"/"millimetre", "um"/"micrometer"/
/// "micron"/"µm", "nm"/"nanometer"; "" for anything else.
std::string length_unit_from_name(std::string_view name);
/// A brick store's code of a short name (0: none or unknown; 1 m, 2 mm, 3 um, 4 nm, 5 cm).
std::uint32_t length_unit_code(const std::string& unit);
/// The short name of a code ("" for 0 and codes it does not know).
std::string length_unit_of_code(std::uint32_t code);
/// A values' unit as a file writes it ("HU", "\"kg/m^3\"", ...), kept for labels: quotes and spaces
/// around it dropped, bytes outside printable ASCII escaped (formats/text_header.hpp escape_field),
/// at most 16 bytes (a brick store's field; longer: ""), else "".
std::string value_unit_text(std::string_view written);
/// NIfTI-1 xyzt_units (header byte 123; its low three bits): 1 m, 2 mm, 3 um; "" otherwise.
std::string nifti_length_unit(std::uint8_t xyzt_units);

}  // namespace meshless
