#include "wearscar/report/html_report.h"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "wearscar/fusion/provenance.h"
#include "wearscar/report/output_folder.h"
#include "wearscar/support/atomic_file.h"

namespace wearscar::report {
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

// SVG text as a data URI's payload, appended to `out`: the characters a
// URL or a quoted attribute cannot hold as they are percent-encoded, the
// rest kept (a tenth larger than the SVG, where base64 is a third). Runs
// of plain characters are copied at once: a report embeds every figure.
void AppendSvgUriText(const std::string& svg, std::string* out) {
  static const char* kHex = "0123456789ABCDEF";
  static const std::array<bool, 256> kPlain = [] {
    std::array<bool, 256> plain{};
    for (int u = 0x20; u < 0x7f; ++u) plain[u] = true;
    for (unsigned char c : {'%', '#', '"', '&', '<', '>'}) plain[c] = false;
    return plain;
  }();
  const char* p = svg.data();
  const char* const end = p + svg.size();
  while (p < end) {
    const char* run = p;
    while (p < end && kPlain[static_cast<unsigned char>(*p)]) ++p;
    out->append(run, static_cast<size_t>(p - run));
    if (p == end) break;
    const auto u = static_cast<unsigned char>(*p++);
    const char escaped[3] = {'%', kHex[u >> 4], kHex[u & 15]};
    out->append(escaped, 3);
  }
}

// The whole file, or what could be read of it (empty when it cannot be
// opened: the report then shows an empty image, as it always did).
std::string ReadWhole(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return {};
  const std::streamoff size = in.tellg();
  if (size <= 0) return {};
  std::string bytes(static_cast<size_t>(size), '\0');
  in.seekg(0);
  in.read(bytes.data(), size);
  bytes.resize(static_cast<size_t>(in.gcount()));
  return bytes;
}

// A figure embedded as a data URI (PNG or SVG, by its extension), appended
// to `h`.
void AppendImage(const std::string& path,
                 const std::string& title,
                 std::string* h) {
  const std::string bytes = ReadWhole(path);
  const bool svg = path.size() > 4 && path.substr(path.size() - 4) == ".svg";
  const std::string alt = Escape(title);
  *h += "<figure><img alt=\"" + alt + "\" src=\"";
  if (svg) {
    *h += "data:image/svg+xml,";
    AppendSvgUriText(bytes, h);
  } else {
    *h += "data:image/png;base64,";
    *h += Base64(bytes);
  }
  *h += "\"><figcaption>" + alt + "</figcaption></figure>\n";
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
th, td {{ border: 1px solid #bbb; padding: 0.3em 0.5em; text-align: right; }}
th {{ background: #eee; }} td.name, td.text {{ text-align: left; }}
tr.flagged td {{ background: #ffe3b3; }} tr.failed td {{ background: #ffc4c4; }}
div.wide {{ overflow-x: auto; max-width: 100%; }}
#summary thead th {{ position: sticky; top: 0; z-index: 1; }}
#summary td.name {{ position: sticky; left: 0; background: #fff; }}
tr.reason td {{ text-align: left; border-top: none; }}
a.back {{ font-size: 0.6em; font-weight: normal; margin-left: 1em; }}
tr.reason div {{ position: sticky; left: 0.5em; max-width: calc(100vw - 6em); white-space: normal; }}
figure {{ display: block; margin: 1em 0; }}
img {{ width: 1200px; max-width: 100%; height: auto; border: 1px solid #ddd; }}
figcaption {{ font-size: 0.9em; color: #555; }}
table.numbers {{ margin: 0.5em 1em 0.5em 0; display: inline-table; vertical-align: top; }}
details {{ margin: 1em 0; font-size: 0.9em; }} pre {{ white-space: pre-wrap; }}
div.viewer {{ margin: 1em 0; }} div.viewer canvas {{ width: 1200px; max-width: 100%; border: 1px solid #ddd; display: block; margin: 0.5em 0; }}
div.viewer input {{ width: 40em; max-width: 70vw; vertical-align: middle; }} p.headline {{ font-size: 1.15em; font-weight: bold; }}
</style></head><body>
<h1>{0}</h1>
<p class="made">made by wearscar {4} (commit {5}) on {6}</p>
<p>{1} specimens: {2} not explained by wear-scar interaction, {3} failed to analyse.
mu-hat: the wear-scar coefficient of friction (Eq. 6) with the slope of the sliding path from the
normal force (k = dP/dx / S) and, with a scan, from the worn track's centreline.</p>
<div class="wide"><table id="summary"><thead><tr><th>specimen</th><th>species</th><th>plane</th><th>direction</th>
<th>mu-hat (k from P or depth)</th><th>its 95% interval</th><th>mu-hat (k from scan)</th><th>mu mean</th><th>mu energy</th>
<th>J</th><th>J noise floor</th><th>J excess</th><th>J (k from scan)</th><th>its floor</th><th>r profiles</th><th>amplitude ratio</th><th>wear rate (mm<sup>3</sup>/(N m))</th><th>warnings</th><th>verdict</th></tr></thead><tbody>
)",
                     Escape(title),
                     sections.size(),
                     flagged,
                     failed,
                     fusion::Version(),
                     fusion::GitCommit(),
                     fusion::CurrentProvenance().date_utc);
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
  // The verdict in a word; the whole sentence on hover and in the
  // specimen's section.
  const std::string full = s.failed
                               ? "error: " + get("error").get<std::string>()
                           : get("verdict", "summary").is_string()
                               ? get("verdict", "summary").get<std::string>()
                               : "";
  const std::string verdict =
      fmt::format("<span title=\"{}\">{}</span>",
                  Escape(full),
                  s.failed                           ? "failed"
                  : full.rfind("not judged", 0) == 0 ? "not judged"
                  : s.flagged                        ? "not explained"
                                                     : "explained");
  h += fmt::format(
      "<tr class=\"{}\"><td class=\"name\"><a href=\"#{}\">{}</a></td><td "
      "class=\"text\">{}</td>"
      "<td class=\"text\">{}</td><td "
      "class=\"text\">{}</td><td>{}</td><td>{}</td><td>{}</td>"
      "<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
      "<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td "
      "class=\"text\">{}</td></tr>\n",
      cls,
      Escape(s.name),
      Escape(s.name),
      Escape(get("species").is_string() ? get("species").get<std::string>()
                                        : ""),
      Escape(get("plane").is_string() ? get("plane").get<std::string>() : ""),
      Escape(get("direction").is_string() ? get("direction").get<std::string>()
                                          : ""),
      Number(get("comparison", "mu_hat_force", "mean")),
      get("comparison", "mu_hat_force", "interval95").is_array()
          ? Number(get("comparison", "mu_hat_force", "interval95")[0]) +
                "&ndash;" +
                Number(get("comparison", "mu_hat_force", "interval95")[1])
          : std::string(),
      Number(get("comparison", "mu_hat_scan", "mean")),
      Number(get("comparison", "mu_mean", "mean")),
      Number(get("comparison", "mu_energy", "mean")),
      Number(get("comparison", "J_force", "mean"), "{:.3f}"),
      Number(get("comparison", "J_force_split", "noise_floor"), "{:.3f}"),
      Number(get("comparison", "J_force_split", "excess"), "{:.3f}"),
      Number(get("comparison", "J_scan", "mean"), "{:.3f}"),
      Number(get("comparison", "J_scan_split", "noise_floor"), "{:.3f}"),
      Number(get("comparison", "profile_correlation"), "{:.3f}"),
      Number(get("comparison", "amplitude_ratio"), "{:.2f}"),
      Number(get("wear", "specific_wear_rate_mm3_per_n_m"), "{:.3g}"),
      get("warnings").is_array() ? std::to_string(get("warnings").size())
                                 : std::string(),
      verdict);
  // A flagged or failed row's reason under it, in view whatever the
  // table's scroll.
  if (s.failed || s.flagged) {
    h += fmt::format(
        "<tr class=\"reason {}\"><td colspan=\"19\"><div>{}</div></td></tr>\n",
        cls,
        Escape(full));
  }
  return h;
}

// A number of the row at a path, or "" where there is none.
std::string At(const nlohmann::json& row,
               std::initializer_list<const char*> path,
               const char* spec = "{:.4f}") {
  const nlohmann::json* j = &row;
  for (const char* k : path) {
    if (!j->is_object() || !j->contains(k)) return "";
    j = &(*j)[k];
  }
  return Number(*j, spec);
}

// The specimen's numbers: mu-hat and J with k from P beside k from the
// scan, the other coefficients, wear, LuGre.
std::string NumbersTable(const nlohmann::json& r) {
  // mean (95% interval), sd
  auto pm = [&](const char* stat) {
    const std::string m = At(r, {"comparison", stat, "mean"}),
                      sd = At(r, {"comparison", stat, "sd"});
    const nlohmann::json* iv = &r;
    for (const char* k : {"comparison", stat, "interval95"}) {
      iv = iv->is_object() && iv->contains(k) ? &(*iv)[k] : nullptr;
      if (iv == nullptr) break;
    }
    const std::string range =
        iv && iv->is_array() && iv->size() == 2
            ? " (" + Number((*iv)[0]) + "&ndash;" + Number((*iv)[1]) + ")"
            : "";
    return m.empty() ? m : m + range + ", sd " + sd;
  };
  std::string h =
      "<table class=\"numbers\"><thead><tr><th></th><th>k from " +
      std::string(r.contains("profile") && r["profile"].is_object() &&
                          r["profile"].value("source", "") == "depth"
                      ? "the depth channel"
                      : "P (spring)") +
      "</th><th>k from the scan</th></tr></thead><tbody>\n";
  h += fmt::format(
      "<tr><td class=\"text\">mu-hat (mean over the compared cycles, its "
      "95% interval, the sd of the cycles)</td><td>{}</td><td>{}</td></tr>\n",
      pm("mu_hat_force"),
      pm("mu_hat_scan"));
  h += fmt::format(
      "<tr><td class=\"text\">J (Eq. 6)</td><td>{}</td><td>{}</td></tr>\n",
      At(r, {"comparison", "J_force", "mean"}, "{:.3f}"),
      At(r, {"comparison", "J_scan", "mean"}, "{:.3f}"));
  h += fmt::format(
      "<tr><td class=\"text\">J's noise floor (what the noise "
      "explains)</td><td>{}</td><td>{}</td></tr>\n",
      At(r, {"comparison", "J_force_split", "noise_floor"}, "{:.3f}"),
      At(r, {"comparison", "J_scan_split", "noise_floor"}, "{:.3f}"));
  h += fmt::format(
      "<tr><td class=\"text\">J excess</td><td>{}</td><td>{}</td></tr>\n",
      At(r, {"comparison", "J_force_split", "excess"}, "{:.3f}"),
      At(r, {"comparison", "J_scan_split", "excess"}, "{:.3f}"));
  h += "</tbody></table>\n<table class=\"numbers\"><tbody>\n";
  const std::pair<const char*, std::string> rows[] = {
      {"mu mean (Q/P over gross slip)", pm("mu_mean")},
      {"mu energy", pm("mu_energy")},
      {"wear volume (mm<sup>3</sup>)", At(r, {"wear", "volume_mm3"}, "{:.4g}")},
      {"track mean / max depth (mm)",
       At(r, {"wear", "mean_depth_mm"}) + " / " +
           At(r, {"wear", "max_depth_mm"})},
      {"track width (mm)", At(r, {"wear", "width_mm"}, "{:.3f}")},
      {"normal load (N)", At(r, {"wear", "normal_load_n"}, "{:.2f}")},
      {"sliding distance (m)", At(r, {"wear", "sliding_distance_m"}, "{:.4g}")},
      {"specific wear rate (mm<sup>3</sup>/(N m))",
       At(r, {"wear", "specific_wear_rate_mm3_per_n_m"}, "{:.4g}")},
      {"spatial variation of mu, corrected (its noise floor); raw",
       At(r, {"friction_map", "spatial_sd_corrected"}) + " (" +
           At(r, {"friction_map", "spatial_sd_noise_floor"}) + "); " +
           At(r, {"friction_map", "spatial_sd_raw"})},
  };
  for (const auto& [label, value] : rows) {
    h += fmt::format(
        "<tr><td class=\"text\">{}</td><td>{}</td></tr>\n", label, value);
  }
  if (r.contains("lugre") && r["lugre"].is_object()) {
    h += fmt::format(
        "<tr><td class=\"text\">LuGre (cycle {})</td><td "
        "class=\"text\">J {} &mdash; {}</td></tr>\n",
        r["lugre"].value("cycle", 0),
        At(r, {"lugre", "J"}, "{:.4f}"),
        Escape(r["lugre"].value("message", std::string())));
  }
  return h + "</tbody></table>\n";
}

// Where the numbers came from: the build, the date, the inputs and the
// options (folded).
std::string ProvenanceBlock(const nlohmann::json& r) {
  if (!r.contains("provenance")) return "";
  const nlohmann::json& p = r["provenance"];
  std::string h = fmt::format(
      "<details><summary>provenance: wearscar {} (commit {}), {}</summary>\n"
      "<ul>\n",
      Escape(p.value("wearscar_version", std::string())),
      Escape(p.value("git_commit", std::string())),
      Escape(p.value("date_utc", std::string())));
  for (const auto& in : p.value("inputs", nlohmann::json::array())) {
    h += fmt::format("<li>{}: {} ({} bytes, SHA-256 {})</li>\n",
                     Escape(in.value("role", std::string())),
                     Escape(in.value("path", std::string())),
                     in.value("bytes", 0),
                     Escape(in.value("sha256", std::string())));
  }
  h += "</ul>\n<pre>options: " +
       Escape(r.value("options", nlohmann::json::object()).dump(2)) +
       "</pre></details>\n";
  return h;
}

// The loop viewer: a cycle slider over the specimen's loop_viewer.json,
// drawn by the page's script (kPageEnd) into two canvases: the cycle's Q-x
// loop with the wear-scar model's Q, and its friction map row. Nothing when
// the file is not there (an audit of an older wearscar).
void AppendViewer(const ReportSection& s, std::string* h) {
  if (s.viewer.empty()) return;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(s.viewer, ec)) return;
  std::string data = ReadWhole(s.viewer);
  // Inside <script> no "</" may appear; JSON allows "<" as \u003c.
  std::string safe;
  safe.reserve(data.size());
  for (char c : data) {
    if (c == '<') {
      safe += "\\u003c";
    } else {
      safe += c;
    }
  }
  *h += fmt::format(
      "<div class=\"viewer\" id=\"viewer-{0}\"><h3>Cycle by cycle</h3>\n"
      "<p><label>cycle <input type=\"range\" min=\"0\" value=\"0\" "
      "aria-label=\"cycle of {0}\"></label> <span class=\"viewer-label\">"
      "</span></p>\n<canvas class=\"loop\" width=\"1200\" height=\"600\">"
      "</canvas>\n<canvas class=\"map\" width=\"1200\" height=\"420\">"
      "</canvas>\n<p class=\"note\">Black: Q measured while sliding, averaged "
      "in bins along the stroke; blue: the wear-scar model P (k + s mu) / (1 - "
      "s mu k) with that cycle's mu-hat and k from P. Below: the cycle's row "
      "of the friction map, s Q/P (grey) and corrected for k (blue); forward "
      "solid, reverse dashed. Open the page with ?cycle=N to start at cycle N."
      "</p>\n<script type=\"application/json\" class=\"viewer-data\">",
      Escape(s.name));
  *h += safe;
  *h += "</script></div>\n";
}

// One specimen's section: verdict, slope estimate, warnings, figures.
void AppendSpecimenSection(const ReportSection& s, std::string* out) {
  std::string& h = *out;
  h += fmt::format(
      "<h2 id=\"{0}\">{0} <a class=\"back\" href=\"#summary\">back to the "
      "table</a></h2>\n",
      Escape(s.name));
  if (s.failed) {
    h += "<p class=\"error\">" + Escape(s.row.value("error", std::string())) +
         "</p>\n";
    return;
  }
  if (s.row.contains("headline") && s.row["headline"].is_string())
    h += "<p class=\"headline\">" +
         Escape(s.row["headline"].get<std::string>()) + "</p>\n";
  // The verdict's sentence where it says more than the headline.
  if (!s.row["verdict"].value("explained", false))
    h += "<p>" + Escape(s.row["verdict"]["summary"].get<std::string>()) +
         "</p>\n";
  if (s.row.contains("pairing") && s.row["pairing"].is_string())
    h += "<p class=\"note\">Files: " +
         Escape(s.row["pairing"].get<std::string>()) + "</p>\n";
  if (s.row.contains("assumptions") && s.row["assumptions"].is_array()) {
    for (const auto& a : s.row["assumptions"])
      h += "<p class=\"note\">Assumed: " + Escape(a.get<std::string>()) +
           "</p>\n";
  }
  h += NumbersTable(s.row);
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
  for (size_t i = 0; i < s.figures.shown.size(); ++i) {
    AppendImage(s.figures.shown[i], s.figures.titles[i], &h);
  }
  AppendViewer(s, &h);
  h += ProvenanceBlock(s.row);
}

}  // namespace

std::string RenderSpecimenSections(const std::vector<ReportSection>& sections) {
  // Reserved once rather than grown by doubling: the sections are mostly
  // their figures, whose sizes are known from the files.
  std::uintmax_t figures_bytes = 0;
  std::error_code ec;
  for (const auto& s : sections) {
    for (const std::string& f : s.figures.shown)
      figures_bytes += std::filesystem::file_size(f, ec) * !ec;
  }
  std::string h;
  h.reserve(static_cast<size_t>(figures_bytes + figures_bytes / 4) +
            sections.size() * 16384);
  for (const auto& s : sections) AppendSpecimenSection(s, &h);
  return h;
}

namespace {

// The page before the specimens' sections: the summary table and the
// batch figures.
std::string PageStart(const std::string& title,
                      const std::vector<ReportSection>& sections,
                      const FigureSet& batch) {
  std::uintmax_t figures_bytes = 0;
  std::error_code ec;
  for (const std::string& f : batch.shown)
    figures_bytes += std::filesystem::file_size(f, ec) * !ec;
  std::string h;
  h.reserve(static_cast<size_t>(figures_bytes + figures_bytes / 4) +
            (sections.size() + 1) * 1024 + 16384);
  h += ReportHead(title, sections);
  for (const auto& s : sections) h += SummaryRow(s);
  h += "</tbody></table></div>\n";
  if (!batch.shown.empty() || !batch.message.empty()) {
    h += "<h2>All specimens</h2>\n";
    if (!batch.message.empty()) h += "<p>" + Escape(batch.message) + "</p>\n";
    for (size_t i = 0; i < batch.shown.size(); ++i)
      AppendImage(batch.shown[i], batch.titles[i], &h);
  }
  return h;
}

// Marks the page once every image has decoded (read by the browser test
// and handy for anyone scripting the report).
constexpr const char* kPageEnd = R"(<script>
window.addEventListener('load', function () {
  var imgs = document.images, ok = 0;
  for (var i = 0; i < imgs.length; ++i) if (imgs[i].complete && imgs[i].naturalWidth > 0) ++ok;
  document.body.setAttribute('data-images-rendered', ok + '/' + imgs.length);
  document.body.setAttribute('data-table-rows', document.querySelectorAll('#summary tbody tr:not(.reason)').length);
  // What a reader sees at this window's width: horizontal overflow of the
  // page (px), the narrowest figure and the smallest text (px).
  var narrowest = Infinity, smallest = Infinity;
  for (var i = 0; i < imgs.length; ++i) narrowest = Math.min(narrowest, imgs[i].getBoundingClientRect().width);
  var texts = document.querySelectorAll('p, td, th, figcaption, li, summary, h1, h2, h3');
  for (var i = 0; i < texts.length; ++i) smallest = Math.min(smallest, parseFloat(getComputedStyle(texts[i]).fontSize));
  document.body.setAttribute('data-layout', [document.documentElement.scrollWidth - window.innerWidth, Math.round(narrowest), Math.round(smallest)].join(' '));
});
</script>
<script>
// The loop viewers: each draws the cycle its slider selects (?cycle=N at
// the start, else the last), from the data embedded beside it; plain
// canvas, no network.
(function () {
  var FORCE = '#1f77b4', MEASURED = '#000000', GREY = '#888888';
  function nice(span) {
    var step = Math.pow(10, Math.floor(Math.log10(span / 5)));
    var m = span / 5 / step;
    return step * (m >= 5 ? 5 : m >= 2 ? 2 : 1);
  }
  function range(arrays) {
    var lo = Infinity, hi = -Infinity;
    arrays.forEach(function (a) { a.forEach(function (v) { if (v !== null) { lo = Math.min(lo, v); hi = Math.max(hi, v); } }); });
    if (!(hi > lo)) { lo -= 1; hi += 1; }
    var pad = 0.05 * (hi - lo);
    return [lo - pad, hi + pad];
  }
  // Axes with ticks and labels; returns the data-to-pixel maps.
  function axes(ctx, w, h, xr, yr, xlabel, ylabel) {
    var L = 90, R = 20, T = 20, B = 70;
    ctx.clearRect(0, 0, w, h);
    ctx.fillStyle = '#fff'; ctx.fillRect(0, 0, w, h);
    ctx.strokeStyle = '#000'; ctx.lineWidth = 1; ctx.setLineDash([]);
    ctx.strokeRect(L, T, w - L - R, h - T - B);
    var X = function (v) { return L + (v - xr[0]) / (xr[1] - xr[0]) * (w - L - R); };
    var Y = function (v) { return h - B - (v - yr[0]) / (yr[1] - yr[0]) * (h - T - B); };
    ctx.font = '16px DejaVu Sans, Arial, sans-serif'; ctx.fillStyle = '#000';
    ctx.textAlign = 'center'; ctx.textBaseline = 'top';
    var sx = nice(xr[1] - xr[0]), sy = nice(yr[1] - yr[0]);
    for (var v = Math.ceil(xr[0] / sx) * sx; v <= xr[1]; v += sx) {
      ctx.beginPath(); ctx.moveTo(X(v), h - B); ctx.lineTo(X(v), h - B + 6); ctx.stroke();
      ctx.fillText(+v.toFixed(6) + '', X(v), h - B + 9);
    }
    ctx.fillText(xlabel, (L + w - R) / 2, h - 30);
    ctx.textAlign = 'right'; ctx.textBaseline = 'middle';
    for (var v = Math.ceil(yr[0] / sy) * sy; v <= yr[1]; v += sy) {
      ctx.beginPath(); ctx.moveTo(L - 6, Y(v)); ctx.lineTo(L, Y(v)); ctx.stroke();
      ctx.fillText(+v.toFixed(6) + '', L - 9, Y(v));
    }
    ctx.save(); ctx.translate(22, (T + h - B) / 2); ctx.rotate(-Math.PI / 2);
    ctx.textAlign = 'center'; ctx.fillText(ylabel, 0, 0); ctx.restore();
    return [X, Y];
  }
  // One direction's line, broken where a bin is empty; the points drawn.
  function line(ctx, map, xs, ys, colour, dashed, width) {
    ctx.strokeStyle = colour; ctx.lineWidth = width; ctx.setLineDash(dashed ? [8, 6] : []);
    var drawn = 0, open = false;
    ctx.beginPath();
    for (var i = 0; i < xs.length; ++i) {
      if (ys[i] === null) { open = false; continue; }
      var px = map[0](xs[i]), py = map[1](ys[i]);
      if (open) ctx.lineTo(px, py); else ctx.moveTo(px, py);
      open = true; ++drawn;
    }
    ctx.stroke();
    return drawn;
  }
  function slice(a, at, n, scale) {
    var out = new Array(n);
    for (var i = 0; i < n; ++i) out[i] = a[at + i] === null ? null : a[at + i] * scale;
    return out;
  }
  function setUp(div, start) {
    var d = JSON.parse(div.querySelector('.viewer-data').textContent);
    var n = d.cycles.length, nb = d.x_mm.length, nm = d.map_x_mm.length;
    var slider = div.querySelector('input'), label = div.querySelector('.viewer-label');
    var loop = div.querySelector('canvas.loop'), map = div.querySelector('canvas.map');
    slider.max = n - 1;
    var qAll = [d.q.map(function (v) { return v === null ? null : v * d.q_scale_n; }),
                d.q_model.map(function (v) { return v === null ? null : v * d.q_scale_n; })];
    var qr = range(qAll), xr = range([d.x_mm]);
    var mr = range([d.mu_raw.map(function (v) { return v === null ? null : v * d.mu_scale; }),
                    d.mu_corrected.map(function (v) { return v === null ? null : v * d.mu_scale; })]);
    function draw(i) {
      var points = 0, c = loop.getContext('2d');
      var m = axes(c, loop.width, loop.height, xr, qr, 'x (mm)', 'Q (N)');
      for (var dir = 0; dir < 2; ++dir) {
        var at = (i * 2 + dir) * nb;
        points += line(c, m, d.x_mm, slice(d.q, at, nb, d.q_scale_n), MEASURED, dir === 1, 2);
        points += line(c, m, d.x_mm, slice(d.q_model, at, nb, d.q_scale_n), FORCE, dir === 1, 2);
      }
      var g = map.getContext('2d');
      var mm = axes(g, map.width, map.height, xr, mr, 'x (mm)', 'mu along the stroke (-)');
      for (var dir = 0; dir < 2; ++dir) {
        var at = (i * 2 + dir) * nm;
        points += line(g, mm, d.map_x_mm, slice(d.mu_raw, at, nm, d.mu_scale), GREY, dir === 1, 2);
        points += line(g, mm, d.map_x_mm, slice(d.mu_corrected, at, nm, d.mu_scale), FORCE, dir === 1, 3);
      }
      var mu = d.mu_hat[i];
      label.textContent = 'cycle ' + d.cycles[i] + ' of ' + d.of_cycles + ': mu-hat ' +
          (mu === null ? 'not fitted' : (mu * d.mu_hat_scale).toFixed(4)) + ' (' + d.mu_hat_from + ')';
      div.setAttribute('data-cycle', d.cycles[i]);
      div.setAttribute('data-points', points);
    }
    var first = n - 1;
    if (start > 0) for (var k = 0; k < n; ++k) if (d.cycles[k] <= start) first = k;
    slider.value = first;
    slider.addEventListener('input', function () { draw(+slider.value); });
    draw(first);
  }
  window.addEventListener('load', function () {
    var start = +(new URLSearchParams(window.location.search).get('cycle') || 0);
    var views = document.querySelectorAll('div.viewer');
    for (var i = 0; i < views.length; ++i) {
      try { setUp(views[i], start); } catch (e) { views[i].setAttribute('data-error', e.message); }
    }
    document.body.setAttribute('data-viewers', views.length);
  });
})();
</script>
</body></html>
)";

}  // namespace

std::string RenderReport(const std::string& title,
                         const std::vector<ReportSection>& sections,
                         const FigureSet& batch) {
  return PageStart(title, sections, batch) + RenderSpecimenSections(sections) +
         kPageEnd;
}

void WriteReport(const std::string& path,
                 const std::string& title,
                 const std::vector<ReportSection>& sections,
                 const FigureSet& batch,
                 const std::string& specimen_sections) {
  support::AtomicFile<OutputError> file(path);
  file.Write(PageStart(title, sections, batch));
  file.Write(specimen_sections);
  file.Write(kPageEnd);
  file.Commit();
}

}  // namespace wearscar::report
