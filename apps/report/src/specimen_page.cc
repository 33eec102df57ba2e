#include "specimen_page.h"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>

#include "html_page.h"
#include "wearscar/report/output_folder.h"
#include "wearscar/support/atomic_file.h"

namespace wearscar::report::internal {
namespace {

namespace fs = std::filesystem;

// The whole file, or "" when it cannot be read.
std::string ReadWhole(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)),
                     std::istreambuf_iterator<char>());
}

// The files the specimen's numbers come from, and how they paired.
std::string FilesLine(const nlohmann::json& row) {
  const auto text = [&](const char* key) {
    return row.contains(key) && row[key].is_string()
               ? row[key].get<std::string>()
               : std::string();
  };
  const std::string force = text("force_file"), scan = text("scan_file"),
                    pairing = text("pairing");
  return "<p class=\"note\">Files: force " +
         Escape(force.empty() ? "-" : force) + "; scan " +
         Escape(scan.empty() ? "none" : scan) +
         (pairing.empty() ? "" : " (" + Escape(pairing) + ")") + "</p>\n";
}

// A number of the row at a path, or "" where there is none.
std::string NumberAt(const nlohmann::json& row,
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
    const std::string m = NumberAt(r, {"comparison", stat, "mean"}),
                      sd = NumberAt(r, {"comparison", stat, "sd"});
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
      NumberAt(r, {"comparison", "J_force", "mean"}, "{:.3f}"),
      NumberAt(r, {"comparison", "J_scan", "mean"}, "{:.3f}"));
  h += fmt::format(
      "<tr><td class=\"text\">J's noise floor (what the noise "
      "explains)</td><td>{}</td><td>{}</td></tr>\n",
      NumberAt(r, {"comparison", "J_force_split", "noise_floor"}, "{:.3f}"),
      NumberAt(r, {"comparison", "J_scan_split", "noise_floor"}, "{:.3f}"));
  h += fmt::format(
      "<tr><td class=\"text\">J excess</td><td>{}</td><td>{}</td></tr>\n",
      NumberAt(r, {"comparison", "J_force_split", "excess"}, "{:.3f}"),
      NumberAt(r, {"comparison", "J_scan_split", "excess"}, "{:.3f}"));
  h += "</tbody></table>\n<table class=\"numbers\"><tbody>\n";
  const std::pair<const char*, std::string> rows[] = {
      {"mu mean (Q/P over gross slip)", pm("mu_mean")},
      {"mu energy", pm("mu_energy")},
      {"wear volume (mm<sup>3</sup>)",
       NumberAt(r, {"wear", "volume_mm3"}, "{:.4g}")},
      {"track mean / max depth (mm)",
       NumberAt(r, {"wear", "mean_depth_mm"}) + " / " +
           NumberAt(r, {"wear", "max_depth_mm"})},
      {"track width (mm)", NumberAt(r, {"wear", "width_mm"}, "{:.3f}")},
      {"normal load (N)", NumberAt(r, {"wear", "normal_load_n"}, "{:.2f}")},
      {"sliding distance (m)",
       NumberAt(r, {"wear", "sliding_distance_m"}, "{:.4g}")},
      {"specific wear rate (mm<sup>3</sup>/(N m))",
       NumberAt(r, {"wear", "specific_wear_rate_mm3_per_n_m"}, "{:.4g}")},
      {"spatial variation of mu, corrected (its noise floor); raw",
       NumberAt(r, {"friction_map", "spatial_sd_corrected"}) + " (" +
           NumberAt(r, {"friction_map", "spatial_sd_noise_floor"}) + "); " +
           NumberAt(r, {"friction_map", "spatial_sd_raw"})},
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
        NumberAt(r, {"lugre", "J"}, "{:.4f}"),
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
// drawn by the page's script (kViewerScript) into two canvases: the cycle's Q-x
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

// The specimen's verdict, files, assumptions, numbers, warnings,
// figures, loop viewer and provenance.
void AppendSpecimenBody(const ReportSection& s,
                        const std::string& page_dir,
                        std::string* out) {
  std::string& h = *out;
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
  h += FilesLine(s.row);
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
    h += ImageTag(s.figures.shown[i], page_dir, s.figures.titles[i]);
  }
  AppendViewer(s, &h);
  h += ProvenanceBlock(s.row);
}

// The loop viewer's drawing: the cycle its slider selects (?cycle=N at
// the start, else the last), from the data embedded beside it; plain
// canvas, no network.
const char* const kViewerScript = R"(<script>
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
)";

}  // namespace

std::string RenderSpecimenPage(const ReportSection& s,
                               const std::string& page_dir,
                               const SpecimenLinks& links) {
  std::string h = PageHead(s.name, At(s.row, {"provenance"}));
  h += "<nav>";
  if (!links.index.empty())
    h += "<a href=\"" + Escape(links.index) + "\">all specimens</a>";
  if (!links.previous.empty())
    h += "<a href=\"" + Escape(links.previous) +
         "\">previous: " + Escape(links.previous_name) + "</a>";
  if (!links.next.empty())
    h += "<a href=\"" + Escape(links.next) +
         "\">next: " + Escape(links.next_name) + "</a>";
  h += "</nav>\n";
  AppendSpecimenBody(s, page_dir, &h);
  h += kImagesScript;
  h += kViewerScript;
  h += "</body></html>\n";
  return h;
}

void WriteSpecimenPage(const ReportSection& s,
                       const std::string& path,
                       const SpecimenLinks& links) {
  support::WriteFileAtomically<OutputError>(
      path,
      RenderSpecimenPage(s, fs::path(path).parent_path().string(), links));
}

}  // namespace wearscar::report::internal
