#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <regex>
#include <thread>

#include "commands.h"
#include "common_options.h"
#include "diagnosis_output.h"
#include "figures.h"
#include "output.h"
#include "report.h"
#include "results.h"
#include "wearscar/scan/formats.h"

namespace wearscar::app {
namespace {

namespace fs = std::filesystem;

struct Specimen {
  std::string name;
  std::string force;
  std::string scan;                   // empty: force-only analysis
  int force_rank = 0, scan_rank = 0;  // pairing preference of the files
  std::string error;                  // pairing problem
};

struct AuditArgs {
  std::string input;
  std::string out = "audit";
  int jobs = 0;
  std::string shard;
  bool no_figures = false;
  bool diagnose = false;
  fusion::DiagnoseOptions diagnose_options;
  std::string name_regex = "[BS]-(RT|RL|TL)-[RTL]";
  CommonArgs common;
};

bool HasExtension(const fs::path& p, std::initializer_list<const char*> exts) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](char c) {
    return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  });
  return std::any_of(
      exts.begin(), exts.end(), [&](const char* x) { return e == x; });
}

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](char c) {
    return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  });
  return s;
}

// Pairs force files with scans in a folder: binary height maps by
// extension, text files by a "scan"/"height" or "force" word in the name;
// the specimen key is the name pattern's match, else the stem without its
// role suffix.
std::vector<Specimen> PairFolder(const std::string& dir,
                                 const std::string& pattern) {
  const std::regex re(pattern);
  std::map<std::string, Specimen> by_key;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file()) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  for (const fs::path& p : files) {
    const std::string file = p.filename().string();
    const std::string lower = Lower(file);
    // A binary height map by its content (the scan registry); ".dat" is a
    // Zygo map or a force export, told apart by the magic.
    const bool binary_scan = scan::BinaryScanFormatOf(p.string()) != nullptr;
    const bool text =
        !binary_scan && HasExtension(p, {".csv", ".txt", ".tsv", ".dat"});
    if (!binary_scan && !text) continue;
    const bool text_scan = text && (lower.find("scan") != std::string::npos ||
                                    lower.find("height") != std::string::npos ||
                                    lower.find("keyence") != std::string::npos);
    std::smatch m;
    const std::string key =
        std::regex_search(file, m, re) ? m.str(0) : SpecimenName(file);
    Specimen& s = by_key[key];
    s.name = key;
    const bool is_scan = binary_scan || text_scan;
    std::string& slot = is_scan ? s.scan : s.force;
    // Several candidates for one role: a binary scan beats a text export of
    // the same map, a file named "force" beats other text; a tie is an error.
    const int rank = is_scan
                         ? (binary_scan ? 2 : 1)
                         : (lower.find("force") != std::string::npos ? 2 : 1);
    int& slot_rank = is_scan ? s.scan_rank : s.force_rank;
    if (!slot.empty() && rank == slot_rank) {
      s.error = fmt::format("two {} files match '{}': {} and {}",
                            is_scan ? "scan" : "force",
                            key,
                            fs::path(slot).filename().string(),
                            file);
    }
    if (slot.empty() || rank >= slot_rank) {
      slot = p.string();
      slot_rank = rank;
    }
  }
  std::vector<Specimen> out;
  for (auto& [k, s] : by_key) {
    if (s.force.empty() && s.error.empty()) {
      s.error = fmt::format("no force file for the scan {}",
                            fs::path(s.scan).filename().string());
    }
    out.push_back(s);
  }
  return out;
}

// manifest.csv: a header naming specimen, force and scan (any order), paths
// relative to the manifest.
std::vector<Specimen> ReadManifest(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw UsageError(fmt::format("{}: cannot open the manifest", path));
  std::string line;
  std::getline(in, line);
  // RFC 4180: a quoted cell may hold commas and doubled quotes (a path
  // "C:\\tests\\beech, run 2\\B-RT-R.csv").
  auto split = [](const std::string& l) {
    std::vector<std::string> cells(1);
    bool quoted = false;
    for (size_t i = 0; i < l.size(); ++i) {
      const char c = l[i];
      if (quoted) {
        if (c == '"' && i + 1 < l.size() && l[i + 1] == '"') {
          cells.back() += '"';
          ++i;
        } else if (c == '"') {
          quoted = false;
        } else {
          cells.back() += c;
        }
      } else if (c == '"') {
        quoted = true;
      } else if (c == ',') {
        cells.emplace_back();
      } else if (c != '\r') {
        cells.back() += c;
      }
    }
    for (auto& c : cells) {
      c.erase(0, c.find_first_not_of(' '));
      c.erase(c.find_last_not_of(' ') + 1);
    }
    return cells;
  };
  const auto header = split(line);
  int is = -1, iforce = -1, iscan = -1;
  for (int i = 0; i < static_cast<int>(header.size()); ++i) {
    const std::string h = Lower(header[i]);
    if (h == "specimen" || h == "name") is = i;
    if (h == "force" || h == "force_file") iforce = i;
    if (h == "scan" || h == "scan_file") iscan = i;
  }
  if (iforce < 0) {
    throw UsageError(
        fmt::format("{}: line 1: found columns '{}'; expected a header with "
                    "specimen, force and (optional) scan",
                    path,
                    line));
  }
  const fs::path base = fs::path(path).parent_path();
  std::vector<Specimen> out;
  std::vector<int> lines;  // of each specimen, for the duplicate message
  int line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.find_first_not_of(" \r,") == std::string::npos) continue;
    const auto cells = split(line);
    Specimen s;
    auto cell = [&](int i) {
      return i >= 0 && i < static_cast<int>(cells.size()) ? cells[i] : "";
    };
    auto resolve = [&](const std::string& p) {
      return p.empty() ? p
                       : (fs::path(p).is_absolute() ? p : (base / p).string());
    };
    s.force = resolve(cell(iforce));
    s.scan = resolve(cell(iscan));
    s.name = cell(is).empty() ? SpecimenName(s.force) : cell(is);
    // A specimen's name is its folder under --out: one path component,
    // never "..", never hidden.
    const std::string bad = s.name.empty() ? "it is empty"
                            : s.name.find_first_of("/\\") != std::string::npos
                                ? "it holds a path separator"
                            : s.name[0] == '.' ? "it starts with a dot"
                                               : "";
    if (!bad.empty()) {
      throw UsageError(fmt::format(
          "{}: line {}: specimen name '{}' cannot be a folder under --out "
          "({}); expected a plain name such as B-RT-R",
          path,
          line_no,
          s.name,
          bad));
    }
    for (size_t j = 0; j < out.size(); ++j) {
      if (out[j].name == s.name) {
        throw UsageError(fmt::format(
            "{}: line {}: specimen '{}' appears twice (also on line {}); "
            "expected each name once (each has its own folder)",
            path,
            line_no,
            s.name,
            lines[j]));
      }
    }
    if (s.force.empty())
      s.error = fmt::format("{}: line {}: no force file", path, line_no);
    out.push_back(s);
    lines.push_back(line_no);
  }
  return out;
}

nlohmann::json Identity(const std::string& name) {
  static const std::regex re("([BS])-(RT|RL|TL)-([RTL])");
  std::smatch m;
  nlohmann::json j = {{"specimen", name}};
  if (std::regex_search(name, m, re)) {
    j["species"] = m.str(1) == "B" ? "beech" : "spruce";
    j["plane"] = m.str(2);
    j["direction"] = m.str(3);
  } else {
    j["species"] = j["plane"] = j["direction"] = "";
  }
  return j;
}

std::string CsvCell(const nlohmann::json& j) {
  if (j.is_array()) {  // a list of sentences: one cell, "; " between them
    std::string joined;
    for (const auto& item : j) {
      if (!item.is_string()) continue;
      joined += (joined.empty() ? "" : "; ") + item.get<std::string>();
    }
    return CsvCell(nlohmann::json(joined));
  }
  if (j.is_number()) {
    const double v = j.get<double>();
    return std::isfinite(v) ? fmt::format("{:.6g}", v) : "";
  }
  if (j.is_boolean()) return j.get<bool>() ? "true" : "false";
  if (j.is_string()) {
    std::string s = j.get<std::string>();
    if (s.find_first_of(",\"\n") != std::string::npos) {
      std::string q = "\"";
      for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
      return q + "\"";
    }
    return s;
  }
  return "";
}

nlohmann::json Dig(const nlohmann::json& j,
                   std::initializer_list<const char*> path) {
  const nlohmann::json* p = &j;
  for (const char* k : path) {
    if (!p->is_object() || !p->contains(k)) return nullptr;
    p = &(*p)[k];
  }
  return *p;
}

const std::vector<std::pair<std::string, std::vector<const char*>>>&
SummaryColumns() {
  static const std::vector<std::pair<std::string, std::vector<const char*>>>
      kColumns = {
          {"specimen", {"specimen"}},
          {"species", {"species"}},
          {"plane", {"plane"}},
          {"direction", {"direction"}},
          {"cycles", {"cycles"}},
          {"mu_hat_mean", {"comparison", "mu_hat_force", "mean"}},
          {"mu_hat_sd", {"comparison", "mu_hat_force", "sd"}},
          {"mu_hat_scan_mean", {"comparison", "mu_hat_scan", "mean"}},
          {"mu_hat_scan_sd", {"comparison", "mu_hat_scan", "sd"}},
          {"mu_mean", {"comparison", "mu_mean", "mean"}},
          {"mu_energy", {"comparison", "mu_energy", "mean"}},
          {"J", {"comparison", "J_force", "mean"}},
          {"J_noise_floor", {"comparison", "J_force_split", "noise_floor"}},
          {"J_excess", {"comparison", "J_force_split", "excess"}},
          {"J_scan", {"comparison", "J_scan", "mean"}},
          {"J_scan_excess", {"comparison", "J_scan_split", "excess"}},
          {"profile_correlation", {"comparison", "profile_correlation"}},
          {"amplitude_ratio", {"comparison", "amplitude_ratio"}},
          {"k_rms_difference", {"comparison", "k_rms_difference"}},
          {"track_mean_depth_mm", {"scan", "track", "mean_depth_mm"}},
          {"track_max_depth_mm", {"scan", "track", "max_depth_mm"}},
          {"track_width_mm", {"scan", "track", "width_mm"}},
          {"explained", {"verdict", "explained"}},
          {"verdict", {"verdict", "summary"}},
          {"warnings", {"warnings"}},
          {"diagnosis", {"diagnosis"}},
          {"error", {"error"}},
      };
  return kColumns;
}

void RunAudit(AuditArgs a) {
  FinaliseCommonOptions(&a.common);
  int shard_i = 1, shard_n = 1;
  if (!a.shard.empty()) {
    if (std::sscanf(a.shard.c_str(), "%d/%d", &shard_i, &shard_n) != 2 ||
        shard_n < 1 || shard_i < 1 || shard_i > shard_n) {
      throw UsageError(
          fmt::format("--shard '{}': expected i/n with 1 <= i <= n", a.shard));
    }
  }
  std::vector<Specimen> all;
  if (fs::is_directory(a.input)) {
    all = PairFolder(a.input, a.name_regex);
  } else if (fs::is_regular_file(a.input)) {
    all = ReadManifest(a.input);
  } else {
    throw UsageError(fmt::format("{}: no such folder or manifest", a.input));
  }
  std::vector<Specimen> mine;
  for (size_t i = 0; i < all.size(); ++i) {
    if (static_cast<int>(i % shard_n) == shard_i - 1) mine.push_back(all[i]);
  }
  if (mine.empty())
    throw UsageError(fmt::format("{}: no specimens found", a.input));
  EnsureDirectory(a.out);
  // One audit per folder at a time: two would interleave summary.csv and
  // the specimen folders.
  const OutputLock out_lock(a.out);
  const int jobs =
      a.jobs > 0 ? a.jobs : std::max(1u, std::thread::hardware_concurrency());
  std::vector<ReportSection> sections(mine.size());
  std::vector<SpecimenSeries> series(mine.size());
  std::atomic<size_t> next{0};
  std::atomic<long> done{0};
  std::atomic<bool> figures_missing{false};
  std::mutex progress_mutex;
  Progress progress(
      fmt::format("audit ({} specimens, {} jobs)", mine.size(), jobs),
      static_cast<long>(mine.size()));
  auto worker = [&] {
    for (size_t i; (i = next++) < mine.size();) {
      const Specimen& s = mine[i];
      ReportSection& sec = sections[i];
      sec.name = s.name;
      sec.row = Identity(s.name);
      const std::string final_dir = (fs::path(a.out) / s.name).string();
      try {
        // Each specimen's files appear together or not at all.
        StagedOutput stage(final_dir);
        const std::string& dir = stage.dir();
        if (!s.error.empty()) throw UsageError(s.error);
        const force::ForceRecord record =
            force::ReadForceFile(s.force, a.common.read_force);
        std::optional<scan::HeightMap> map;
        if (!s.scan.empty()) map = scan::ReadScan(s.scan, a.common.read_scan);
        const fusion::TestResult r =
            fusion::AnalyzeTest(record, std::move(map), a.common.fuse);
        WriteTestResults(dir, s.name, record, r, a.common.fuse);
        nlohmann::json row = ResultJson(s.name, record, r, a.common.fuse);
        row.update(Identity(s.name));
        row["scan_file"] = s.scan;
        sec.row = row;
        sec.flagged = !r.verdict.explained;
        series[i] = {s.name,
                     dir,
                     r.mismatch.mu_force_minus_mean.mean,
                     r.mismatch.mu_force_minus_mean.sd,
                     r.mismatch.mu_force_minus_energy.mean,
                     r.mismatch.mu_force_minus_energy.sd};
        if (!a.no_figures)
          sec.figures = DrawTestFigures(dir, s.name, r, a.common.fuse);
        if (a.diagnose) {
          // A diagnosis that cannot run is reported; the analysis stands.
          try {
            fusion::DiagnoseOptions dopt = a.diagnose_options;
            dopt.running_in_cycles = r.force.running_in.cycles;
            const fusion::Diagnosis d =
                DiagnoseTest(record, r, a.common.fuse, dopt);
            const std::string png =
                WriteDiagnosis(dir, s.name, d, !a.no_figures);
            sec.row["missing_effects"] = d.named;
            sec.row["diagnosis"] = d.message;
            if (!png.empty()) {
              sec.figures.png.push_back(png);
              sec.figures.titles.push_back(
                  s.name + ": diagnosis, residual map before and after");
            }
          } catch (const std::exception& e) {
            sec.row["diagnosis"] = std::string("not run: ") + e.what();
          }
        }
        if (!sec.figures.missing.empty()) {
          AddWarningToResult(dir, sec.figures.message);
          figures_missing = true;
        }
        stage.Commit();
        // The report and the batch figures read the files where they are
        // now.
        for (std::string& png : sec.figures.png) png = stage.Final(png);
        series[i].dir = final_dir;
      } catch (const std::exception& e) {
        sec.failed = true;
        sec.flagged = false;
        sec.row["error"] = e.what();
      }
      std::lock_guard<std::mutex> lock(progress_mutex);
      progress.Update(++done);
    }
  };
  std::vector<std::thread> threads;
  for (int t = 0; t < std::min<int>(jobs, static_cast<int>(mine.size())); ++t) {
    threads.emplace_back(worker);
  }
  for (auto& t : threads) t.join();
  progress.Finish();
  // Tables: shard 1 (or an unsharded run) writes the CSV header, so the
  // shards' summary.csv files concatenate into one table; summary.jsonl
  // concatenates as it is.
  std::string csv, jsonl;
  if (shard_i == 1) {
    for (size_t c = 0; c < SummaryColumns().size(); ++c) {
      csv += (c ? "," : "") + SummaryColumns()[c].first;
    }
    csv += "\n";
  }
  nlohmann::json array = nlohmann::json::array();
  int failed = 0, flagged = 0;
  for (const auto& sec : sections) {
    for (size_t c = 0; c < SummaryColumns().size(); ++c) {
      const auto& path = SummaryColumns()[c].second;
      nlohmann::json v = sec.row;
      for (const char* k : path)
        v = v.is_object() && v.contains(k) ? v[k] : nlohmann::json();
      csv += (c ? "," : "") + CsvCell(v);
    }
    csv += "\n";
    jsonl += sec.row.dump() + "\n";
    array.push_back(sec.row);
    failed += sec.failed;
    flagged += sec.flagged;
  }
  WriteTextAtomically((fs::path(a.out) / "summary.csv").string(), csv);
  WriteTextAtomically((fs::path(a.out) / "summary.jsonl").string(), jsonl);
  WriteTextAtomically((fs::path(a.out) / "summary.json").string(),
                      array.dump(2) + "\n");
  FigureSet batch;
  if (!a.no_figures) {
    std::vector<SpecimenSeries> ok;
    for (size_t i = 0; i < sections.size(); ++i) {
      if (!sections[i].failed) ok.push_back(series[i]);
    }
    batch = DrawAuditFigures(a.out, ok);
  }
  const std::string title =
      shard_n > 1
          ? fmt::format(
                "wearscar audit of {} (shard {}/{})", a.input, shard_i, shard_n)
          : fmt::format("wearscar audit of {}", a.input);
  WriteTextAtomically((fs::path(a.out) / "report.html").string(),
                      RenderReport(title, sections, batch));
  for (const auto& sec : sections) {
    if (sec.failed) {
      fmt::print(
          "  FAILED   {}: {}\n", sec.name, sec.row["error"].get<std::string>());
    } else {
      fmt::print(
          "  {:8} {}: mu-hat {:.4f}, J {:.3f} (noise floor {:.3f}){}\n",
          sec.flagged ? "FLAGGED" : "ok",
          sec.name,
          Dig(sec.row, {"comparison", "mu_hat_force", "mean"}).get<double>(),
          Dig(sec.row, {"comparison", "J_force", "mean"}).get<double>(),
          Dig(sec.row, {"comparison", "J_force_split", "noise_floor"})
              .get<double>(),
          sec.flagged ? " - " + sec.row["verdict"]["summary"].get<std::string>()
                      : "");
    }
  }
  fmt::print("{} specimens: {} explained, {} not explained, {} failed\n",
             sections.size(),
             sections.size() - flagged - failed,
             flagged,
             failed);
  fmt::print("report: {}\n",
             fs::absolute(fs::path(a.out) / "report.html").string());
  fmt::print("tables: {} and summary.json\n",
             (fs::path(a.out) / "summary.csv").string());
  if (!batch.message.empty())
    fmt::print(stderr, "wearscar: {}\n", batch.message);
  SetExitStatus(failed > 0        ? std::min(failed, 125)
                : figures_missing ? kExitFiguresMissing
                                  : 0);
}

}  // namespace

void AddAuditCommand(CLI::App& app) {
  auto args = std::make_shared<AuditArgs>();
  auto* cmd = app.add_subcommand(
      "audit",
      "Batch over specimens: pair each force file with its scan (by name or a "
      "manifest), "
      "analyse them in parallel, write a summary table, one folder per "
      "specimen and "
      "report.html. Exit status: the number of specimens that failed.");
  cmd->add_option("input",
                  args->input,
                  "Folder of files, or manifest.csv (specimen,force,scan)")
      ->required();
  cmd->add_option("-o,--out", args->out, "Output folder")
      ->capture_default_str();
  cmd->add_option(
      "-j,--jobs", args->jobs, "Parallel specimens (default: all cores)");
  cmd->add_option(
      "--shard", args->shard, "Process shard i of n (1-based), e.g. 2/4");
  cmd->add_option("--name-pattern",
                  args->name_regex,
                  "Regular expression naming a specimen in file names")
      ->capture_default_str();
  cmd->add_flag("--no-figures", args->no_figures, "Skip the figures");
  cmd->add_flag(
      "--diagnose",
      args->diagnose,
      "Also diagnose each specimen (named missing effects, residual maps)");
  AddCommonOptions(cmd, &args->common, true);
  cmd->callback([args] { RunAudit(*args); });
}

}  // namespace wearscar::app
