#pragma once

#include <string>

#include "wearscar/scan/height_map.h"

namespace wearscar::scan {

// Gwyddion Simple Field: "Gwyddion Simple Field 1.0", "Name = value" lines
// (XRes, YRes required; XReal, YReal, XYUnits, ZUnits optional), NUL padding
// to a multiple of 4, then XRes * YRes little-endian float32. NaN = invalid.
HeightMap ReadGsf(const std::string& path);
HeightMap ParseGsf(const std::string& bytes, const std::string& name);

// Writes heights in metres (Gwyddion's convention), temporary name then
// rename.
void WriteGsf(const HeightMap& map, const std::string& path);

// Writes a Keyence VR CSV height export (FORMATS.md): `key,value` header rows
// (Horizontal, Vertical, XY Calibration in um, Unit mm), a `Height` row, then
// one row of heights in mm per scan row; invalid pixels are empty cells.
// ReadScan reads it back to the written precision (0.1 nm).
void WriteKeyenceCsv(const HeightMap& map, const std::string& path);

}  // namespace wearscar::scan
