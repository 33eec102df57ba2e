#include "audit_parts.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>

#include "wearscar/report/output_folder.h"

namespace wearscar::report::internal {
namespace {

namespace fs = std::filesystem;

double Number(const nlohmann::json& j) {
  return j.is_number() ? j.get<double>() : NAN;  // NaN was written as null
}

nlohmann::json StatisticJson(const fusion::Statistic& s) {
  return {{"mean", s.mean},
          {"sd", s.sd},
          {"count", s.count},
          {"low", s.low},
          {"high", s.high}};
}

fusion::Statistic StatisticOf(const nlohmann::json& j) {
  fusion::Statistic s;
  s.mean = Number(j.value("mean", nlohmann::json()));
  s.sd = Number(j.value("sd", nlohmann::json()));
  s.count = j.value("count", 0);
  s.low = Number(j.value("low", nlohmann::json()));
  s.high = Number(j.value("high", nlohmann::json()));
  return s;
}

// The columns of cycles.csv the batch figures draw.
const std::vector<std::string> kCycleColumns = {
    "cycle", "mu_hat_force", "J_force", "mu_energy_g"};

nlohmann::json SeriesJson(const SpecimenSeries& s) {
  nlohmann::json cycles = nlohmann::json::object();
  for (const std::string& c : kCycleColumns) {
    const int at = s.cycles.ColumnIndex(c);
    std::vector<double> v;
    if (at >= 0)
      for (const auto& row : s.cycles.rows) v.push_back(row[at]);
    cycles[c] = v;
  }
  return {{"cycles", cycles},
          {"diff_mean", StatisticJson(s.diff_mean)},
          {"diff_energy", StatisticJson(s.diff_energy)},
          {"mu_hat", StatisticJson(s.mu_hat)},
          {"wear_rate", s.wear_rate}};
}

SpecimenSeries SeriesOf(const std::string& name, const nlohmann::json& j) {
  SpecimenSeries s;
  s.name = name;
  s.cycles = fusion::Table(kCycleColumns);
  const nlohmann::json& cycles = j.at("cycles");
  const std::size_t n = cycles.at("cycle").size();
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<double> row;
    for (const std::string& c : kCycleColumns)
      row.push_back(i < cycles.at(c).size() ? Number(cycles.at(c)[i]) : NAN);
    s.cycles.rows.push_back(std::move(row));
  }
  s.diff_mean = StatisticOf(j.at("diff_mean"));
  s.diff_energy = StatisticOf(j.at("diff_energy"));
  s.mu_hat = StatisticOf(j.at("mu_hat"));
  s.wear_rate = Number(j.at("wear_rate"));
  return s;
}

}  // namespace

std::string PartName(int index, int count) {
  return fmt::format("shard-{}-of-{}.json", index, count);
}

namespace {

nlohmann::json SpecimensJson(const std::string& out,
                             const std::vector<ReportSection>& sections,
                             const std::vector<SpecimenSeries>& series) {
  nlohmann::json specimens = nlohmann::json::array();
  for (std::size_t k = 0; k < sections.size(); ++k) {
    const ReportSection& sec = sections[k];
    nlohmann::json shown = nlohmann::json::array();
    for (const std::string& f : sec.figures.shown)
      shown.push_back(fs::relative(f, out).string());
    nlohmann::json one = {
        {"name", sec.name},
        {"row", sec.row},
        {"failed", sec.failed},
        {"flagged", sec.flagged},
        {"viewer",
         sec.viewer.empty() ? std::string()
                            : fs::relative(sec.viewer, out).string()},
        {"figures", shown},
        {"titles", sec.figures.titles}};
    if (!sec.failed && k < series.size()) one["series"] = SeriesJson(series[k]);
    specimens.push_back(std::move(one));
  }
  return specimens;
}

using Entry = std::pair<ReportSection, std::optional<SpecimenSeries>>;

// The specimens of one part file, appended to `all`; OutputError naming
// the file when it cannot be read.
void ReadSpecimens(const std::string& out,
                   const fs::path& path,
                   const char* expected,
                   std::vector<Entry>* all) {
  std::ifstream in(path);
  nlohmann::json j;
  try {
    in >> j;
    for (const auto& s : j.at("specimens")) {
      ReportSection sec;
      sec.name = s.at("name").get<std::string>();
      sec.row = s.at("row");
      sec.failed = s.at("failed").get<bool>();
      sec.flagged = s.at("flagged").get<bool>();
      for (const auto& f : s.at("figures"))
        sec.figures.shown.push_back(
            (fs::path(out) / f.get<std::string>()).string());
      sec.figures.titles = s.at("titles").get<std::vector<std::string>>();
      const std::string viewer = s.value("viewer", std::string());
      if (!viewer.empty()) sec.viewer = (fs::path(out) / viewer).string();
      std::optional<SpecimenSeries> series;
      if (s.contains("series")) series = SeriesOf(sec.name, s["series"]);
      all->emplace_back(std::move(sec), std::move(series));
    }
  } catch (const std::exception& e) {
    throw OutputError(
        fmt::format("{}: {}; expected {}", path.string(), e.what(), expected));
  }
}

void Split(std::vector<Entry>* all, Parts* p) {
  for (auto& [sec, series] : *all) {
    if (series) p->analysed.push_back(std::move(*series));
    p->sections.push_back(std::move(sec));
  }
}

}  // namespace

void WritePart(const std::string& out,
               int index,
               int count,
               const std::vector<ReportSection>& sections,
               const std::vector<SpecimenSeries>& series) {
  const fs::path dir = fs::path(out) / "parts";
  EnsureDirectory(dir.string());
  WriteTextAtomically(
      (dir / PartName(index, count)).string(),
      nlohmann::json({{"shard", index},
                      {"of", count},
                      {"specimens", SpecimensJson(out, sections, series)}})
              .dump() +
          "\n");
}

void WriteBatchRecord(const std::string& out,
                      const std::vector<ReportSection>& sections,
                      const std::vector<SpecimenSeries>& series) {
  const fs::path dir = fs::path(out) / "parts";
  EnsureDirectory(dir.string());
  WriteTextAtomically(
      (dir / kBatchRecord).string(),
      nlohmann::json({{"specimens", SpecimensJson(out, sections, series)}})
              .dump() +
          "\n");
}

std::optional<Parts> ReadBatchRecord(const std::string& out) {
  const fs::path file = fs::path(out) / "parts" / kBatchRecord;
  std::error_code ec;
  if (!fs::exists(file, ec)) return std::nullopt;
  std::vector<Entry> all;
  ReadSpecimens(out, file, "the batch record wearscar audit wrote", &all);
  Parts p;
  p.files.push_back((fs::path("parts") / kBatchRecord).string());
  Split(&all, &p);
  return p;
}

Parts ReadParts(const std::string& out) {
  Parts p;
  const fs::path dir = fs::path(out) / "parts";
  std::map<int, fs::path> found;
  const std::regex name(R"(shard-(\d+)-of-(\d+)\.json)");
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    std::smatch m;
    const std::string file = e.path().filename().string();
    if (!std::regex_match(file, m, name)) continue;
    const int index = std::stoi(m[1]), count = std::stoi(m[2]);
    if (p.count != 0 && count != p.count) {
      throw OutputError(fmt::format(
          "{}: parts of audits split {} and {} ways; expected the parts of "
          "one audit (remove the older ones)",
          dir.string(),
          p.count,
          count));
    }
    p.count = count;
    found[index] = e.path();
  }
  if (found.empty()) {
    throw OutputError(fmt::format(
        "{}: no parts (shard-<i>-of-<n>.json); expected the output of "
        "`wearscar audit ... --shard i/n -o {}`",
        dir.string(),
        out));
  }
  for (int i = 1; i <= p.count; ++i)
    if (!found.count(i)) p.missing.push_back(i);
  std::vector<Entry> all;
  for (const auto& [index, path] : found) {
    ReadSpecimens(out, path, "a part written by wearscar audit --shard", &all);
    p.files.push_back((fs::path("parts") / path.filename()).string());
  }
  if (fs::exists(dir / "plan.json", ec))
    p.files.emplace_back("parts/plan.json");
  std::stable_sort(all.begin(), all.end(), [](const auto& a, const auto& b) {
    return a.first.name < b.first.name;
  });
  Split(&all, &p);
  return p;
}

}  // namespace wearscar::report::internal

namespace wearscar::report {

std::optional<ShardPlan> ReadShardPlan(const std::string& out) {
  const fs::path file = fs::path(out) / "parts" / "plan.json";
  std::error_code ec;
  if (!fs::exists(file, ec)) return std::nullopt;
  std::ifstream in(file);
  try {
    nlohmann::json j;
    in >> j;
    ShardPlan kept;
    kept.count = j.at("shards").get<int>();
    kept.first = j.at("first").get<long>();
    kept.step = j.at("step").get<long>();
    kept.by = j.at("by").get<std::string>();
    if (kept.count < 1 || kept.step < 1)
      throw std::out_of_range("shards and step must be positive");
    return kept;
  } catch (const std::exception& e) {
    throw OutputError(fmt::format(
        "{}: {}; expected the shard plan wearscar audit --shard wrote "
        "(remove it to start the split again)",
        file.string(),
        e.what()));
  }
}

void RecordShardPlan(const std::string& out, const ShardPlan& plan) {
  const fs::path dir = fs::path(out) / "parts";
  EnsureDirectory(dir.string());
  // Tasks starting at once write the same plan: the last rename wins.
  WriteTextAtomically((dir / "plan.json").string(),
                      nlohmann::json({{"shards", plan.count},
                                      {"first", plan.first},
                                      {"step", plan.step},
                                      {"by", plan.by}})
                              .dump() +
                          "\n");
}

}  // namespace wearscar::report
