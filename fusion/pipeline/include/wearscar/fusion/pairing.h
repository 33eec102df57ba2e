#pragma once

#include <string>
#include <vector>

namespace wearscar::fusion {

// One specimen of a batch: its force export and, optionally, its scan.
struct Specimen {
  // Unique in the batch: the file name without role words ("oak_30N_run01"),
  // prefixed by its folder when two folders hold the same ("run1/oak_01").
  std::string name;
  std::string force;
  std::string scan;   // empty: force-only analysis
  std::string error;  // a pairing problem: reported as the specimen's failure
  // Why there is no scan (empty when there is one): "no scan in its
  // folder", "no scan's name matches (scans here: a.vk4)", ...
  std::string no_scan;
  // Other specimens of the batch have a scan: this one's missing scan is a
  // warning in the summary, the table and the report.
  bool scan_expected = false;

  // Factors a manifest's extra columns give (column name, value), in the
  // manifest's order: "load" -> "30 N".
  std::vector<std::pair<std::string, std::string>> factors;

  // "force + scan" or "force only (no scan: <why>)": what the audit's line
  // and the summary's pairing column say.
  std::string Pairing() const;
  // What an audit warns of its pairing where scan_expected ("no scan
  // paired, although other specimens of the batch have one (<why>); ..."),
  // else "".
  std::string PairingWarning() const;
};

// The words that say which role a file plays, ignored when names are
// compared (with the separators _ - . and space, and case).
const std::vector<std::string>& ForceRoleWords();  // force, friction, cof, ...
const std::vector<std::string>& ScanRoleWords();   // scan, height, topo, ...

// A name pattern with named groups, "(?<species>[BS])_(?<load>\\d+N)": the
// pattern std::regex reads (the names taken out, each group still
// capturing) and the names by group number (1-based; "" for an unnamed
// group). A pattern without names is itself.
struct NamedPattern {
  std::string regex;
  std::vector<std::string> names;  // names[i]: the name of group i + 1
  bool HasNames() const;
};
NamedPattern ParseNamedPattern(const std::string& pattern);

// A specimen name from a file name: the stem without its role words and
// their separators: "data/B-RT-R.force.csv" -> "B-RT-R",
// "oak_30N_run01_height.csv" -> "oak_30N_run01"; the stem itself when it
// holds nothing but role words.
std::string SpecimenName(const std::string& path);

// Pairs the force files of a folder with their scans.
//  - A file's role: a binary height map by its content (the scan
//    registry); a text file by its name's role words (ScanRoleWords,
//    ForceRoleWords), else as a scan when a text height-map layout
//    recognises it (a Keyence VR CSV), else as a force record.
//  - Its key: the name's words without role words, in lower case
//    (replicates "B-RT-R_rep1_force" and "B-RT-R_rep2_force" stay two).
//  - Within a folder, files with one key are one specimen; a scan and a
//    force file left over pair when one's key extends the other's
//    ("oak_1" with "oak_1_20x_height") and neither has another such match,
//    else by `name_pattern`'s match in their names when they are the only
//    two left with it (named by it);
//    a sub-folder whose files are one force file and one scan that pair by
//    none of these is one specimen named after the folder.
//  - Ties (two files of one role and rank for a key, two equally good
//    matches) and leftovers are listed, never guessed: a scan without a
//    force file is a failed specimen saying why; a force file without a
//    scan is analysed alone, saying why (Specimen::no_scan).
//  - With `recursive`, sub-folders too; a name found in two folders is
//    prefixed with its folder relative to `dir`. Hidden folders and the
//    outputs of wearscar's analyses (a .wearscar-manifest written by
//    fuse, audit, ...; not `wearscar simulate`'s, which are inputs) are
//    not searched unless `output_folders`; each one skipped is added to
//    `skipped` as "path (why)".
std::vector<Specimen> PairFolder(const std::string& dir,
                                 const std::string& name_pattern,
                                 bool recursive = false,
                                 bool output_folders = false,
                                 std::vector<std::string>* skipped = nullptr);

// The pairing as a text table (specimen, force, scan, note), paths
// relative to `root`: what `wearscar audit --dry-run` prints.
std::string PairingTable(const std::vector<Specimen>& specimens,
                         const std::string& root);

}  // namespace wearscar::fusion
