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
  o.max_member_bytes = 64u << 20;  // keep the fuzzer's memory bounded
  o.ascii_pitch_mm = 0.01;
  try {
    const std::string format = WEARSCAR_FUZZ_FORMAT;
    if (format == "gsf") ParseGsf(bytes, "fuzz.gsf");
    if (format == "x3p") ParseX3p(bytes, "fuzz.x3p", o);
    if (format == "vk4") ParseVk4(bytes, "fuzz.vk4");
    if (format == "vk67") ParseVk67(bytes, "fuzz.vk6", o);
    if (format == "zon") ParseZon(bytes, "fuzz.zon", o);
    if (format == "zag") {
      ListZagMeasurements(bytes, "fuzz.zag");
      ParseZag(bytes, "fuzz.zag", o);
    }
    if (format == "keyence_csv") ParseKeyenceCsv(bytes, "fuzz.csv");
    if (format == "ascii") ParseAsciiMatrix(bytes, "fuzz.txt", o);
  } catch (const ScanError&) {
  }
  return 0;
}
