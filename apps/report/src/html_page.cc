#include "html_page.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>

#include "wearscar/fusion/provenance.h"

namespace wearscar::report::internal {

std::string Escape(const std::string& s) {
  std::string out;
  out.reserve(s.size());
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

std::string Number(const nlohmann::json& j, const char* fmt_spec) {
  if (!j.is_number()) return "";
  const double v = j.get<double>();
  return std::isfinite(v) ? fmt::format(fmt::runtime(fmt_spec), v) : "";
}

nlohmann::json At(const nlohmann::json& j,
                  std::initializer_list<const char*> path) {
  const nlohmann::json* p = &j;
  for (const char* k : path) {
    if (!p->is_object() || !p->contains(k)) return nullptr;
    p = &(*p)[k];
  }
  return *p;
}

std::string PageHead(const std::string& title,
                     const nlohmann::json& provenance) {
  return fmt::format(
      R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{0}</title>
<meta name="viewport" content="width=device-width, initial-scale=1">
<style>
body {{ font-family: 'DejaVu Sans', Arial, sans-serif; margin: 2em; color: #222; }}
table {{ border-collapse: collapse; font-size: 0.9em; }}
th, td {{ border: 1px solid #bbb; padding: 0.3em 0.5em; text-align: right; }}
th {{ background: #eee; }} td.name, td.text {{ text-align: left; }}
tr.flagged td {{ background: #ffe3b3; }} tr.failed td {{ background: #ffc4c4; }}
tr.unsettled td, tr.unjudged td {{ background: #fff6cc; }}
div.wide {{ overflow-x: auto; max-width: 100%; }}
#summary thead th {{ position: sticky; top: 0; z-index: 1; cursor: pointer; }}
#summary td.name {{ position: sticky; left: 0; background: #fff; white-space: nowrap; }}
#summary tr.flagged td.name {{ background: #ffe3b3; }} #summary tr.failed td.name {{ background: #ffc4c4; }}
#summary tr.unsettled td.name, #summary tr.unjudged td.name {{ background: #fff6cc; }}
#summary td.file {{ white-space: nowrap; }}
#summary th.sorted-up::after {{ content: ' \25B2'; }} #summary th.sorted-down::after {{ content: ' \25BC'; }}
tr.reason td {{ text-align: left; border-top: none; }}
tr.reason div {{ position: sticky; left: 0.5em; max-width: calc(100vw - 6em); white-space: normal; }}
nav {{ margin: 0.5em 0 1em; }} nav a {{ margin-right: 1.5em; }}
figure {{ display: block; margin: 1em 0; }}
img {{ width: 1200px; max-width: 100%; height: auto; border: 1px solid #ddd; }}
figcaption {{ font-size: 0.9em; color: #555; }}
table.numbers {{ margin: 0.5em 1em 0.5em 0; display: inline-table; vertical-align: top; }}
details {{ margin: 1em 0; font-size: 0.9em; }} pre {{ white-space: pre-wrap; }}
div.viewer {{ margin: 1em 0; }} div.viewer canvas {{ width: 1200px; max-width: 100%; border: 1px solid #ddd; display: block; margin: 0.5em 0; }}
div.viewer input {{ width: 40em; max-width: 70vw; vertical-align: middle; }} p.headline {{ font-size: 1.15em; font-weight: bold; }}
input.filter {{ width: 24em; font-size: 1em; }} p.filters {{ margin: 0.5em 0; }}
</style></head><body>
<h1>{0}</h1>
<p class="made">made by wearscar {1} (commit {2}) on {3}</p>
)",
      Escape(title),
      provenance.is_object() ? Escape(provenance.value("wearscar_version", ""))
                             : fusion::Version(),
      provenance.is_object() ? Escape(provenance.value("git_commit", ""))
                             : fusion::GitCommit(),
      provenance.is_object() ? Escape(provenance.value("date_utc", ""))
                             : fusion::CurrentProvenance().date_utc);
}

std::string RelativeUrl(const std::string& path, const std::string& dir) {
  namespace fs = std::filesystem;
  const fs::path from = fs::absolute(dir).lexically_normal();
  const fs::path to = fs::absolute(path).lexically_normal();
  const fs::path rel = to.lexically_relative(from);
  return rel.empty() ? to.generic_string() : rel.generic_string();
}

std::string ImageTag(const std::string& path,
                     const std::string& page_dir,
                     const std::string& title) {
  const std::string alt = Escape(title);
  return fmt::format(
      "<figure><img loading=\"lazy\" decoding=\"async\" alt=\"{0}\" "
      "src=\"{1}\"><figcaption>{0}</figcaption></figure>\n",
      alt,
      Escape(RelativeUrl(path, page_dir)));
}

const char* const kImagesScript = R"(<script>
window.addEventListener('load', function () {
  var t = performance.timing;
  document.body.setAttribute('data-load-ms', t.loadEventStart - t.navigationStart);
  var imgs = Array.prototype.slice.call(document.images);
  var all = new URLSearchParams(window.location.search).get('images') === 'all';
  if (all) imgs.forEach(function (i) { i.loading = 'eager'; });
  function settled(i) {
    if (i.complete && i.naturalWidth > 0) return Promise.resolve(1);
    if (!all) return Promise.resolve(0);
    return new Promise(function (done) {
      i.addEventListener('load', function () { done(1); });
      i.addEventListener('error', function () { done(0); });
    });
  }
  Promise.all(imgs.map(settled)).then(function (ok) {
    var n = ok.reduce(function (a, b) { return a + b; }, 0);
    // What a reader sees at this window's width: horizontal overflow of
    // the page (px), the narrowest figure and the smallest text (px).
    var narrowest = Infinity, smallest = Infinity;
    imgs.forEach(function (i) { narrowest = Math.min(narrowest, i.getBoundingClientRect().width); });
    var texts = document.querySelectorAll('p, td, th, figcaption, li, summary, h1, h2, h3');
    for (var k = 0; k < texts.length; ++k) smallest = Math.min(smallest, parseFloat(getComputedStyle(texts[k]).fontSize));
    document.body.setAttribute('data-layout', [document.documentElement.scrollWidth - window.innerWidth, Math.round(narrowest), Math.round(smallest)].join(' '));
    document.body.setAttribute('data-images-rendered', n + '/' + imgs.length);
  });
});
</script>
)";

}  // namespace wearscar::report::internal
