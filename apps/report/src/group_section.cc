// The audit report's section on groups and factors: what was compared and
// how, the levels' table, a figure of each level's specimens, mean and
// interval, the differences, the planning line and the specimens left out.

#include "group_section.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "html_page.h"

namespace wearscar::report::internal {
namespace {

std::string Num(double v, const char* format) {
  return std::isfinite(v) ? fmt::format(fmt::runtime(format), v) : "&ndash;";
}

// Each level a row: its specimens' values (grey), its mean (black) and the
// mean's 95% interval (a bar), on one axis of mu.
std::string LevelFigure(const fusion::GroupComparison& c) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& s : c.levels) {
    for (double v : s.values) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    if (std::isfinite(s.low)) lo = std::min(lo, s.low);
    if (std::isfinite(s.high)) hi = std::max(hi, s.high);
  }
  if (!(hi > lo)) return "";
  const double pad = 0.05 * (hi - lo);
  lo -= pad;
  hi += pad;
  const int row = 22, left = 190, width = 420,
            height = row * static_cast<int>(c.levels.size()) + 40;
  auto x = [&](double v) { return left + (v - lo) / (hi - lo) * width; };
  std::string svg = fmt::format(
      "<svg class=\"groups\" role=\"img\" width=\"{}\" height=\"{}\" "
      "viewBox=\"0 0 {} {}\" font-size=\"12\"><title>{}: each level's "
      "specimens (grey), their mean (black) and its 95% interval</title>\n",
      left + width + 20,
      height,
      left + width + 20,
      height,
      c.quantity);
  for (size_t i = 0; i < c.levels.size(); ++i) {
    const auto& s = c.levels[i];
    const int y = 14 + row * static_cast<int>(i);
    svg += fmt::format(
        "<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{}: {} (n = {})</text>\n",
        left - 8,
        y + 4,
        Escape(s.factor),
        Escape(s.level),
        s.n);
    for (double v : s.values)
      svg += fmt::format(
          "<circle cx=\"{:.1f}\" cy=\"{}\" r=\"2.5\" fill=\"#999\"/>", x(v), y);
    if (std::isfinite(s.low))
      svg += fmt::format(
          "<line x1=\"{:.1f}\" x2=\"{:.1f}\" y1=\"{}\" y2=\"{}\" "
          "stroke=\"#000\" stroke-width=\"2\"/>",
          x(s.low),
          x(s.high),
          y,
          y);
    svg += fmt::format(
        "<rect x=\"{:.1f}\" y=\"{}\" width=\"4\" height=\"10\" "
        "fill=\"#000\"/>\n",
        x(s.mean) - 2,
        y - 5);
  }
  const int axis = height - 22;
  svg += fmt::format(
      "<line x1=\"{}\" x2=\"{}\" y1=\"{}\" y2=\"{}\" stroke=\"#444\"/>",
      left,
      left + width,
      axis,
      axis);
  for (int k = 0; k <= 4; ++k) {
    const double v = lo + (hi - lo) * k / 4;
    svg += fmt::format(
        "<text x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">{:.4g}</text>",
        x(v),
        axis + 16,
        v);
  }
  return svg + "</svg>\n";
}

std::string Comparison(const fusion::GroupComparison& c) {
  const bool mu = c.quantity == "mu_to_quote";
  const char* f = mu ? "{:.4f}" : "{:.3g}";
  std::string h = fmt::format(
      "<h3>{}</h3>\n",
      mu ? "mu to quote" : "specific wear rate (mm<sup>3</sup>/(N m))");
  if (!c.abstained.empty()) {
    h += "<p>Not compared: " + Escape(c.abstained) + ".</p>\n";
  } else {
    h += "<p>" + Escape("Differences by " + c.test) + ".</p>\n";
    h += "<table class=\"groups\"><thead><tr><th>factor</th><th>level</th>"
         "<th>specimens</th><th>mean</th><th>spread between specimens "
         "(SD)</th><th>mean's 95% interval</th></tr></thead><tbody>\n";
    for (const auto& s : c.levels) {
      h += fmt::format(
          "<tr><td class=\"text\">{}</td><td class=\"text\">{}</td><td>{}</td>"
          "<td>{}</td><td>{}</td><td>{}&ndash;{}</td></tr>\n",
          Escape(s.factor),
          Escape(s.level),
          s.n,
          Num(s.mean, f),
          Num(s.sd, "{:.2g}"),
          Num(s.low, f),
          Num(s.high, f));
    }
    h += "</tbody></table>\n" + LevelFigure(c);
    h += "<table class=\"groups\"><thead><tr><th>factor</th><th>A</th>"
         "<th>B</th><th>B &minus; A</th><th>95% interval</th><th>p</th>"
         "<th>different (5%)</th></tr></thead><tbody>\n";
    for (const auto& d : c.differences) {
      h += fmt::format(
          "<tr><td class=\"text\">{}</td><td class=\"text\">{}</td><td "
          "class=\"text\">{}</td><td>{}</td><td>{}&ndash;{}</td><td>{}</td>"
          "<td class=\"text\">{}</td></tr>\n",
          Escape(d.factor),
          Escape(d.level_a),
          Escape(d.level_b),
          Num(d.difference, f),
          Num(d.low, f),
          Num(d.high, f),
          Num(d.p, "{:.2g}"),
          d.Different() ? "yes" : "no");
    }
    h += "</tbody></table>\n";
  }
  if (mu && !c.plan.said.empty())
    h += "<p>Planning the next batch: " + Escape(c.plan.said) + ".</p>\n";
  if (!c.left_out.empty()) {
    std::string names;
    for (const auto& n : c.left_out) names += (names.empty() ? "" : "; ") + n;
    h += "<p>Left out: " + Escape(names) + ".</p>\n";
  }
  return h;
}

}  // namespace

std::string GroupSection(const std::vector<fusion::GroupComparison>& groups) {
  if (groups.empty()) return "";
  std::string h =
      "<h2 id=\"groups\">Groups</h2>\n<p>Each specimen is one value (its "
      "cycles are not independent replicates); the spread between "
      "specimens is the error. groups.csv, group_differences.csv and "
      "groups.tex hold these tables.</p>\n";
  for (const auto& c : groups) h += Comparison(c);
  return h;
}

}  // namespace wearscar::report::internal
