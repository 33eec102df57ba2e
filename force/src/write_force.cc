#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <random>

#include "wearscar/force/read_force.h"
#include "wearscar/support/atomic_file.h"

namespace wearscar::force {
namespace {

// Streams rows made by `emit(i, buffer)` to a temporary name beside `path`,
// then renames it: a reader never sees a half-written file.
template <typename Header, typename Row, typename Footer>
void WriteRowsAtomically(const ForceRecord& record,
                         const std::string& path,
                         Header&& header,
                         Row&& row,
                         Footer&& footer) {
  support::AtomicFile<ForceError> file(path);
  fmt::memory_buffer buf;
  header(buf);
  for (Eigen::Index i = 0; i < record.size(); ++i) {
    row(i, buf);
    if (buf.size() > (1u << 20)) {
      file.Write(std::string_view(buf.data(), buf.size()));
      buf.clear();
    }
  }
  footer(buf);
  file.Write(std::string_view(buf.data(), buf.size()));
  file.Commit();
}

}  // namespace

void WriteForceCsv(const ForceRecord& record, const std::string& path) {
  WriteRowsAtomically(
      record,
      path,
      [&](fmt::memory_buffer& b) {
        fmt::format_to(std::back_inserter(b),
                       "time_s,x_mm,Q_N,P_N{}\n",
                       record.has_depth() ? ",depth_mm" : "");
      },
      [&](Eigen::Index i, fmt::memory_buffer& b) {
        fmt::format_to(std::back_inserter(b),
                       "{:.6f},{:.6f},{:.5f},{:.5f}",
                       record.time_s[i],
                       record.x_mm[i],
                       record.tangential_n[i],
                       record.normal_n[i]);
        if (record.has_depth())
          fmt::format_to(std::back_inserter(b), ",{:.7f}", record.depth_mm[i]);
        b.push_back('\n');
      },
      [](fmt::memory_buffer&) {});
}

void WriteRtecCsv(const ForceRecord& record,
                  const std::string& path,
                  double step_s) {
  if (!(step_s > 0)) {
    throw ForceError(fmt::format("{}: recipe step must be > 0 s", path));
  }
  const double t0 = record.size() > 0 ? record.time_s[0] : 0.0;
  WriteRowsAtomically(
      record,
      path,
      [&](fmt::memory_buffer& b) {
        fmt::format_to(std::back_inserter(b),
                       "Recipe: reciprocating {},Operator: wearscar,"
                       "Source: {}\n"
                       "RecipeStep,Timestamp,DAQ.Fx (N),DAQ.Fz (N),DAQ.COF (),"
                       "Piezo X (mm),\n",
                       record.metadata.source,
                       record.metadata.layout);
      },
      [&](Eigen::Index i, fmt::memory_buffer& b) {
        const double t = record.time_s[i] - t0;
        const double step = std::floor(t / step_s + 1e-9);
        const double p = record.normal_n[i], q = record.tangential_n[i];
        fmt::format_to(std::back_inserter(b),
                       "{},{:.4f},{:.4f},{:.4f},{:.4f},{:.5f},\n",
                       static_cast<long>(step) + 1,
                       t - step * step_s,
                       q,
                       -p,
                       p != 0 ? q / std::abs(p) : 0.0,
                       record.x_mm[i]);
      },
      [](fmt::memory_buffer& b) {
        fmt::format_to(std::back_inserter(b), "End of data\n");
      });
}

}  // namespace wearscar::force
