// The products of a test: its tables and result.json from the analysis's
// result, formatted only (tables.cc, result_json.cc).

#include "wearscar/fusion/products.h"

#include <fmt/format.h>

#include <filesystem>
#include <future>

#include "tables.h"
#include "wearscar/fusion/error.h"
#include "wearscar/fusion/unit.h"

namespace wearscar::fusion {

bool ProductOptions::IsValid(std::string* why) const {
  for (int c : loop_cycles) {
    if (c < 0) {
      if (why) *why = "loop cycles are counted from 1";
      return false;
    }
  }
  return true;
}

std::vector<std::pair<std::string, std::string>> TestProducts::Files() const {
  std::vector<std::pair<std::string, std::string>> files;
  for (const auto& [name, table] : tables)
    files.emplace_back(name, table.ToCsv());
  files.insert(files.end(), documents.begin(), documents.end());
  files.emplace_back(result_name, ResultText());
  return files;
}

std::string TestProducts::ResultText() const { return result.dump(2) + "\n"; }

const Table* TestProducts::Find(std::string_view file) const {
  for (const auto& [name, table] : tables) {
    if (name == file) return &table;
  }
  return nullptr;
}

Provenance TestProvenance(const force::ForceRecord& record,
                          const TestResult& result) {
  std::vector<InputFile> inputs;
  namespace fs = std::filesystem;
  std::error_code ec;
  for (auto [role, path] : {std::pair<const char*, const std::string*>{
                                "force", &record.metadata.source},
                            {"scan", &result.scan_file}}) {
    if (path->empty() || !fs::is_regular_file(*path, ec)) continue;
    // The force file's checksum taken as it was read, when it was.
    const std::string& read_sum = record.metadata.sha256;
    if (std::string(role) == "force" && !read_sum.empty()) {
      inputs.push_back({role, *path, fs::file_size(*path, ec), read_sum});
    } else {
      inputs.push_back(DescribeInputFile(role, *path));
    }
  }
  return CurrentProvenance(std::move(inputs));
}

TestProducts MakeTestProducts(const std::string& name,
                              const force::ForceRecord& record,
                              const TestResult& r,
                              const FuseOptions& o,
                              const ProductOptions& p) {
  std::string why;
  if (!p.IsValid(&why)) throw FusionError("product options: " + why);
  const int n = static_cast<int>(r.force.cycles.cycles.size());
  for (int c : p.loop_cycles) {
    if (c >= n) {
      throw FusionError(fmt::format(
          "the loops of cycle {} were asked for, but the test has {} "
          "complete cycles; expected 1 to {}",
          c + 1,
          n,
          n));
    }
  }
  // The loop viewer's text (the largest product) beside the tables, where
  // the friction map holds the loops it draws.
  std::future<std::string> viewer;
  if (!r.units.Get<FrictionMap>().loop_x_mm.empty()) {
    viewer = std::async(o.parallel ? std::launch::async : std::launch::deferred,
                        [&r] { return internal::LoopViewerJson(r); });
  }
  TestProducts out;
  auto add = [&out](const char* file, Table t) {
    out.tables.emplace_back(file, std::move(t));
  };
  add("cycles.csv", internal::CycleTable(r));
  add("loops.csv", internal::LoopTable(record, r, p.loop_cycles));
  if (r.scan) {
    add("profiles.csv", internal::ProfileTable(*r.scan));
    add("centreline.csv", internal::CentrelineTable(r.scan->centreline));
  }
  // The analysis units' tables, in the registry's order.
  for (const auto& [unit, result] : UnitsThatRan(r)) {
    for (UnitTable& t : unit->TablesErased(result, record, r))
      out.tables.emplace_back(std::move(t.file), std::move(t.table));
  }
  if (viewer.valid())
    out.documents.emplace_back("loop_viewer.json", viewer.get());
  if (p.provenance) {
    const Provenance prov = TestProvenance(record, r);
    out.result = ResultJson(name, record, r, &prov);
  } else {
    out.result = ResultJson(name, record, r);
  }
  return out;
}

TestProducts MakeMapProducts(const std::string& file, const MapAnalysis& a) {
  TestProducts out;
  if (a.track) {
    out.tables.emplace_back("centreline.csv",
                            internal::CentrelineTable(a.centreline));
    Table x(TableColumns("cross_sections.csv"));
    for (size_t k = 0; k < a.sections.size(); ++k) {
      const scan::WearProfile& cs = a.sections[k];
      for (Eigen::Index i = 0; i < cs.s_mm.size(); ++i)
        x.rows.push_back({a.sections_mm[k], cs.s_mm[i], cs.height_mm[i]});
    }
    out.tables.emplace_back("cross_sections.csv", std::move(x));
  }
  const scan::HeightMap& map = a.levelled;
  out.result_name = "scan.json";
  out.result = {{"file", file},
                {"format", map.metadata.format},
                {"instrument", map.metadata.instrument},
                {"date", map.metadata.date},
                {"size_px", {map.cols(), map.rows()}},
                {"pitch_mm", {map.dx_mm, map.dy_mm}},
                {"valid_points", map.ValidCount()},
                {"level", LevelJson(a.level)},
                {"spikes_removed", a.spikes_removed},
                {"track", a.track ? TrackJson(*a.track) : nlohmann::json()},
                {"warnings", map.metadata.warnings}};
  if (!a.track) out.result["track_missing"] = a.no_track;
  return out;
}

}  // namespace wearscar::fusion
