#include "report.h"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <iterator>

namespace wearscar::app {
namespace {

std::string Escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string Number(const nlohmann::json& j, const char* fmt_spec = "{:.4f}") {
  if (!j.is_number()) return "";
  const double v = j.get<double>();
  return std::isfinite(v) ? fmt::format(fmt::runtime(fmt_spec), v) : "";
}

std::string Image(const std::string& path, const std::string& title) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in), {}};
  return fmt::format(
      "<figure><img alt=\"{0}\" "
      "src=\"data:image/png;base64,{1}\"><figcaption>{0}</figcaption>"
      "</figure>\n",
      Escape(title),
      Base64(bytes));
}

}  // namespace

std::string Base64(const std::string& bytes) {
  static const char* kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < bytes.size()) {
    unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size())
      v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

namespace {

// The page's head, style and the summary table's header.
std::string ReportHead(const std::string& title,
                       const std::vector<ReportSection>& sections) {
  int flagged = 0, failed = 0;
  for (const auto& s : sections) {
    flagged += s.flagged;
    failed += s.failed;
  }
  return fmt::format(R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{0}</title>
<style>
body {{ font-family: 'DejaVu Sans', Arial, sans-serif; margin: 2em; color: #222; }}
table {{ border-collapse: collapse; font-size: 0.9em; }}
th, td {{ border: 1px solid #bbb; padding: 0.3em 0.6em; text-align: right; }}
th {{ background: #eee; }} td.name, td.text {{ text-align: left; }}
tr.flagged td {{ background: #ffe3b3; }} tr.failed td {{ background: #ffc4c4; }}
figure {{ display: inline-block; margin: 0.5em; }} img {{ max-width: 720px; border: 1px solid #ddd; }}
figcaption {{ font-size: 0.85em; color: #555; }}
</style></head><body>
<h1>{0}</h1>
<p>{1} specimens: {2} not explained by wear-scar interaction, {3} failed to analyse.
mu-hat: the wear-scar coefficient of friction (Eq. 6) with the slope of the sliding path from the
normal force (k = dP/dx / S) and, with a scan, from the worn track's centreline.</p>
<table id="summary"><thead><tr><th>specimen</th><th>species</th><th>plane</th><th>direction</th>
<th>mu-hat (k from P)</th><th>sd</th><th>mu-hat (k from scan)</th><th>mu mean</th><th>mu energy</th>
<th>J</th><th>J noise floor</th><th>J excess</th><th>J (k from scan)</th><th>r profiles</th><th>amplitude ratio</th><th>verdict</th></tr></thead><tbody>
)",
                     Escape(title),
                     sections.size(),
                     flagged,
                     failed);
}

// One specimen's row of the summary table.
std::string SummaryRow(const ReportSection& s) {
  std::string h;
  const auto& r = s.row;
  auto get =
      [&](const char* a, const char* b = nullptr, const char* c = nullptr) {
        const nlohmann::json* j = &r;
        for (const char* k : {a, b, c}) {
          if (k == nullptr) break;
          if (!j->contains(k)) return nlohmann::json();
          j = &(*j)[k];
        }
        return *j;
      };
  const std::string cls = s.failed ? "failed" : s.flagged ? "flagged" : "ok";
  std::string verdict = s.failed ? "error: " + get("error").get<std::string>()
                        : get("verdict", "summary").is_string()
                            ? get("verdict", "summary").get<std::string>()
                            : "";
  h += fmt::format(
      "<tr class=\"{}\"><td class=\"name\"><a href=\"#{}\">{}</a></td><td "
      "class=\"text\">{}</td>"
      "<td class=\"text\">{}</td><td "
      "class=\"text\">{}</td><td>{}</td><td>{}</td><td>{}</td>"
      "<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
      "<td>{}</td><td>{}</td><td class=\"text\">{}</td></tr>\n",
      cls,
      Escape(s.name),
      Escape(s.name),
      Escape(get("species").is_string() ? get("species").get<std::string>()
                                        : ""),
      Escape(get("plane").is_string() ? get("plane").get<std::string>() : ""),
      Escape(get("direction").is_string() ? get("direction").get<std::string>()
                                          : ""),
      Number(get("comparison", "mu_hat_force", "mean")),
      Number(get("comparison", "mu_hat_force", "sd")),
      Number(get("comparison", "mu_hat_scan", "mean")),
      Number(get("comparison", "mu_mean", "mean")),
      Number(get("comparison", "mu_energy", "mean")),
      Number(get("comparison", "J_force", "mean"), "{:.3f}"),
      Number(get("comparison", "J_force_split", "noise_floor"), "{:.3f}"),
      Number(get("comparison", "J_force_split", "excess"), "{:.3f}"),
      Number(get("comparison", "J_scan", "mean"), "{:.3f}"),
      Number(get("comparison", "profile_correlation"), "{:.3f}"),
      Number(get("comparison", "amplitude_ratio"), "{:.2f}"),
      Escape(verdict));
  return h;
}

// One specimen's section: verdict, slope estimate, warnings, figures.
std::string SpecimenSection(const ReportSection& s) {
  std::string h;
  h += fmt::format("<h2 id=\"{0}\">{0}</h2>\n", Escape(s.name));
  if (s.failed) {
    h += "<p class=\"error\">" + Escape(s.row.value("error", std::string())) +
         "</p>\n";
    return h;
  }
  h +=
      "<p>" + Escape(s.row["verdict"]["summary"].get<std::string>()) + "</p>\n";
  if (s.row.contains("slope_estimate") && s.row["slope_estimate"].is_string())
    h += "<p class=\"note\">" +
         Escape(s.row["slope_estimate"].get<std::string>()) + "</p>\n";
  if (s.row.contains("warnings") && s.row["warnings"].is_array() &&
      !s.row["warnings"].empty()) {
    h += "<ul class=\"warnings\">\n";
    for (const auto& w : s.row["warnings"]) {
      if (w.is_string())
        h += "<li>warning: " + Escape(w.get<std::string>()) + "</li>\n";
    }
    h += "</ul>\n";
  }
  if (!s.figures.message.empty())
    h += "<p>" + Escape(s.figures.message) + "</p>\n";
  for (size_t i = 0; i < s.figures.png.size(); ++i) {
    h += Image(s.figures.png[i], s.figures.titles[i]);
  }
  return h;
}

}  // namespace

std::string RenderReport(const std::string& title,
                         const std::vector<ReportSection>& sections,
                         const FigureSet& batch) {
  std::string h = ReportHead(title, sections);
  for (const auto& s : sections) h += SummaryRow(s);
  h += "</tbody></table>\n";
  if (!batch.png.empty() || !batch.message.empty()) {
    h += "<h2>All specimens</h2>\n";
    if (!batch.message.empty()) h += "<p>" + Escape(batch.message) + "</p>\n";
    for (size_t i = 0; i < batch.png.size(); ++i)
      h += Image(batch.png[i], batch.titles[i]);
  }
  for (const auto& s : sections) h += SpecimenSection(s);
  // Marks the page once every image has decoded (read by the browser test
  // and handy for anyone scripting the report).
  h += R"(<script>
window.addEventListener('load', function () {
  var imgs = document.images, ok = 0;
  for (var i = 0; i < imgs.length; ++i) if (imgs[i].complete && imgs[i].naturalWidth > 0) ++ok;
  document.body.setAttribute('data-images-rendered', ok + '/' + imgs.length);
  document.body.setAttribute('data-table-rows', document.querySelectorAll('#summary tbody tr').length);
});
</script>
</body></html>
)";
  return h;
}

}  // namespace wearscar::app
