// libFuzzer target: the delimited force reader (every layout of the
// registry goes through the same detection and parsing). Bad input must end
// in ForceError, never a crash, a hang or a sanitizer report.
// WEARSCAR_FUZZ_SEEDS=DIR writes each layout's example into DIR (the
// registry's seeds, for scripts/fuzz) and exits.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "wearscar/force/cycles.h"
#include "wearscar/force/layouts.h"
#include "wearscar/force/read_force.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("WEARSCAR_FUZZ_SEEDS")) {
    for (const auto& l : wearscar::force::ForceLayouts()) {
      std::ofstream(std::string(dir) + "/layout-" + l.name + ".txt",
                    std::ios::binary)
          << l.example;
    }
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  for (bool lenient : {false, true}) {
    wearscar::force::ReadForceOptions o;
    o.lenient = lenient;
    o.sampling_rate_hz = 100;
    try {
      const auto r = wearscar::force::ReadForceText(text, "fuzz.csv", o);
      wearscar::force::CycleSet c =
          wearscar::force::SegmentCycles(r.x_mm, {}, "fuzz.csv");
      wearscar::force::FindGrossSlip(r, &c);
    } catch (const wearscar::force::ForceError&) {
    }
  }
  return 0;
}
