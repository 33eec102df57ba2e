#include "wearscar/report/html_report.h"

#include <fmt/format.h>

#include <filesystem>

#include "group_section.h"
#include "html_page.h"
#include "specimen_page.h"
#include "wearscar/report/output_folder.h"
#include "wearscar/support/atomic_file.h"

namespace wearscar::report {

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

namespace fs = std::filesystem;
using internal::At;
using internal::Escape;
using internal::Number;

std::string Text(const nlohmann::json& j) {
  return j.is_string() ? j.get<std::string>() : std::string();
}

// A column of the summary table: its heading, and its cell of a row.
struct Column {
  const char* heading;
  std::string (*cell)(const nlohmann::json& row);
  bool text = false;  // left-aligned, sorted as text
  bool file = false;  // a file name: on one line
};

std::string FileName(const nlohmann::json& j) {
  const std::string path = Text(j);
  return path.empty() ? "" : fs::path(path).filename().string();
}

// Test conditions, files and results, in the table's order. The
// frequency and speed are the drive's over the complete cycles.
const Column kColumns[] = {
    {"species",
     [](const nlohmann::json& r) { return Text(r["species"]); },
     true},
    {"plane", [](const nlohmann::json& r) { return Text(r["plane"]); }, true},
    {"direction",
     [](const nlohmann::json& r) { return Text(r["direction"]); },
     true},
    {"force file",
     [](const nlohmann::json& r) { return FileName(r["force_file"]); },
     true,
     true},
    {"scan file",
     [](const nlohmann::json& r) { return FileName(r["scan_file"]); },
     true,
     true},
    {"load (N)",
     [](const nlohmann::json& r) {
       return Number(At(r, {"wear", "normal_load_n"}), "{:.2f}");
     }},
    {"frequency (Hz)",
     [](const nlohmann::json& r) {
       return Number(r["frequency_hz"], "{:.3g}");
     }},
    {"stroke (mm)",
     [](const nlohmann::json& r) { return Number(r["stroke_mm"], "{:.3f}"); }},
    {"mean speed (mm/s)",
     [](const nlohmann::json& r) {
       return Number(r["mean_speed_mm_s"], "{:.3g}");
     }},
    {"sampling rate (Hz)",
     [](const nlohmann::json& r) {
       return Number(r["sampling_rate_hz"], "{:.6g}");
     }},
    {"cycles",
     [](const nlohmann::json& r) { return Number(r["cycles"], "{:.0f}"); }},
    {"mu to quote",
     [](const nlohmann::json& r) {
       return Number(At(r, {"quote", "mu"}));
     }},
    {"its 95% interval",
     [](const nlohmann::json& r) {
       const nlohmann::json iv = At(r, {"quote", "interval95"});
       return iv.is_array() && iv.size() == 2 && iv[0].is_number()
                  ? Number(iv[0]) + "&ndash;" + Number(iv[1])
                  : std::string();
     }},
    {"mu-hat (k from P or depth)",
     [](const nlohmann::json& r) {
       return Number(At(r, {"comparison", "mu_hat_force", "mean"}));
     }},
    {"its 95% interval",
     [](const nlohmann::json& r) {
       const nlohmann::json iv =
           At(r, {"comparison", "mu_hat_force", "interval95"});
       return iv.is_array() && iv.size() == 2
                  ? Number(iv[0]) + "&ndash;" + Number(iv[1])
                  : std::string();
     }},
    {"mu-hat (k from scan)",
     [](const nlohmann::json& r) {
       return Number(At(r, {"comparison", "mu_hat_scan", "mean"}));
     }},
    {"mu mean",
     [](const nlohmann::json& r) {
       return Number(At(r, {"comparison", "mu_mean", "mean"}));
     }},
    {"mu energy",
     [](const nlohmann::json& r) {
       return Number(At(r, {"comparison", "mu_energy", "mean"}));
     }},
    {"J",
     [](const nlohmann::json& r) {
       return Number(At(r, {"comparison", "J_force", "mean"}), "{:.3f}");
     }},
    {"J noise floor",
     [](const nlohmann::json& r) {
       return Number(At(r, {"comparison", "J_force_split", "noise_floor"}),
                     "{:.3f}");
     }},
    {"J excess",
     [](const nlohmann::json& r) {
       return Number(At(r, {"comparison", "J_force_split", "excess"}),
                     "{:.3f}");
     }},
    {"J (k from scan)",
     [](const nlohmann::json& r) {
       return Number(At(r, {"comparison", "J_scan", "mean"}), "{:.3f}");
     }},
    {"its floor",
     [](const nlohmann::json& r) {
       return Number(At(r, {"comparison", "J_scan_split", "noise_floor"}),
                     "{:.3f}");
     }},
    {"r profiles",
     [](const nlohmann::json& r) {
       return Number(At(r, {"comparison", "profile_correlation"}), "{:.3f}");
     }},
    {"amplitude ratio",
     [](const nlohmann::json& r) {
       return Number(At(r, {"comparison", "amplitude_ratio"}), "{:.2f}");
     }},
    {"wear rate (mm<sup>3</sup>/(N m))",
     [](const nlohmann::json& r) {
       return Number(At(r, {"wear", "specific_wear_rate_mm3_per_n_m"}),
                     "{:.3g}");
     }},
    {"warnings",
     [](const nlohmann::json& r) {
       return r["warnings"].is_array() ? std::to_string(r["warnings"].size())
                                       : std::string();
     }},
};

// The columns with a value in some row (species, plane and direction are
// empty when no name follows the naming pattern).
std::vector<const Column*> ShownColumns(
    const std::vector<ReportSection>& sections) {
  std::vector<const Column*> shown;
  for (const Column& c : kColumns) {
    for (const auto& s : sections) {
      if (!s.failed && !c.cell(s.row).empty()) {
        shown.push_back(&c);
        break;
      }
    }
  }
  return shown;
}

// The specimen's page, relative to the index ("" when it has none).
std::string PageUrl(const ReportSection& s) {
  return s.failed ? std::string()
                  : (fs::path(s.name) / "report.html").generic_string();
}

// One specimen's rows of the summary table: its cells, and for a flagged
// or failed one the reason under it, in view whatever the table's scroll
// (one <tbody> each: sorted and filtered together).
std::string SummaryRows(const ReportSection& s,
                        const std::vector<const Column*>& columns) {
  // The status fusion::QuoteOf gave (an older row without one: its verdict).
  std::string status = Text(At(s.row, {"quote", "status"}));
  if (s.failed) status = "failed";
  if (status.empty()) status = s.flagged ? "not explained" : "explained";
  const std::string cls = status == "failed"          ? "failed"
                          : status == "not explained" ? "flagged"
                          : status == "not settled"   ? "unsettled"
                          : status == "explained"     ? "ok"
                                                      : "unjudged";
  const std::string full = s.failed ? "error: " + Text(s.row["error"])
                                    : Text(At(s.row, {"verdict", "summary"}));
  const std::string url = PageUrl(s);
  std::string h = fmt::format(
      "<tbody><tr class=\"{}\"><td class=\"name\">{}</td>",
      cls,
      url.empty()
          ? Escape(s.name)
          : "<a href=\"" + Escape(url) + "\">" + Escape(s.name) + "</a>");
  for (const Column* c : columns) {
    h += c->file   ? "<td class=\"text file\">"
         : c->text ? "<td class=\"text\">"
                   : "<td>";
    h += s.failed ? std::string()
                  : (c->text ? Escape(c->cell(s.row)) : c->cell(s.row));
    h += "</td>";
  }
  h +=
      fmt::format("<td class=\"text\"><span title=\"{}\">{}</span></td></tr>\n",
                  Escape(full),
                  Escape(status));
  if (cls != "ok") {
    h += fmt::format(
        "<tr class=\"reason {}\"><td colspan=\"{}\"><div>{}</div></td></tr>\n",
        cls,
        columns.size() + 2,
        Escape(status == "not settled"
                   ? "not settled: " + Text(At(s.row, {"verdict", "screen"}))
                   : full));
  }
  return h + "</tbody>\n";
}

// The table's rows wait in a <template> (parsed, not laid out) and are
// shown a page at a time: a thousand rows laid out at once took Chromium
// seconds. Sorting by a heading's click (numbers as numbers, empty cells
// last) and filtering by text and by verdict act on every row, also from
// the page's address (?filter=, ?verdict=, ?sort=); the body's
// data-table-rows counts the rows that pass the filters, data-page-rows
// those on the page.
constexpr const char* kTableScript = R"(<script>
(function () {
  var table = document.getElementById('summary');
  var rows = Array.prototype.slice.call(document.getElementById('rows').content.children);
  var text = document.getElementById('filter-text'), verdict = document.getElementById('filter-verdict');
  var size = document.getElementById('page-size'), shown = document.getElementById('shown');
  var prev = document.getElementById('page-prev'), next = document.getElementById('page-next');
  // Each row's cells and words, read when first sorted or filtered.
  var keys = null, words = null;
  function read() {
    if (keys) return;
    keys = rows.map(function (b) {
      return Array.prototype.map.call(b.rows[0].cells, function (c) { return c.textContent.trim(); });
    });
    words = rows.map(function (b) { return b.textContent.toLowerCase(); });
  }
  var order = rows.map(function (b, i) { return i; }), passing = order, page = 0;
  function draw() {
    var n = size.value === 'all' ? passing.length : +size.value;
    var pages = Math.max(1, Math.ceil(passing.length / n));
    page = Math.min(Math.max(page, 0), pages - 1);
    while (table.tBodies.length) table.removeChild(table.tBodies[0]);
    var from = page * n, to = Math.min(passing.length, from + n);
    for (var k = from; k < to; ++k) table.appendChild(rows[passing[k]]);
    shown.textContent = (passing.length ? (from + 1) + '-' + to : '0') + ' of ' + passing.length +
        (passing.length < rows.length ? ' passing the filter (' + rows.length + ' specimens)' : '');
    prev.disabled = page === 0;
    next.disabled = page >= pages - 1;
    document.body.setAttribute('data-table-rows', passing.length);
    document.body.setAttribute('data-page-rows', to - from);
  }
  function filter() {
    read();
    var want = text.value.toLowerCase().split(/\s+/).filter(Boolean), v = verdict.value;
    passing = order.filter(function (i) {
      return want.every(function (w) { return words[i].indexOf(w) >= 0; }) &&
          (v === '' || rows[i].rows[0].classList.contains(v));
    });
    page = 0;
    draw();
  }
  var heads = table.tHead.rows[0].cells;
  Array.prototype.forEach.call(heads, function (head, c) {
    head.addEventListener('click', function () {
      read();
      var up = !head.classList.contains('sorted-up');
      Array.prototype.forEach.call(heads, function (h) { h.classList.remove('sorted-up', 'sorted-down'); });
      head.classList.add(up ? 'sorted-up' : 'sorted-down');
      order.sort(function (a, b) {
        var x = keys[a][c], y = keys[b][c], nx = parseFloat(x), ny = parseFloat(y);
        if (x === '' || y === '') return x === y ? 0 : x === '' ? 1 : -1;
        var d = !isNaN(nx) && !isNaN(ny) ? nx - ny : x.localeCompare(y);
        return up ? d : -d;
      });
      filter();
    });
  });
  text.addEventListener('input', filter);
  verdict.addEventListener('change', filter);
  size.addEventListener('change', draw);
  prev.addEventListener('click', function () { --page; draw(); });
  next.addEventListener('click', function () { ++page; draw(); });
  // A view to link to: ?filter=words&verdict=flagged&sort=heading (-heading
  // descending).
  var q = new URLSearchParams(window.location.search);
  if (q.get('filter')) text.value = q.get('filter');
  if (q.get('verdict')) verdict.value = q.get('verdict');
  var by = q.get('sort') || '', down = by.charAt(0) === '-';
  if (down) by = by.slice(1);
  Array.prototype.forEach.call(heads, function (head) {
    if (by && head.textContent === by) {
      head.click();
      if (down) head.click();
    }
  });
  if (text.value || verdict.value) filter(); else draw();
})();
</script>
)";

}  // namespace

std::string RenderIndex(const std::string& out,
                        const std::string& title,
                        const std::vector<ReportSection>& sections,
                        const FigureSet& batch,
                        const std::vector<fusion::GroupComparison>& groups) {
  int flagged = 0, failed = 0;
  for (const auto& s : sections) {
    flagged += s.flagged;
    failed += s.failed;
  }
  const std::vector<const Column*> columns = ShownColumns(sections);
  std::string h = internal::PageHead(title);
  h.reserve(h.size() + sections.size() * 2048 + 16384);
  h += fmt::format(
      "<p>{} specimens: {} not explained by wear-scar interaction, {} failed "
      "to analyse. mu-hat: the wear-scar coefficient of friction (Eq. 6) "
      "with the slope of the sliding path from the normal force (k = dP/dx / "
      "S) and, with a scan, from the worn track (the sphere's path or its "
      "centreline). A specimen's name opens its page: verdict, numbers, "
      "figures and its loops cycle by cycle. <a href=\"#groups\">The groups "
      "compared</a> follow the table.</p>\n"
      "<p class=\"filters\"><input class=\"filter\" id=\"filter-text\" "
      "type=\"search\" placeholder=\"filter: words in any column\" "
      "aria-label=\"filter the specimens\"> <select id=\"filter-verdict\" "
      "aria-label=\"verdict\"><option value=\"\">every verdict</option>"
      "<option value=\"ok\">explained</option><option value=\"unsettled\">"
      "not settled</option><option value=\"flagged\">not explained</option>"
      "<option value=\"unjudged\">not judged</option><option "
      "value=\"failed\">failed</option></select> "
      "<button id=\"page-prev\" type=\"button\">previous</button> "
      "<span id=\"shown\"></span> <button id=\"page-next\" "
      "type=\"button\">next</button> <select id=\"page-size\" "
      "aria-label=\"rows a page\"><option>100</option><option>500</option>"
      "<option value=\"all\">all rows</option></select></p>\n"
      "<noscript><p>The table is shown by the page's script; summary.csv "
      "holds the same rows.</p></noscript>\n"
      "<div class=\"wide\"><table id=\"summary\"><thead><tr><th>specimen</th>",
      sections.size(),
      flagged,
      failed);
  for (const Column* c : columns)
    h += std::string("<th>") + c->heading + "</th>";
  h += "<th>status</th></tr></thead></table></div>\n<template id=\"rows\">";
  for (const auto& s : sections) h += SummaryRows(s, columns);
  h += "</template>\n";
  h += internal::GroupSection(groups);
  if (!batch.shown.empty() || !batch.message.empty()) {
    h += "<h2>All specimens</h2>\n";
    if (!batch.message.empty()) h += "<p>" + Escape(batch.message) + "</p>\n";
    for (size_t i = 0; i < batch.shown.size(); ++i)
      h += internal::ImageTag(batch.shown[i], out, batch.titles[i]);
  }
  h += kTableScript;
  h += internal::kImagesScript;
  return h + "</body></html>\n";
}

void WriteTestPage(const std::string& dir,
                   const std::string& name,
                   const nlohmann::json& result,
                   const FigureSet& figures) {
  ReportSection s;
  s.name = name;
  s.row = result;
  s.figures = figures;
  s.flagged = !result.value("verdict", nlohmann::json::object())
                   .value("explained", true);
  const fs::path viewer = fs::path(dir) / "loop_viewer.json";
  std::error_code ec;
  if (fs::exists(viewer, ec)) s.viewer = viewer.string();
  internal::WriteSpecimenPage(
      s, (fs::path(dir) / "report.html").string(), internal::SpecimenLinks{});
}

void WriteReport(const std::string& out,
                 const std::string& title,
                 const std::vector<ReportSection>& sections,
                 const FigureSet& batch,
                 const std::vector<fusion::GroupComparison>& groups) {
  std::vector<size_t> pages;
  for (size_t i = 0; i < sections.size(); ++i)
    if (!sections[i].failed) pages.push_back(i);
  for (size_t k = 0; k < pages.size(); ++k) {
    const ReportSection& s = sections[pages[k]];
    const fs::path page = fs::path(out) / PageUrl(s);
    const std::string dir = page.parent_path().string();
    internal::SpecimenLinks links;
    links.index =
        internal::RelativeUrl((fs::path(out) / "report.html").string(), dir);
    if (k > 0) {
      const ReportSection& p = sections[pages[k - 1]];
      links.previous =
          internal::RelativeUrl((fs::path(out) / PageUrl(p)).string(), dir);
      links.previous_name = p.name;
    }
    if (k + 1 < pages.size()) {
      const ReportSection& n = sections[pages[k + 1]];
      links.next =
          internal::RelativeUrl((fs::path(out) / PageUrl(n)).string(), dir);
      links.next_name = n.name;
    }
    internal::WriteSpecimenPage(s, page.string(), links);
  }
  support::WriteFileAtomically<OutputError>(
      (fs::path(out) / "report.html").string(),
      RenderIndex(out, title, sections, batch, groups));
}

}  // namespace wearscar::report
