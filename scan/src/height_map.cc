#include "wearscar/scan/height_map.h"

#include <cmath>
#include <limits>

namespace wearscar::scan {

void HeightMap::Resize(Eigen::Index rows, Eigen::Index cols) {
  height_mm.resize(rows, cols);
  valid.resize(rows, cols);
}

void SyncValidity(HeightMap* map) {
  map->valid.resize(map->height_mm.rows(), map->height_mm.cols());
  float* h = map->height_mm.data();
  std::uint8_t* v = map->valid.data();
  const Eigen::Index n = map->height_mm.size();
  for (Eigen::Index i = 0; i < n; ++i) {
    v[i] = std::isfinite(h[i]) ? 1 : 0;
    if (!v[i]) h[i] = std::numeric_limits<float>::quiet_NaN();
  }
}

}  // namespace wearscar::scan
