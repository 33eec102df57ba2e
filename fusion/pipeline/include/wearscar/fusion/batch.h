#pragma once

#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "wearscar/force/read_force.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/pairing.h"
#include "wearscar/scan/read_scan.h"

namespace wearscar::fusion {

// What a specimen's name says of it: `pattern`'s groups are the material
// (looked up in `materials`), the plane and the direction. The defaults are
// the paper's names (B-RT-R: beech, radial-tangential plane, radial
// sliding).
// What a specimen's name says of its test conditions when the name
// pattern (BatchOptions::name_pattern) names no groups: the paper's
// naming, "B-RT-R" (species, plane, direction) and the same in words
// ("Buche_RT-R", "spruce-TL-L"), case aside; `materials` maps the species
// as written (lower case) to its name.
struct SpecimenNaming {
  std::string pattern =
      "(?<species>[BS]|beech|spruce|buche|fichte)[-_ ](?<plane>RT|RL|TL)[-_ ]"
      "(?<direction>[RTL])(?![a-z])";
  std::map<std::string, std::string> materials = {{"b", "beech"},
                                                  {"beech", "beech"},
                                                  {"buche", "beech"},
                                                  {"s", "spruce"},
                                                  {"spruce", "spruce"},
                                                  {"fichte", "spruce"}};
};

struct BatchOptions {
  // The part of a file name that names its specimen (regular expression);
  // files without it are keyed by their stem without a role suffix.
  std::string name_pattern = "[BS]-(RT|RL|TL)-[RTL]";
  SpecimenNaming naming;
  int jobs = 0;  // specimens analysed at once; 0 = one per core
  // This run processes specimens i, i + n, i + 2n, ... (1-based i of n).
  int shard_index = 1, shard_count = 1;
  // Search the folder's sub-folders too (not hidden ones, not folders
  // wearscar wrote).
  bool recursive = true;
  // Search the outputs of wearscar's analyses too (skipped by default).
  bool output_folders = false;

  bool IsValid(std::string* why) const;
};

// manifest.csv: a header naming specimen, force and (optional) scan in any
// order (RFC 4180 cells), paths relative to the manifest. Throws
// FusionError for a manifest that cannot be read, a name that cannot be a
// folder (empty, a path separator, a leading dot) or a name given twice.
std::vector<Specimen> ReadManifest(const std::string& path);

// The specimens of `input` (a folder or a manifest) this shard processes:
// none for a shard beyond the specimens' count. Throws FusionError when
// the input holds none.
// `skipped`, when given, receives the folders not searched ("path (why)",
// PairFolder); the error when none is found names them.
// `others`, when given, receives the batch's specimens the other shards
// process (none unsharded).
std::vector<Specimen> FindSpecimens(const std::string& input,
                                    const BatchOptions& options,
                                    std::vector<std::string>* skipped = nullptr,
                                    std::vector<Specimen>* others = nullptr);

// A specimen's files read and analysed.
struct SpecimenAnalysis {
  force::ForceRecord record;
  TestResult result;
};
// Throws the specimen's pairing error (FusionError), the readers' errors
// and the analysis's.
SpecimenAnalysis AnalyzeSpecimen(const Specimen& specimen,
                                 const force::ReadForceOptions& read_force,
                                 const scan::ReadScanOptions& read_scan,
                                 const FuseOptions& fuse);

// A specimen's identity: {"specimen", "species", "plane", "direction",
// "factors": {name: level}}. The factors are the named groups of
// options.name_pattern where it names any ("(?<load>\\d+N)"), else the
// default naming's (SpecimenNaming); a manifest's extra columns
// (Specimen::factors) add to them and win. Empty strings where nothing
// matches.
nlohmann::json SpecimenIdentity(const Specimen& specimen,
                                const BatchOptions& options);

// The threads ForEachSpecimen runs for n specimens: `jobs` (0 = one per
// core), at most n.
size_t SpecimenWorkers(size_t n, int jobs);
// Whether those workers keep every core busy: each specimen is then best
// analysed on its worker's thread alone (FuseOptions::parallel false).
bool WorkersFillCores(size_t n, int jobs);

// Runs work(i) for every i in [0, n) on `jobs` threads (0 = one per core);
// progress(done) is called after each, one call at a time.
void ForEachSpecimen(size_t n,
                     int jobs,
                     const std::function<void(size_t)>& work,
                     const std::function<void(long)>& progress);

// Inputs that specimens of one batch share: for each row (a specimen's
// result.json with "specimen"), a warning per input whose SHA-256 another
// specimen's input of the same role has too, naming those specimens (a
// copied file or a mix-up: two tests are never byte-identical). Rows
// without provenance (failed specimens) share nothing. One entry per row,
// empty where nothing is shared.
std::vector<std::vector<std::string>> SharedInputWarnings(
    const std::vector<nlohmann::json>& rows);
// The same warnings before any specimen is analysed, so that each one's
// result.json is written once with them: for each specimen of `mine` (by
// name) that shares an input with another of `mine`, of `others` (the
// batch's specimens of the other shards) or of `earlier` (rows of
// specimens an earlier run analysed that the batch keeps: their
// provenance's size and SHA-256; rows of specimens in `mine` or `others`
// are skipped). Only the files whose role and size another input has too
// are read for their SHA-256; a file that cannot be read shares nothing
// (its specimen's analysis says why).
std::map<std::string, std::vector<std::string>> SharedInputsBefore(
    const std::vector<Specimen>& mine,
    const std::vector<Specimen>& others,
    const std::vector<nlohmann::json>& earlier);

// The batch table: one row per specimen from its result.json (ResultJson
// with SpecimenIdentity, "error" when it failed), columns by path.
const std::vector<std::pair<std::string, std::vector<std::string>>>&
SummaryColumns();
// The factors some row names beyond species, plane and direction (a name
// pattern's named groups, a manifest's extra columns), in order of first
// appearance: summary.csv's columns after direction.
std::vector<std::string> ExtraFactors(const std::vector<nlohmann::json>& rows);
// summary.csv's text: the header (when asked; shards after the first leave
// it out so that their files concatenate) and one line per row.
std::string SummaryCsv(const std::vector<nlohmann::json>& rows, bool header);

}  // namespace wearscar::fusion
