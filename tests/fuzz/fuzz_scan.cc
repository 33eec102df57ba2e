// libFuzzer target for the scan readers: one binary, the format chosen at
// run time from the registry by WEARSCAR_FUZZ_FORMAT (its name: zon, plu,
// ...). WEARSCAR_FUZZ_FORMATS=1 lists the formats, one line each with
// their extensions, for scripts/fuzz. Bad input must end in ScanError.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "wearscar/scan/formats.h"
#include "wearscar/scan/read_scan.h"

namespace {
const wearscar::scan::ScanFormat* format = nullptr;
}

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  using wearscar::scan::ScanFormats;
  if (std::getenv("WEARSCAR_FUZZ_FORMATS") != nullptr) {
    for (const auto& f : ScanFormats()) {
      std::printf("%s", f.name.c_str());
      for (const auto& e : f.extensions) std::printf(" %s", e.c_str());
      std::printf("\n");
    }
    std::exit(0);
  }
  const char* name = std::getenv("WEARSCAR_FUZZ_FORMAT");
  format = name ? wearscar::scan::FindScanFormat(name) : nullptr;
  if (format == nullptr) {
    std::fprintf(stderr,
                 "WEARSCAR_FUZZ_FORMAT must name a scan format "
                 "(WEARSCAR_FUZZ_FORMATS=1 lists them)\n");
    std::exit(2);
  }
  return 0;
}

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
    const std::string name = "fuzz" + format->extensions.front();
    if (format->name == "zag") ListZagMeasurements(bytes, name);
    HeightMap map = format->parse(bytes, name, o);
    CheckPixels(&map, o);  // what ReadScan applies to every map
    DetectScanFormat(bytes, name);
  } catch (const ScanError&) {
  }
  return 0;
}
