// libFuzzer target: the delimited force reader (every vendor layout goes
// through the same detection and parsing). Bad input must end in ForceError,
// never a crash, a hang or a sanitizer report.
#include <cstddef>
#include <cstdint>
#include <string>

#include "wearscar/force/cycles.h"
#include "wearscar/force/read_force.h"

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
