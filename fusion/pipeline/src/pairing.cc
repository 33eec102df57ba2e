#include "wearscar/fusion/pairing.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <set>

#include "wearscar/force/layouts.h"
#include "wearscar/scan/formats.h"
#include "wearscar/support/compressed.h"
#include "wearscar/support/text.h"

namespace wearscar::fusion {

namespace fs = std::filesystem;

// The words that say a file's role, in English, German, French and
// Spanish, lower case (names are compared lower-cased, accented capitals
// too), with and without their accents; docs/formats.md lists them.
const std::vector<std::string>& ForceRoleWords() {
  static const std::vector<std::string> kWords = {"force",
                                                  "forces",
                                                  "friction",
                                                  "cof",
                                                  "tribo",
                                                  "tribometer",
                                                  // German
                                                  "kraft",
                                                  "kraefte",
                                                  "kräfte",
                                                  "reibung",
                                                  "reibkraft",
                                                  "reibwert",
                                                  // French ("force" above)
                                                  "frottement",
                                                  "frottements",
                                                  // Spanish
                                                  "fuerza",
                                                  "fuerzas",
                                                  "fricción",
                                                  "friccion",
                                                  "rozamiento"};
  return kWords;
}

const std::vector<std::string>& ScanRoleWords() {
  static const std::vector<std::string> kWords = {
      "scan",
      "height",
      "heights",
      "topo",
      "topography",
      "profile",
      "map",
      "surface",
      "keyence",
      // German
      "oberfläche",
      "oberflaeche",
      "profil",
      "höhe",
      "hoehe",
      "topographie",
      "topografie",
      // French ("surface", "profil", "topographie" above)
      "hauteur",
      "hauteurs",
      // Spanish
      "superficie",
      "perfil",
      "altura",
      "alturas",
      "topografía",
      "topografia"};
  return kWords;
}

std::string Specimen::Pairing() const {
  if (!scan.empty()) return force.empty() ? "scan only" : "force + scan";
  return no_scan.empty() ? "force only"
                         : "force only (no scan: " + no_scan + ")";
}

std::string Specimen::PairingWarning() const {
  if (!scan_expected) return "";
  return "no scan paired, although other specimens of the batch have one (" +
         no_scan + "); the verdict is the force side's alone";
}

namespace {

bool IsIn(const std::vector<std::string>& words, const std::string& w) {
  return std::find(words.begin(), words.end(), w) != words.end();
}

// Words that name the instrument a force export came from ("B-RT-R.rtec"
// beside "B-RT-R.force"): left out of the specimen's name, without making
// the file a force file any more than its content does.
bool NamesAnInstrument(const std::string& lower) {
  static const std::vector<std::string> kWords = {
      "rtec", "cetr", "umt", "bruker", "trb", "antonpaar"};
  return IsIn(kWords, lower);
}

// A file name's words: the stem split at _ - . and space.
struct NameWords {
  std::vector<std::string> key;  // lower case, role words left out
  std::string name;              // the stem without role words, as written
  bool says_force = false, says_scan = false;
};

NameWords SplitName(const std::string& stem) {
  NameWords out;
  char separator = 0;  // the one before the current word
  size_t i = 0;
  while (i <= stem.size()) {
    size_t j = stem.find_first_of("_-. ", i);
    if (j == std::string::npos) j = stem.size();
    const std::string word = stem.substr(i, j - i);
    const std::string lower = support::Lower(word);
    if (word.empty()) {
    } else if (IsIn(ForceRoleWords(), lower)) {
      out.says_force = true;
    } else if (IsIn(ScanRoleWords(), lower)) {
      out.says_scan = true;
    } else if (NamesAnInstrument(lower)) {
    } else {
      if (!out.name.empty() && separator != 0) out.name += separator;
      out.name += word;
      out.key.push_back(lower);
    }
    if (j < stem.size()) separator = stem[j];
    i = j + 1;
  }
  return out;
}

// A force export's extension, by the layouts of the registry.
bool HasForceExtension(const fs::path& p) {
  static const std::vector<std::string> extensions = force::ForceExtensions();
  const std::string e = support::Lower(p.extension().string());
  return std::find(extensions.begin(), extensions.end(), e) != extensions.end();
}

// A file found in a folder, with the role it plays for its specimen and how
// strongly (a binary scan beats a text export of the same map; a file named
// "force" beats other text).
struct Candidate {
  std::string key;                 // words joined; unique when it has none
  std::vector<std::string> words;  // for the prefix match
  std::string name, path;
  // The name pattern's match ("B-RT-R"; "" without one): files left
  // unpaired by their whole names pair by it.
  std::string pattern_name, pattern_key;
  bool is_scan = false;
  int rank = 0;
};

std::optional<Candidate> Classify(const fs::path& found, const std::regex& re) {
  // "oak_01.csv.gz" is named as "oak_01.csv" (and read expanded).
  const fs::path p(support::WithoutCompressionSuffix(found.string()));
  const std::string file = p.filename().string();
  // A binary height map by its content; ".dat" is a Zygo map or a force
  // export, told apart by the magic.
  const bool binary_scan = scan::BinaryScanFormatOf(found.string()) != nullptr;
  const bool text = !binary_scan && HasForceExtension(p);
  if (!binary_scan && !text) return std::nullopt;
  NameWords w = SplitName(p.stem().string());
  const std::string lower = support::Lower(file);
  const bool named_scan = w.says_scan ||
                          lower.find("scan") != std::string::npos ||
                          lower.find("height") != std::string::npos;
  Candidate c;
  c.path = found.string();
  c.is_scan = binary_scan || named_scan ||
              (!w.says_force &&
               scan::ScanFormatOf(c.path, scan::kDetectText) != nullptr);
  c.rank = c.is_scan ? (binary_scan ? 2 : 1) : (w.says_force ? 2 : 1);
  // The whole name less its role words is the specimen's, so that
  // replicates ("B-RT-R_rep1_force", "B-RT-R_rep2_force") stay apart.
  c.name = w.name.empty() ? p.stem().string() : w.name;
  c.words = std::move(w.key);
  std::smatch m;
  if (std::regex_search(file, m, re)) {
    c.pattern_name = m.str(0);
    c.pattern_key =
        fmt::format("{}", fmt::join(SplitName(c.pattern_name).key, "-"));
  }
  c.key = c.words.empty() ? "\x01" + found.filename().string()
                          : fmt::format("{}", fmt::join(c.words, "-"));
  return c;
}

struct Slot {
  Specimen s;
  std::vector<std::string> words;
  std::string pattern_name, pattern_key;
  int force_rank = 0, scan_rank = 0;
  bool ForceOnly() const {
    return s.error.empty() && !s.force.empty() && s.scan.empty();
  }
  bool ScanOnly() const {
    return s.error.empty() && s.force.empty() && !s.scan.empty();
  }
};

// File names, at most five and how many more.
std::string FileList(const std::vector<std::string>& paths) {
  std::vector<std::string> names;
  for (size_t i = 0; i < paths.size() && i < 5; ++i)
    names.push_back(fs::path(paths[i]).filename().string());
  std::string list = fmt::format("{}", fmt::join(names, ", "));
  if (paths.size() > 5) list += fmt::format(" and {} more", paths.size() - 5);
  return list;
}

// Files with one key are one specimen; two of one role and rank are a tie.
std::vector<Slot> GroupByKey(std::vector<fs::path> files,
                             const std::regex& re) {
  std::sort(files.begin(), files.end());
  std::map<std::string, Slot> by_key;
  for (const fs::path& p : files) {
    const std::optional<Candidate> c = Classify(p, re);
    if (!c) continue;
    Slot& slot = by_key[c->key];
    slot.words = c->words;
    slot.pattern_name = c->pattern_name;
    slot.pattern_key = c->pattern_key;
    std::string& role = c->is_scan ? slot.s.scan : slot.s.force;
    int& role_rank = c->is_scan ? slot.scan_rank : slot.force_rank;
    if (!c->is_scan || slot.s.name.empty()) slot.s.name = c->name;
    if (!role.empty() && c->rank == role_rank) {
      slot.s.error = fmt::format(
          "two {} files match '{}': {} and {}; expected one (rename one, or "
          "use a manifest)",
          c->is_scan ? "scan" : "force",
          c->name,
          fs::path(role).filename().string(),
          p.filename().string());
    }
    if (role.empty() || c->rank >= role_rank) {
      role = c->path;
      role_rank = c->rank;
    }
  }
  std::vector<Slot> out;
  for (auto& [key, slot] : by_key) out.push_back(std::move(slot));
  return out;
}

// A force file and a scan left over pair by the name pattern's match
// ("run07_B-RT-R_force.csv" with "B-RT-R_height.csv") when they are the
// only two left with it, named by it.
void PairByPattern(std::vector<Slot>* slots) {
  std::map<std::string, std::vector<size_t>> forces, scans;
  for (size_t i = 0; i < slots->size(); ++i) {
    const Slot& s = (*slots)[i];
    if (s.pattern_key.empty()) continue;
    if (s.ForceOnly()) forces[s.pattern_key].push_back(i);
    if (s.ScanOnly()) scans[s.pattern_key].push_back(i);
  }
  std::vector<bool> absorbed(slots->size(), false);
  for (const auto& [key, f] : forces) {
    const auto found = scans.find(key);
    if (f.size() != 1 || found == scans.end() || found->second.size() != 1)
      continue;
    Slot& force = (*slots)[f[0]];
    force.s.scan = (*slots)[found->second[0]].s.scan;
    force.s.name = force.pattern_name;
    absorbed[found->second[0]] = true;
  }
  std::vector<Slot> kept;
  for (size_t i = 0; i < slots->size(); ++i) {
    if (!absorbed[i]) kept.push_back(std::move((*slots)[i]));
  }
  *slots = std::move(kept);
}

// One key extends the other ("oak-1" and "oak-1-20x").
bool Extends(const std::vector<std::string>& a,
             const std::vector<std::string>& b) {
  const size_t n = std::min(a.size(), b.size());
  return n > 0 && std::equal(a.begin(), a.begin() + n, b.begin());
}

// A scan and a force file left over pair when one's key extends the
// other's and neither has another such match; ties are said.
void PairByLongerName(std::vector<Slot>* slots) {
  std::vector<Slot>& v = *slots;
  std::vector<std::vector<size_t>> match(v.size());
  for (size_t i = 0; i < v.size(); ++i) {
    for (size_t j = 0; j < v.size(); ++j) {
      if (v[i].ForceOnly() && v[j].ScanOnly() &&
          Extends(v[i].words, v[j].words))
        match[i].push_back(j), match[j].push_back(i);
    }
  }
  std::vector<bool> absorbed(v.size(), false);
  for (size_t i = 0; i < v.size(); ++i) {
    if (!v[i].ForceOnly() || match[i].empty()) continue;
    const size_t j = match[i][0];
    if (match[i].size() == 1 && match[j].size() == 1) {
      v[i].s.scan = v[j].s.scan;
      absorbed[j] = true;
      continue;
    }
    std::vector<std::string> scans;
    for (size_t k : match[i]) scans.push_back(v[k].s.scan);
    v[i].s.no_scan = match[i].size() > 1
                         ? "its name matches " + std::to_string(scans.size()) +
                               " scans equally: " + FileList(scans)
                         : "the scan " + FileList(scans) +
                               " matches other force files as well";
  }
  for (size_t j = 0; j < v.size(); ++j) {
    if (!v[j].ScanOnly() || match[j].empty() || absorbed[j]) continue;
    const size_t i = match[j][0];
    std::vector<std::string> others;
    for (size_t k : match[j].size() > 1 ? match[j] : match[i])
      others.push_back(match[j].size() > 1 ? v[k].s.force : v[k].s.scan);
    v[j].s.error = match[j].size() > 1
                       ? fmt::format(
                             "the scan {} matches {} force files equally ({}); "
                             "expected one (rename, or use a manifest)",
                             FileList({v[j].s.scan}),
                             others.size(),
                             FileList(others))
                       : fmt::format(
                             "the scans {} match the force file {} equally; "
                             "expected one (rename, or use a manifest)",
                             FileList(others),
                             FileList({v[i].s.force}));
  }
  std::vector<Slot> kept;
  for (size_t i = 0; i < v.size(); ++i) {
    if (!absorbed[i]) kept.push_back(std::move(v[i]));
  }
  v = std::move(kept);
}

// A sub-folder whose files are one force file and one scan that did not
// pair by name (lab/B-RT-R/test.csv with lab/B-RT-R/surface.zon) is one
// specimen named after the folder.
void PairByFolder(const fs::path& folder, std::vector<Slot>* slots) {
  if (slots->size() != 2) return;
  Slot& a = (*slots)[0];
  Slot& b = (*slots)[1];
  if (!((a.ForceOnly() && b.ScanOnly()) || (a.ScanOnly() && b.ForceOnly())))
    return;
  Slot s;
  s.s.name = folder.filename().string();
  s.s.force = a.ForceOnly() ? a.s.force : b.s.force;
  s.s.scan = a.ScanOnly() ? a.s.scan : b.s.scan;
  *slots = {s};
}

// What is said of the files left without a partner: the unpaired files
// of the other role in the folder, which a rename or a manifest would pair.
void SayWhyUnpaired(std::vector<Slot>* slots) {
  std::vector<std::string> lone_scans, lone_forces;
  bool any_scan = false, any_force = false;
  for (const Slot& s : *slots) {
    any_scan = any_scan || !s.s.scan.empty();
    any_force = any_force || !s.s.force.empty();
    if (s.ScanOnly()) lone_scans.push_back(s.s.scan);
    if (s.ForceOnly()) lone_forces.push_back(s.s.force);
  }
  for (Slot& s : *slots) {
    if (s.ForceOnly() && s.s.no_scan.empty()) {
      s.s.no_scan = !lone_scans.empty()
                        ? "no scan's name matches (unpaired scans here: " +
                              FileList(lone_scans) + ")"
                    : any_scan ? "no scan of its name in its folder"
                               : "no scan in its folder";
    } else if (s.ScanOnly() && s.s.error.empty()) {
      s.s.error = fmt::format(
          "no force file for the scan {}: {}; expected a force file named "
          "like it (or a manifest)",
          fs::path(s.s.scan).filename().string(),
          !lone_forces.empty()
              ? "none of the unpaired force files here (" +
                    FileList(lone_forces) + ") matches its name"
          : any_force ? "no force file of its name in its folder"
                      : "no force file in its folder");
    }
  }
}

// Why a folder is not searched ("" when it is): hidden, or the output of
// a wearscar analysis (its manifest names a command other than simulate,
// whose folders hold inputs).
std::string WhySkipped(const fs::path& dir, bool output_folders) {
  if (dir.filename().string().rfind('.', 0) == 0) return "hidden";
  if (output_folders) return "";
  std::ifstream manifest(dir / ".wearscar-manifest");
  std::set<std::string> commands;
  std::string line;
  while (std::getline(manifest, line))
    commands.insert(line.substr(0, line.find('\t')));
  commands.erase("simulate");
  if (commands.empty()) return "";
  return fmt::format("written by wearscar {}", fmt::join(commands, ", "));
}

std::map<fs::path, std::vector<fs::path>> FilesByFolder(
    const std::string& dir,
    bool recursive,
    bool output_folders,
    std::vector<std::string>* skipped) {
  std::map<fs::path, std::vector<fs::path>> by_folder;
  by_folder[fs::path(dir)];
  if (recursive) {
    std::error_code ec;
    fs::recursive_directory_iterator it(
        dir, fs::directory_options::skip_permission_denied, ec);
    for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
      const std::string why =
          it->is_directory() ? WhySkipped(it->path(), output_folders) : "";
      if (!why.empty()) {
        it.disable_recursion_pending();
        if (skipped != nullptr && why != "hidden")
          skipped->push_back(fmt::format(
              "{} ({})",
              it->path().lexically_relative(dir).generic_string() + "/",
              why));
      } else if (it->is_regular_file()) {
        by_folder[it->path().parent_path()].push_back(it->path());
      }
    }
  } else {
    for (const auto& e : fs::directory_iterator(dir)) {
      if (e.is_regular_file()) by_folder[fs::path(dir)].push_back(e.path());
    }
  }
  return by_folder;
}

}  // namespace

bool NamedPattern::HasNames() const {
  for (const std::string& n : names)
    if (!n.empty()) return true;
  return false;
}

NamedPattern ParseNamedPattern(const std::string& pattern) {
  NamedPattern out;
  bool in_class = false;
  for (size_t i = 0; i < pattern.size(); ++i) {
    const char c = pattern[i];
    if (c == '\\') {  // an escaped character, whatever it is
      out.regex += c;
      if (i + 1 < pattern.size()) out.regex += pattern[++i];
      continue;
    }
    if (in_class) {
      in_class = c != ']';
      out.regex += c;
      continue;
    }
    if (c == '[') in_class = true;
    if (c == '(' && pattern.compare(i, 3, "(?<") == 0 &&
        i + 3 < pattern.size() && pattern[i + 3] != '=' &&
        pattern[i + 3] != '!') {
      const size_t end = pattern.find('>', i + 3);
      if (end != std::string::npos) {
        out.names.push_back(pattern.substr(i + 3, end - i - 3));
        out.regex += '(';
        i = end;
        continue;
      }
    }
    if (c == '(' && (i + 1 >= pattern.size() || pattern[i + 1] != '?'))
      out.names.emplace_back();
    out.regex += c;
  }
  return out;
}

std::string SpecimenName(const std::string& path) {
  const std::string stem =
      fs::path(support::WithoutCompressionSuffix(path)).stem().string();
  const NameWords w = SplitName(stem);
  return w.name.empty() ? stem : w.name;
}

std::vector<Specimen> PairFolder(const std::string& dir,
                                 const std::string& name_pattern,
                                 bool recursive,
                                 bool output_folders,
                                 std::vector<std::string>* skipped) {
  const std::regex re(ParseNamedPattern(name_pattern).regex);
  std::vector<std::pair<Specimen, fs::path>> found;
  for (auto& [folder, files] :
       FilesByFolder(dir, recursive, output_folders, skipped)) {
    std::vector<Slot> here = GroupByKey(files, re);
    PairByLongerName(&here);
    PairByPattern(&here);
    if (folder != fs::path(dir)) PairByFolder(folder, &here);
    SayWhyUnpaired(&here);
    for (Slot& s : here) found.emplace_back(std::move(s.s), folder);
  }
  // A name in two folders is prefixed with its folder.
  std::map<std::string, int> count;
  for (const auto& [s, folder] : found) ++count[s.name];
  const bool any_scan =
      std::any_of(found.begin(), found.end(), [](const auto& f) {
        return !f.first.scan.empty() && !f.first.force.empty();
      });
  std::vector<Specimen> out;
  for (auto& [s, folder] : found) {
    if (count[s.name] > 1 && folder != fs::path(dir)) {
      s.name = (folder.lexically_relative(dir) / s.name).generic_string();
    }
    s.scan_expected = any_scan && s.scan.empty() && !s.force.empty();
    out.push_back(std::move(s));
  }
  std::sort(out.begin(), out.end(), [](const Specimen& a, const Specimen& b) {
    return a.name < b.name;
  });
  return out;
}

std::string PairingTable(const std::vector<Specimen>& specimens,
                         const std::string& root) {
  auto shown = [&](const std::string& path) {
    if (path.empty()) return std::string("-");
    const fs::path rel = fs::path(path).lexically_relative(root);
    return rel.empty() || *rel.begin() == ".." ? path : rel.generic_string();
  };
  std::vector<std::vector<std::string>> rows = {
      {"specimen", "force", "scan", "note"}};
  for (const Specimen& s : specimens) {
    std::string note = !s.error.empty() ? "FAILED: " + s.error
                       : s.scan.empty() ? s.Pairing()
                                        : "";
    if (s.scan_expected) note = "warning: " + note;
    rows.push_back({s.name, shown(s.force), shown(s.scan), note});
  }
  size_t width[3] = {0, 0, 0};
  for (const auto& r : rows) {
    for (size_t c = 0; c < 3; ++c) width[c] = std::max(width[c], r[c].size());
  }
  std::string out;
  for (const auto& r : rows) {
    std::string line = fmt::format("{:<{}}  {:<{}}  {:<{}}  {}",
                                   r[0],
                                   width[0],
                                   r[1],
                                   width[1],
                                   r[2],
                                   width[2],
                                   r[3]);
    line.erase(line.find_last_not_of(' ') + 1);
    out += line + "\n";
  }
  return out;
}

}  // namespace wearscar::fusion
