#include "wearscar/report/specimen_folder.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <future>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "draw.h"
#include "wearscar/report/figures.h"
#include "wearscar/report/output_folder.h"

namespace wearscar::report {

namespace fs = std::filesystem;

namespace {

// The tables' files, on two threads when `parallel`: each table's text in
// pieces of at most kPieceRows rows, the largest tables' first, formatted
// by whichever thread takes each; the thread that formats a table's last
// piece joins them and writes the file (only the tables in progress are
// held as text: 6000 cycles' tables are tens of MB).
void WriteTables(const std::string& dir,
                 const std::vector<std::pair<std::string, fusion::Table>>& t,
                 bool parallel) {
  constexpr std::size_t kPieceRows = 8192;
  std::vector<std::size_t> order(t.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto cells = [&t](std::size_t i) {
    return t[i].second.rows.size() * t[i].second.columns.size();
  };
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) {
    return cells(a) > cells(b);
  });
  struct Piece {
    std::size_t table, index, first, last;
  };
  std::vector<Piece> pieces;
  std::vector<std::vector<std::string>> text(t.size());
  const auto left = std::make_unique<std::atomic<std::size_t>[]>(t.size());
  for (const std::size_t i : order) {
    const std::size_t rows = t[i].second.rows.size();
    const std::size_t n =
        std::max<std::size_t>(1, (rows + kPieceRows - 1) / kPieceRows);
    text[i].resize(n);
    left[i] = n;
    for (std::size_t j = 0; j < n; ++j)
      pieces.push_back(
          {i, j, j * kPieceRows, std::min(rows, (j + 1) * kPieceRows)});
  }
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t k; (k = next++) < pieces.size();) {
      const Piece& p = pieces[k];
      text[p.table][p.index] = t[p.table].second.ToCsv(p.first, p.last);
      if (--left[p.table] > 0) continue;
      std::size_t bytes = 0;
      for (const std::string& part : text[p.table]) bytes += part.size();
      std::string whole;
      whole.reserve(bytes);
      for (std::string& part : text[p.table]) {
        whole += part;
        std::string().swap(part);
      }
      WriteTextAtomically((fs::path(dir) / t[p.table].first).string(), whole);
    }
  };
  std::future<void> beside =
      std::async(parallel ? std::launch::async : std::launch::deferred, work);
  work();
  beside.get();
}

}  // namespace

fusion::TestProducts WriteTestTables(const std::string& dir,
                                     const std::string& name,
                                     const force::ForceRecord& record,
                                     const fusion::TestResult& r,
                                     const fusion::FuseOptions& o,
                                     const fusion::ProductOptions& w) {
  EnsureDirectory(dir);
  // The inputs' checksums (the scan's, and the force file's unless the
  // record holds it) on a second core while the tables are made and
  // written; result.json takes them as MakeTestProducts would have put
  // them, under "provenance".
  std::future<fusion::Provenance> provenance;
  if (w.provenance) {
    provenance =
        std::async(o.parallel ? std::launch::async : std::launch::deferred,
                   [&record, &r] { return fusion::TestProvenance(record, r); });
  }
  fusion::ProductOptions without_provenance = w;
  without_provenance.provenance = false;
  fusion::TestProducts products =
      fusion::MakeTestProducts(name, record, r, o, without_provenance);
  WriteTables(dir, products.tables, o.parallel);
  for (const auto& [file, text] : products.documents)
    WriteTextAtomically((fs::path(dir) / file).string(), text);
  if (provenance.valid()) {
    products.result["provenance"] = provenance.get().ToJson();
  }
  return products;
}

void WriteResult(const std::string& dir, const fusion::TestProducts& products) {
  WriteTextAtomically((fs::path(dir) / products.result_name).string(),
                      products.ResultText());
}

fusion::TestProducts WriteTestResults(const std::string& dir,
                                      const std::string& name,
                                      const force::ForceRecord& record,
                                      const fusion::TestResult& r,
                                      const fusion::FuseOptions& o,
                                      const fusion::ProductOptions& w) {
  fusion::TestProducts products = WriteTestTables(dir, name, record, r, o, w);
  WriteResult(dir, products);
  return products;
}

namespace {

// a(x) beside what was measured along the track: above, the recovered
// shape with the friction map's steady pattern per direction (the same
// units); below, the groove's depth, on the same x.
std::string AlongTrackFigure(const std::string& ext,
                             const std::string& name,
                             const fusion::Diagnosis& d) {
  const auto& a = d.along_track;
  const bool map = a.map_x_mm.size() > 0;
  std::string gp = fmt::format(
      "{}set output 'diagnosis_friction_along_track.{}'\n"
      "set multiplot layout 2,1 title {} noenhanced\nset xlabel 'x (mm)'\n"
      "set ylabel 'mu / mean mu - 1 (-)'\nset title {} noenhanced\nplot "
      "'friction_along_track.csv' skip 1 using 1:2 with lines lw 2 title "
      "'a(x), recovered'",
      internal::Terminal(ext, 2),
      ext,
      internal::Quote(name + ": friction along the track"),
      internal::Quote(
          map ? fmt::format("a(x) recovered and the friction map's pattern "
                            "(r = {:.2f})",
                            a.correlation_map)
              : std::string("a(x) recovered")));
  if (map) {
    gp +=
        ", 'friction_map_along_track.csv' skip 1 using 1:2 with linespoints "
        "pt 7 ps 0.6 title 'friction map, forward', '' skip 1 using 1:3 with "
        "linespoints pt 5 ps 0.6 title 'friction map, reverse'";
  }
  return gp + fmt::format(
                  "\nset ylabel 'groove depth (mm)'\nset title 'the groove "
                  "depth (r = {:.2f} with a(x))'\nplot "
                  "'friction_along_track.csv' skip 1 using 1:3 with lines lw 2 "
                  "lc rgb '#555555' notitle\nunset multiplot\nunset output\n",
                  a.correlation_depth);
}

}  // namespace

FigureSet WriteDiagnosis(const std::string& dir,
                         const std::string& name,
                         const fusion::Diagnosis& d,
                         bool figures,
                         const FigureFormats& formats) {
  EnsureDirectory(dir);
  for (const auto& [file, text] : fusion::DiagnosisFiles(name, d)) {
    WriteTextAtomically((fs::path(dir) / file).string(), text);
  }
  if (!figures || !PlotterAvailable(nullptr)) return {};
  std::string gp;
  std::vector<std::string> terms;
  if (formats.png) terms.emplace_back("png");
  if (formats.svg) terms.emplace_back("svg");
  for (const std::string& ext : terms) {
    gp += internal::Terminal(ext, 1);
    gp += fmt::format(
        "set output 'diagnosis_residual_map.{0}'\nset datafile separator "
        "','\nset grid\nset xlabel 'x (mm)'\nset ylabel 'mean |Q_measured - "
        "Q_model| (N)'\nset key below\nset title '{1}: residual along the "
        "stroke before and after the named effects ({2})' noenhanced\nplot "
        "'residual_map_before.csv' skip 1 using 1:2 with lines lw 2 title "
        "'before, forward', '' skip 1 using 1:3 with lines lw 2 title "
        "'before, reverse', 'residual_map_after.csv' skip 1 using 1:2 with "
        "lines dt 2 title 'after, forward', '' skip 1 using 1:3 with lines "
        "dt 2 title 'after, reverse'\nunset output\n",
        ext,
        name,
        d.named.empty() ? std::string("none named")
                        : fmt::format("{}", fmt::join(d.named, ", ")));
    // The residual split by the direction of sliding at the same x.
    gp += fmt::format(
        "set output 'diagnosis_direction_split.{0}'\nset ylabel 'part of "
        "the signed residual (N)'\nset title '{1}: direction-odd (friction "
        "along the track) and direction-even parts (a scale of k, a "
        "pick-up)' noenhanced\nplot 'residual_map_before.csv' skip 1 using 1:6 "
        "with lines lw 2 title 'odd, before', '' skip 1 using 1:7 with lines "
        "lw 2 title 'even, before', 'residual_map_after.csv' skip 1 using "
        "1:6 with lines dt 2 title 'odd, after', '' skip 1 using 1:7 with "
        "lines dt 2 title 'even, after'\nunset output\n",
        ext,
        name);
    if (!d.along_track.empty()) gp += AlongTrackFigure(ext, name, d);
  }
  WriteTextAtomically(FigureDataPath(dir, "diagnosis.gp"), gp);
  FigureSet shown;
  if (terms.empty() || !RunGnuplotScript(dir, "diagnosis.gp")) return shown;
  const std::pair<const char*, const char*> drawn[] = {
      {"diagnosis_residual_map", "residual map before and after"},
      {"diagnosis_direction_split", "the residual split by direction"},
      {"diagnosis_friction_along_track", "friction along the track"}};
  for (const auto& [file, title] : drawn) {
    const std::string path =
        (fs::path(dir) / file).string() + "." + terms.front();
    if (!fs::exists(path)) continue;
    shown.shown.push_back(path);
    shown.titles.push_back(fmt::format("{}: diagnosis, {}", name, title));
  }
  return shown;
}

}  // namespace wearscar::report
