#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace wearscar::scan {

// Raised for bad scan files and bad user input. The message names the file,
// the byte offset or archive member, what was found and what was expected.
class ScanError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct HeightMapMetadata {
  std::string source;      // file path, or "simulator"
  std::string format;      // "gsf", "x3p", "vk4", "zon", ...
  std::string instrument;  // device model when the file says
  std::string date;        // acquisition date when the file says
  std::string channel = "height";
  std::vector<std::string> warnings;
};

// A profilometer height map in mm. Row r is y = r * dy_mm, column c is
// x = c * dx_mm. Invalid pixels are NaN in height_mm and 0 in valid; the two
// always agree. Row-major so that OpenCV can view the memory without a copy.
struct HeightMap {
  using Heights =
      Eigen::Array<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  using Mask = Eigen::
      Array<std::uint8_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

  Heights height_mm;
  Mask valid;
  double dx_mm = 0.0;
  double dy_mm = 0.0;
  HeightMapMetadata metadata;

  // Sizes both arrays (their contents undefined until written).
  void Resize(Eigen::Index rows, Eigen::Index cols);

  Eigen::Index rows() const { return height_mm.rows(); }
  Eigen::Index cols() const { return height_mm.cols(); }
  Eigen::Index ValidCount() const { return valid.cast<Eigen::Index>().sum(); }
  // valid and height_mm of one size, positive pitches (what every analysis
  // of a map requires; the readers return only such maps).
  bool IsConsistent() const {
    return valid.rows() == height_mm.rows() &&
           valid.cols() == height_mm.cols() && dx_mm > 0 && dy_mm > 0;
  }
};

// Largest pixel count a reader accepts before allocating (2^28).
inline constexpr std::int64_t kMaxPixels = std::int64_t{1} << 28;

// Sets valid from height_mm (finite = valid) and NaN where invalid.
void SyncValidity(HeightMap* map);

}  // namespace wearscar::scan
