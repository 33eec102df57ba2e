// loop_viewer.json: what the report's loop viewer draws, from the
// analysis's result (formatting only).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>

#include "tables.h"
#include "wearscar/fusion/friction_map.h"

namespace wearscar::fusion::internal {
namespace {

// At most this many cycles are embedded (every n-th beyond it), so that a
// report of long tests stays a page a browser opens.
constexpr int kMostCycles = 1000;

// Values as integers times `scale`, "null" where not finite (fmt's integer
// formatter: a few hundred thousand values a full-size test).
template <typename Get>
void AppendScaled(std::string* out, size_t count, double scale, Get get) {
  *out += '[';
  for (size_t i = 0; i < count; ++i) {
    if (i > 0) *out += ',';
    const double v = get(i);
    if (std::isfinite(v)) {
      const fmt::format_int digits(std::lround(v / scale));
      out->append(digits.data(), digits.size());
    } else {
      *out += "null";
    }
  }
  *out += ']';
}

// A round scale giving about 3000 steps to the largest magnitude.
double ScaleFor(double largest) {
  if (!(largest > 0)) return 1;
  const double raw = largest / 3000;
  return std::pow(10.0, std::floor(std::log10(raw)));
}

// The friction map's rows of the cycles shown (raw and corrected), after
// their bins' x and their scale.
void AppendMapRows(const FrictionMap& m,
                   const std::vector<int>& shown,
                   std::string* out) {
  double mu_max = 0;
  for (double v : m.mu_raw)
    if (std::isfinite(v)) mu_max = std::max(mu_max, std::abs(v));
  for (double v : m.mu_corrected)
    if (std::isfinite(v)) mu_max = std::max(mu_max, std::abs(v));
  const double mu_scale = ScaleFor(mu_max);
  const size_t map_bins = m.x_mm.size();
  auto it = std::back_inserter(*out);
  *out += ",\n\"map_x_mm\":[";
  for (size_t b = 0; b < map_bins; ++b)
    fmt::format_to(it, "{}{:.4f}", b ? "," : "", m.x_mm[b]);
  fmt::format_to(it, "],\n\"mu_scale\":{:g},\n\"mu_raw\":", mu_scale);
  const size_t map_cells = shown.size() * 2 * map_bins;
  auto map_value = [&](const std::vector<double>& v, size_t i) {
    const size_t b = i % map_bins;
    const int d = static_cast<int>(i / map_bins % 2);
    return v[m.Index(shown[i / map_bins / 2], d, b)];
  };
  AppendScaled(out, map_cells, mu_scale, [&](size_t i) {
    return map_value(m.mu_raw, i);
  });
  *out += ",\n\"mu_corrected\":";
  AppendScaled(out, map_cells, mu_scale, [&](size_t i) {
    return map_value(m.mu_corrected, i);
  });
}

}  // namespace

std::string LoopViewerJson(const TestResult& r) {
  const FrictionMap& m = r.units.Get<FrictionMap>();
  const size_t bins = m.loop_x_mm.size();
  const int n = m.cycles;
  const std::vector<MuFit>& force_fits = r.ForceFits().cycles;
  const bool from_p = !force_fits.empty();
  const std::vector<MuFit>& fits =
      from_p ? force_fits : (r.scan ? r.ScanSlopeFits().cycles : force_fits);
  const int stride = std::max(1, (n + kMostCycles - 1) / kMostCycles);
  std::vector<int> shown;
  for (int c = 0; c < n; c += stride) shown.push_back(c);
  if (n > 0 && shown.back() != n - 1) shown.push_back(n - 1);
  auto mu_of = [&](int c) {
    return c < static_cast<int>(fits.size()) && fits[c].converged
               ? fits[c].mu_hat
               : NAN;
  };
  double q_max = 0;
  for (float q : m.loop_q_n)
    if (std::isfinite(q)) q_max = std::max(q_max, std::abs(double(q)));
  const double q_scale = ScaleFor(q_max);
  const size_t cells = shown.size() * 2 * bins;
  std::string out;
  // Room for every value at once (at most about 6 characters each, the
  // loops' two arrays and the map's two; untouched room costs nothing),
  // rather than the text copied as it grows.
  out.reserve(8 * (2 * cells + 4 * shown.size() * m.x_mm.size()) + 65536);
  auto it = std::back_inserter(out);
  fmt::format_to(
      it,
      "{{\"about\":\"each cycle's gross-slip loop: Q averaged in {} bins "
      "along the stroke per direction, the wear-scar model's Q there, P (k + "
      "s mu) / (1 - s mu k) with the bin's P and k and the cycle's "
      "mu-hat ({}), and the friction map's row of the cycle (raw s Q/P and "
      "corrected for k); values are integers times their scale, cycle-major, "
      "forward then reverse\",\n\"mu_hat_from\":\"{}\",\n\"cycles\":[",
      bins,
      from_p ? r.profile.SlopeName() : "k from the scan",
      from_p ? r.profile.SlopeName() : "k from the scan");
  for (size_t i = 0; i < shown.size(); ++i)
    fmt::format_to(it, "{}{}", i ? "," : "", shown[i] + 1);
  fmt::format_to(it, "],\n\"of_cycles\":{},\n\"x_mm\":[", n);
  for (size_t b = 0; b < bins; ++b)
    fmt::format_to(it, "{}{:.4f}", b ? "," : "", m.loop_x_mm[b]);
  out += "],\n\"mu_hat\":";
  AppendScaled(
      &out, shown.size(), 1e-7, [&](size_t i) { return mu_of(shown[i]); });
  fmt::format_to(
      it, ",\n\"mu_hat_scale\":1e-7,\n\"q_scale_n\":{:g},\n", q_scale);
  auto cell = [&](size_t i, size_t* b, int* d) {
    *b = i % bins;
    *d = static_cast<int>(i / bins % 2);
    return shown[i / bins / 2];
  };
  out += "\"q\":";
  AppendScaled(&out, cells, q_scale, [&](size_t i) {
    size_t b;
    int d;
    const int c = cell(i, &b, &d);
    return double(m.loop_q_n[m.LoopIndex(c, d, b)]);
  });
  out += ",\n\"q_model\":";
  AppendScaled(&out, cells, q_scale, [&](size_t i) {
    size_t b;
    int d;
    const int c = cell(i, &b, &d);
    return m.LoopModelQ(c, d, b, mu_of(c));
  });
  AppendMapRows(m, shown, &out);
  out += "}\n";
  return out;
}

}  // namespace wearscar::fusion::internal
