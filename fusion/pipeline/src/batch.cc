#include "wearscar/fusion/batch.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <future>
#include <map>
#include <mutex>
#include <optional>
#include <regex>
#include <set>
#include <thread>

#include "wearscar/force/layouts.h"
#include "wearscar/fusion/error.h"
#include "wearscar/fusion/provenance.h"
#include "wearscar/scan/formats.h"
#include "wearscar/support/text.h"

namespace wearscar::fusion {
namespace {

namespace fs = std::filesystem;

// RFC 4180 cells of one line: a quoted cell may hold commas and doubled
// quotes (a path "C:\tests\beech, run 2\B-RT-R.csv"); cells trimmed.
std::vector<std::string> SplitCsvLine(const std::string& l) {
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
}

// A specimen's name is its folder under the output: one path component,
// never "..", never hidden. Returns why not, or "".
std::string NameProblem(const std::string& name) {
  return name.empty() ? "it is empty"
         : name.find_first_of("/\\") != std::string::npos
             ? "it holds a path separator"
         : name[0] == '.' ? "it starts with a dot"
                          : "";
}

struct ManifestColumns {
  int specimen = -1, force = -1, scan = -1;
  // Any other column: a factor of the test (load, lubricant, operator).
  std::vector<std::pair<int, std::string>> factors;
};

ManifestColumns FindManifestColumns(const std::string& path,
                                    const std::string& line) {
  ManifestColumns c;
  const auto header = SplitCsvLine(line);
  for (int i = 0; i < static_cast<int>(header.size()); ++i) {
    const std::string h = support::Lower(header[i]);
    if (h == "specimen" || h == "name") c.specimen = i;
    if (h == "force" || h == "force_file") c.force = i;
    if (h == "scan" || h == "scan_file") c.scan = i;
    if (h != "specimen" && h != "name" && h != "force" && h != "force_file" &&
        h != "scan" && h != "scan_file" && !header[i].empty())
      c.factors.emplace_back(i, header[i]);
  }
  if (c.force < 0) {
    throw FusionError(
        fmt::format("{}: line 1: found columns '{}'; expected a header with "
                    "specimen, force and (optional) scan",
                    path,
                    line));
  }
  return c;
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
  if (j.is_number_integer()) return fmt::format("{}", j.dump());
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

}  // namespace

bool BatchOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (jobs < 0) return fail("jobs must be >= 0");
  if (shard_count < 1 || shard_index < 1 || shard_index > shard_count)
    return fail("the shard must be i of n with 1 <= i <= n");
  try {
    const std::regex key(ParseNamedPattern(name_pattern).regex),
        identity(ParseNamedPattern(naming.pattern).regex);
  } catch (const std::regex_error& e) {
    return fail(std::string("the name pattern is not a regular expression: ") +
                e.what());
  }
  return true;
}

std::vector<Specimen> ReadManifest(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw FusionError(fmt::format("{}: cannot open the manifest", path));
  std::string line;
  std::getline(in, line);
  const ManifestColumns col = FindManifestColumns(path, line);
  const fs::path base = fs::path(path).parent_path();
  auto resolve = [&](const std::string& p) {
    return p.empty() ? p
                     : (fs::path(p).is_absolute() ? p : (base / p).string());
  };
  std::vector<Specimen> out;
  std::vector<int> lines;  // of each specimen, for the duplicate message
  for (int line_no = 2; std::getline(in, line); ++line_no) {
    if (line.find_first_not_of(" \r,") == std::string::npos) continue;
    const auto cells = SplitCsvLine(line);
    auto cell = [&](int i) {
      return i >= 0 && i < static_cast<int>(cells.size()) ? cells[i] : "";
    };
    Specimen s;
    s.force = resolve(cell(col.force));
    s.scan = resolve(cell(col.scan));
    for (const auto& [at, factor] : col.factors)
      s.factors.emplace_back(factor, cell(at));
    s.name =
        cell(col.specimen).empty() ? SpecimenName(s.force) : cell(col.specimen);
    if (const std::string bad = NameProblem(s.name); !bad.empty()) {
      throw FusionError(fmt::format(
          "{}: line {}: specimen name '{}' cannot be a folder under --out "
          "({}); expected a plain name such as B-RT-R",
          path,
          line_no,
          s.name,
          bad));
    }
    for (size_t j = 0; j < out.size(); ++j) {
      if (out[j].name != s.name) continue;
      throw FusionError(fmt::format(
          "{}: line {}: specimen '{}' appears twice (also on line {}); "
          "expected each name once (each has its own folder)",
          path,
          line_no,
          s.name,
          lines[j]));
    }
    if (s.force.empty())
      s.error = fmt::format("{}: line {}: no force file", path, line_no);
    out.push_back(s);
    lines.push_back(line_no);
  }
  return out;
}

namespace {

// The scan read and prepared; a scan that cannot be read is kept in
// `unreadable` (it fails the specimen, as a force file does, after the
// force file's own errors) and rethrown. One without a usable track is
// left out by AnalyzeTest with a warning.
ScanAnalysis ReadAndPrepareScan(const std::string& path,
                                const scan::ReadScanOptions& read_scan,
                                const FuseOptions& fuse,
                                std::exception_ptr* unreadable) {
  scan::HeightMap map;
  try {
    map = scan::ReadScan(path, read_scan);
  } catch (...) {
    *unreadable = std::current_exception();
    throw;
  }
  return PrepareScan(std::move(map), fuse);
}

}  // namespace

SpecimenAnalysis AnalyzeSpecimen(const Specimen& s,
                                 const force::ReadForceOptions& read_force,
                                 const scan::ReadScanOptions& read_scan,
                                 const FuseOptions& fuse) {
  if (!s.error.empty()) throw FusionError(s.error);
  // On the caller's thread alone (a batch whose workers fill the cores),
  // the force file's checksum for the provenance is taken as the reader
  // reads it, not by a second read of the file, and the scan is read where
  // AnalyzeTest asks for it. Otherwise a large force file is parsed on two
  // threads while a third takes the checksum of a regular file, where the
  // reader's set-up leaves a core idle (the provenance then has it,
  // TestProvenance), and then reads and prepares the scan: the parse's
  // last rows, the force record's checks and its cycles leave a core idle
  // after the checksum, and the scan needs nothing of the force record.
  std::optional<Sha256> hash;
  std::promise<std::string> sum;
  std::future<std::string> force_sum;
  force::ReadForceOptions read = read_force;
  std::error_code ec;
  const bool sum_aside =
      fuse.parallel && std::filesystem::is_regular_file(s.force, ec);
  if (fuse.parallel) {
    read.threads = std::max(read.threads, 2);
  } else {
    hash.emplace();
    read.on_bytes = [&hash](const char* bytes, std::size_t size) {
      hash->Update(bytes, size);
    };
  }
  auto take_sum = [&sum, path = s.force] {
    try {
      sum.set_value(Sha256OfFile(path));
    } catch (...) {
      sum.set_exception(std::current_exception());
    }
  };
  if (sum_aside) force_sum = sum.get_future();
  std::exception_ptr scan_unreadable;
  std::future<ScanAnalysis> prepared;
  std::future<void> sum_alone;
  if (!s.scan.empty()) {
    // (Deferred without the cores: run where AnalyzeTest asks for it.)
    prepared = std::async(
        fuse.parallel ? std::launch::async : std::launch::deferred,
        [&, sum_aside] {
          if (sum_aside) take_sum();
          return ReadAndPrepareScan(s.scan, read_scan, fuse, &scan_unreadable);
        });
  } else if (sum_aside) {
    sum_alone = std::async(std::launch::async, take_sum);
  }
  SpecimenAnalysis a{force::ReadForceFile(s.force, read), {}};
  if (hash) a.record.metadata.sha256 = hash->Hex();
  a.result = AnalyzeTest(a.record, std::move(prepared), s.scan, fuse);
  // (AnalyzeTest has waited for the scan.)
  if (scan_unreadable) std::rethrow_exception(scan_unreadable);
  if (force_sum.valid()) a.record.metadata.sha256 = force_sum.get();
  return a;
}

std::vector<Specimen> FindSpecimens(const std::string& input,
                                    const BatchOptions& options,
                                    std::vector<std::string>* skipped,
                                    std::vector<Specimen>* others) {
  std::vector<std::string> not_searched;
  std::string why;
  if (!options.IsValid(&why)) throw FusionError("batch options: " + why);
  std::vector<Specimen> all;
  if (fs::is_directory(input)) {
    all = PairFolder(input,
                     options.name_pattern,
                     options.recursive,
                     options.output_folders,
                     &not_searched);
  } else if (fs::is_regular_file(input)) {
    all = ReadManifest(input);
  } else {
    throw FusionError(fmt::format("{}: no such folder or manifest", input));
  }
  std::vector<Specimen> mine;
  for (size_t i = 0; i < all.size(); ++i) {
    if (static_cast<int>(i % options.shard_count) == options.shard_index - 1)
      mine.push_back(all[i]);
    else if (others != nullptr)
      others->push_back(all[i]);
  }
  if (skipped != nullptr) *skipped = not_searched;
  if (mine.empty() && all.empty() && fs::is_directory(input)) {
    std::string skipped_said;
    if (!not_searched.empty()) {
      std::vector<std::string> some(
          not_searched.begin(),
          not_searched.begin() +
              static_cast<long>(std::min<size_t>(not_searched.size(), 5)));
      skipped_said = fmt::format(
          "; skipped {} folder{}: {}{} (--include-output-folders searches "
          "them)",
          not_searched.size(),
          not_searched.size() > 1 ? "s" : "",
          fmt::join(some, ", "),
          not_searched.size() > 5 ? ", ..." : "");
    }
    throw FusionError(fmt::format(
        "{}: no specimens found: looked{} for force exports ({}) and scans "
        "({}), paired by the name pattern '{}' or by their names without "
        "role words (force, scan, height, ...){}; expected at least one "
        "force file (or give a manifest.csv)",
        input,
        options.recursive ? " in it and its sub-folders" : "",
        fmt::join(force::ForceExtensions(), ", "),
        scan::ScanExtensionList(),
        options.name_pattern,
        skipped_said));
  }
  // A shard of more shards than specimens has none (and writes an empty
  // part); an unsharded run with none found fails.
  if (mine.empty() && (all.empty() || options.shard_count == 1))
    throw FusionError(fmt::format("{}: no specimens found", input));
  return mine;
}

nlohmann::json SpecimenIdentity(const Specimen& specimen,
                                const BatchOptions& options) {
  const NamedPattern own = ParseNamedPattern(options.name_pattern);
  const NamedPattern pattern =
      own.HasNames() ? own : ParseNamedPattern(options.naming.pattern);
  const std::regex re(pattern.regex,
                      own.HasNames()
                          ? std::regex::ECMAScript
                          : std::regex::ECMAScript | std::regex::icase);
  nlohmann::json factors = nlohmann::json::object();
  for (const char* f : {"species", "plane", "direction"}) factors[f] = "";
  std::smatch m;
  if (std::regex_search(specimen.name, m, re)) {
    for (size_t g = 0; g < pattern.names.size() && g + 1 < m.size(); ++g) {
      if (pattern.names[g].empty()) continue;
      std::string value = m.str(g + 1);
      if (!own.HasNames() && pattern.names[g] != "species")
        value = support::Upper(value);
      factors[pattern.names[g]] = value;
    }
  }
  const auto material = options.naming.materials.find(
      support::Lower(factors["species"].get<std::string>()));
  if (material != options.naming.materials.end())
    factors["species"] = material->second;
  for (const auto& [name, value] : specimen.factors) factors[name] = value;
  nlohmann::json j = {{"specimen", specimen.name}};
  for (const char* f : {"species", "plane", "direction"}) j[f] = factors[f];
  j["factors"] = factors;
  return j;
}

namespace {
size_t Cores() { return std::max(1u, std::thread::hardware_concurrency()); }
}  // namespace

size_t SpecimenWorkers(size_t n, int jobs) {
  return std::min(n, jobs > 0 ? static_cast<size_t>(jobs) : Cores());
}

bool WorkersFillCores(size_t n, int jobs) {
  return SpecimenWorkers(n, jobs) >= Cores();
}

void ForEachSpecimen(size_t n,
                     int jobs,
                     const std::function<void(size_t)>& work,
                     const std::function<void(long)>& progress) {
  std::atomic<size_t> next{0};
  std::atomic<long> done{0};
  std::mutex progress_mutex;
  auto worker = [&] {
    for (size_t i; (i = next++) < n;) {
      work(i);
      std::lock_guard<std::mutex> lock(progress_mutex);
      progress(++done);
    }
  };
  std::vector<std::thread> threads;
  for (size_t t = 0; t < SpecimenWorkers(n, jobs); ++t)
    threads.emplace_back(worker);
  for (auto& t : threads) t.join();
}

namespace {

using Columns = std::vector<std::pair<std::string, std::vector<std::string>>>;

// name, name_low and name_high: a comparison's mean and 95% interval.
void AddInterval(Columns* c, const std::string& name, const std::string& key) {
  c->push_back({name, {"comparison", key, "mean"}});
  c->push_back({name + "_low", {"comparison", key, "interval95", "0"}});
  c->push_back({name + "_high", {"comparison", key, "interval95", "1"}});
}

Columns MakeSummaryColumns() {
  Columns c = {
      {"specimen", {"specimen"}},
      {"species", {"species"}},
      {"plane", {"plane"}},
      {"direction", {"direction"}},
      {"cycles", {"cycles"}},
      {"status", {"quote", "status"}},
      {"mu_to_quote", {"quote", "mu"}},
      {"mu_to_quote_low", {"quote", "interval95", "0"}},
      {"mu_to_quote_high", {"quote", "interval95", "1"}},
      {"mu_to_quote_k_from", {"quote", "k_from"}},
      {"no_mu_to_quote_because", {"quote", "reason"}},
      {"mu_hat_mean", {"comparison", "mu_hat_force", "mean"}},
      {"mu_hat_sd", {"comparison", "mu_hat_force", "sd"}},
      {"mu_hat_scan_mean", {"comparison", "mu_hat_scan", "mean"}},
      {"mu_hat_scan_sd", {"comparison", "mu_hat_scan", "sd"}},
      {"mu_hat_low", {"comparison", "mu_hat_force", "interval95", "0"}},
      {"mu_hat_high", {"comparison", "mu_hat_force", "interval95", "1"}},
      {"mu_hat_effective_cycles",
       {"comparison", "mu_hat_force", "effective_cycles"}},
      {"mu_hat_scan_low", {"comparison", "mu_hat_scan", "interval95", "0"}},
      {"mu_hat_scan_high", {"comparison", "mu_hat_scan", "interval95", "1"}}};
  AddInterval(&c, "mu_mean", "mu_mean");
  AddInterval(&c, "mu_energy", "mu_energy");
  AddInterval(&c, "mu_hat_minus_mu_mean", "mu_hat_minus_mu_mean");
  AddInterval(&c, "mu_hat_minus_mu_energy", "mu_hat_minus_mu_energy");
  const Columns rest = {
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
      {"wear_volume_mm3", {"wear", "volume_mm3"}},
      {"normal_load_N", {"wear", "normal_load_n"}},
      {"sliding_distance_m", {"wear", "sliding_distance_m"}},
      {"specific_wear_rate_mm3_per_N_m",
       {"wear", "specific_wear_rate_mm3_per_n_m"}},
      {"mu_spatial_sd", {"friction_map", "spatial_sd_corrected"}},
      {"mu_spatial_sd_noise_floor", {"friction_map", "spatial_sd_noise_floor"}},
      {"mu_spatial_sd_raw", {"friction_map", "spatial_sd_raw"}},
      {"explained", {"verdict", "explained"}},
      {"verdict", {"verdict", "summary"}},
      {"warnings", {"warnings"}},
      {"diagnosis", {"diagnosis"}},
      {"error", {"error"}},
      {"force_file", {"provenance", "inputs", "0", "path"}},
      {"force_bytes", {"provenance", "inputs", "0", "bytes"}},
      {"force_sha256", {"provenance", "inputs", "0", "sha256"}},
      {"scan_file", {"provenance", "inputs", "1", "path"}},
      {"scan_bytes", {"provenance", "inputs", "1", "bytes"}},
      {"scan_sha256", {"provenance", "inputs", "1", "sha256"}},
      {"pairing", {"pairing"}},
      {"assumptions", {"assumptions"}},
      {"wearscar_version", {"provenance", "wearscar_version"}},
      {"git_commit", {"provenance", "git_commit"}},
      {"date_utc", {"provenance", "date_utc"}}};
  c.insert(c.end(), rest.begin(), rest.end());
  return c;
}

}  // namespace

const std::vector<std::pair<std::string, std::vector<std::string>>>&
SummaryColumns() {
  static const Columns kColumns = MakeSummaryColumns();
  return kColumns;
}

std::vector<std::vector<std::string>> SharedInputWarnings(
    const std::vector<nlohmann::json>& rows) {
  // (role, sha256) -> the rows holding such an input.
  std::map<std::pair<std::string, std::string>, std::vector<size_t>> holders;
  for (size_t i = 0; i < rows.size(); ++i) {
    const nlohmann::json* inputs = rows[i].contains("provenance")
                                       ? &rows[i]["provenance"]["inputs"]
                                       : nullptr;
    if (inputs == nullptr || !inputs->is_array()) continue;
    for (const nlohmann::json& in : *inputs) {
      const std::string sha = in.value("sha256", "");
      if (!sha.empty()) holders[{in.value("role", ""), sha}].push_back(i);
    }
  }
  std::vector<std::vector<std::string>> out(rows.size());
  for (const auto& [key, at] : holders) {
    if (at.size() < 2) continue;
    for (size_t i : at) {
      std::vector<std::string> others;
      for (size_t j : at) {
        if (j != i) others.push_back(rows[j].value("specimen", "?"));
      }
      out[i].push_back(fmt::format(
          "the {} file is byte-identical to that of {} (SHA-256 {}...): a "
          "copied file or a mix-up; two tests never give the same bytes",
          key.first,
          fmt::join(others, ", "),
          key.second.substr(0, 12)));
    }
  }
  return out;
}

namespace {

// The SHA-256 of a file's first and last 64 KiB ("" where it cannot be
// read): files that differ there differ.
std::string EndsFingerprint(const std::string& path) {
  constexpr std::streamoff kSpan = 64 * 1024;
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) return "";
  Sha256 hash;
  std::vector<char> bytes(static_cast<size_t>(kSpan));
  for (const std::streamoff from :
       {std::streamoff{0}, std::max<std::streamoff>(0, size - kSpan)}) {
    in.seekg(from);
    in.read(bytes.data(), std::min(kSpan, size - from));
    hash.Update(bytes.data(), static_cast<size_t>(in.gcount()));
    in.clear();
  }
  return hash.Hex();
}

}  // namespace

std::map<std::string, std::vector<std::string>> SharedInputsBefore(
    const std::vector<Specimen>& mine,
    const std::vector<Specimen>& others,
    const std::vector<nlohmann::json>& earlier) {
  // Rows as SharedInputWarnings reads them: this run's first, then the
  // other shards', then the earlier ones kept.
  std::vector<nlohmann::json> rows;
  std::set<std::string> analysed;
  // (role, bytes) -> the inputs (row, its index) of that size.
  std::map<std::pair<std::string, std::uintmax_t>,
           std::vector<std::pair<size_t, size_t>>>
      sized;
  auto add = [&](const Specimen& s) {
    analysed.insert(s.name);
    nlohmann::json inputs = nlohmann::json::array();
    for (auto [role, path] :
         {std::pair<const char*, const std::string*>{"force", &s.force},
          {"scan", &s.scan}}) {
      std::error_code ec;
      if (path->empty() || !fs::is_regular_file(*path, ec)) continue;
      const std::uintmax_t bytes = fs::file_size(*path, ec);
      if (ec) continue;
      sized[{role, bytes}].push_back({rows.size(), inputs.size()});
      inputs.push_back({{"role", role}, {"path", *path}, {"sha256", ""}});
    }
    rows.push_back(
        {{"specimen", s.name}, {"provenance", {{"inputs", inputs}}}});
  };
  for (const Specimen& s : mine) add(s);
  for (const Specimen& s : others) add(s);
  for (const nlohmann::json& row : earlier) {
    if (!row.is_object() || analysed.count(row.value("specimen", ""))) continue;
    const nlohmann::json* inputs =
        row.contains("provenance") ? &row["provenance"]["inputs"] : nullptr;
    if (inputs == nullptr || !inputs->is_array()) continue;
    for (size_t k = 0; k < inputs->size(); ++k) {
      const nlohmann::json& in = (*inputs)[k];
      if (in.contains("bytes") && in["bytes"].is_number_unsigned())
        sized[{in.value("role", ""), in["bytes"].get<std::uintmax_t>()}]
            .push_back({rows.size(), k});
    }
    rows.push_back(row);
  }
  // A file is read whole only where another input of its role has its size
  // and, among this batch's files (a scanner's exports of one field all
  // have one size), its first and last 64 KiB; an earlier specimen's input
  // of that size is known by its SHA-256 alone.
  auto input = [&rows](const std::pair<size_t, size_t>& at) -> nlohmann::json& {
    return rows[at.first]["provenance"]["inputs"][at.second];
  };
  auto hash_whole = [&input](const std::pair<size_t, size_t>& at) {
    nlohmann::json& in = input(at);
    if (!in.value("sha256", "").empty()) return;
    try {
      in["sha256"] = Sha256OfFile(in.value("path", ""));
    } catch (const std::exception&) {  // its analysis will say why
    }
  };
  for (const auto& [key, at] : sized) {
    if (at.size() < 2) continue;
    const bool earlier_one = std::any_of(at.begin(), at.end(), [&](auto& a) {
      return !input(a).value("sha256", "").empty();
    });
    if (earlier_one) {
      for (const auto& a : at) hash_whole(a);
      continue;
    }
    std::map<std::string, std::vector<std::pair<size_t, size_t>>> ends;
    for (const auto& a : at)
      ends[EndsFingerprint(input(a).value("path", ""))].push_back(a);
    for (const auto& [print, same] : ends)
      if (!print.empty() && same.size() > 1)
        for (const auto& a : same) hash_whole(a);
  }
  const auto warnings = SharedInputWarnings(rows);
  std::map<std::string, std::vector<std::string>> out;
  for (size_t i = 0; i < mine.size(); ++i)
    if (!warnings[i].empty()) out[mine[i].name] = warnings[i];
  return out;
}

std::vector<std::string> ExtraFactors(const std::vector<nlohmann::json>& rows) {
  std::vector<std::string> names;
  for (const nlohmann::json& row : rows) {
    if (!row.contains("factors") || !row["factors"].is_object()) continue;
    for (const auto& [name, level] : row["factors"].items()) {
      if (name == "species" || name == "plane" || name == "direction") continue;
      if (std::find(names.begin(), names.end(), name) == names.end())
        names.push_back(name);
    }
  }
  return names;
}

std::string SummaryCsv(const std::vector<nlohmann::json>& rows, bool header) {
  std::string csv;
  // The lab's own factors after the paper's three (a name that is already
  // a column's gets "factor_" before it).
  Columns columns = SummaryColumns();
  auto at = columns.begin() + 4;
  for (const std::string& name : ExtraFactors(rows)) {
    const bool taken =
        std::any_of(columns.begin(), columns.end(), [&](const auto& c) {
          return c.first == name;
        });
    at = columns.insert(at,
                        {taken ? "factor_" + name : name, {"factors", name}}) +
         1;
  }
  if (header) {
    for (size_t c = 0; c < columns.size(); ++c) {
      csv += (c ? "," : "") + columns[c].first;
    }
    csv += "\n";
  }
  for (const nlohmann::json& row : rows) {
    for (size_t c = 0; c < columns.size(); ++c) {
      nlohmann::json v = row;
      for (const std::string& k : columns[c].second) {
        if (v.is_array()) {  // a path step into a list is its index
          const size_t i = std::strtoul(k.c_str(), nullptr, 10);
          v = i < v.size() ? v[i] : nlohmann::json();
        } else {
          v = v.is_object() && v.contains(k) ? v[k] : nlohmann::json();
        }
      }
      csv += (c ? "," : "") + CsvCell(v);
    }
    csv += "\n";
  }
  return csv;
}

}  // namespace wearscar::fusion
