// libFuzzer targets for the scan readers, one binary per format chosen by
// WEARSCAR_FUZZ_FORMAT at compile time. Bad input must end in ScanError.
#include <cstddef>
#include <cstdint>
#include <string>

#include "wearscar/scan/gsf.h"
#include "wearscar/scan/read_scan.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace wearscar::scan;
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  ReadScanOptions o;
  // The same limits, scaled down so that a bomb among the seeds costs
  // milliseconds, not the fuzzer's time and memory.
  o.max_member_bytes = 16u << 20;
  o.max_total_bytes = 32u << 20;
  o.free_expansion_bytes = 1u << 20;
  o.ascii_pitch_mm = 0.01;
  try {
    const std::string format = WEARSCAR_FUZZ_FORMAT;
    HeightMap map;
    if (format == "gsf") map = ParseGsf(bytes, "fuzz.gsf");
    if (format == "x3p") map = ParseX3p(bytes, "fuzz.x3p", o);
    if (format == "vk4") map = ParseVk4(bytes, "fuzz.vk4");
    if (format == "vk67") map = ParseVk67(bytes, "fuzz.vk6", o);
    if (format == "zon") map = ParseZon(bytes, "fuzz.zon", o);
    if (format == "zag") {
      ListZagMeasurements(bytes, "fuzz.zag");
      map = ParseZag(bytes, "fuzz.zag", o);
    }
    if (format == "keyence_csv") map = ParseKeyenceCsv(bytes, "fuzz.csv");
    if (format == "ascii") map = ParseAsciiMatrix(bytes, "fuzz.txt", o);
    CheckPixels(&map, o);  // what ReadScan applies to every map
  } catch (const ScanError&) {
  }
  return 0;
}
