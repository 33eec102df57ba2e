#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <random>

#include "wearscar/force/read_force.h"

namespace wearscar::force {

void WriteForceCsv(const ForceRecord& record, const std::string& path) {
  // Write to a temporary name beside the target, then rename: a reader never
  // sees a half-written file.
  const std::string tmp =
      fmt::format("{}.tmp-{:08x}", path, std::random_device{}());
  {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(
        std::fopen(tmp.c_str(), "wb"), &std::fclose);
    if (!f) {
      throw ForceError(
          fmt::format("{}: cannot write: {}", path, std::strerror(errno)));
    }
    fmt::memory_buffer buf;
    fmt::format_to(std::back_inserter(buf), "time_s,x_mm,Q_N,P_N\n");
    bool ok = true;
    for (Eigen::Index i = 0; i < record.size() && ok; ++i) {
      fmt::format_to(std::back_inserter(buf),
                     "{:.6f},{:.6f},{:.5f},{:.5f}\n",
                     record.time_s[i],
                     record.x_mm[i],
                     record.tangential_n[i],
                     record.normal_n[i]);
      if (buf.size() > (1u << 20)) {
        ok = std::fwrite(buf.data(), 1, buf.size(), f.get()) == buf.size();
        buf.clear();
      }
    }
    ok = ok && std::fwrite(buf.data(), 1, buf.size(), f.get()) == buf.size();
    ok = (std::fflush(f.get()) == 0) && ok;
    if (!ok) {
      std::remove(tmp.c_str());
      throw ForceError(
          fmt::format("{}: write failed: {}", path, std::strerror(errno)));
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw ForceError(
        fmt::format("{}: cannot rename from {}: {}", path, tmp, ec.message()));
  }
}

}  // namespace wearscar::force
