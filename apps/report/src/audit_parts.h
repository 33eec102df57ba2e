#pragma once
// The parts of a sharded audit: each shard writes what the merge needs of
// its specimens into <out>/parts/shard-<i>-of-<n>.json; the merge reads
// every part present and writes the summaries, batch figures and report of
// them all.

#include <optional>
#include <string>
#include <vector>

#include "wearscar/report/audit.h"
#include "wearscar/report/figures.h"
#include "wearscar/report/html_report.h"

namespace wearscar::report::internal {

// "shard-2-of-3.json"
std::string PartName(int index, int count);

// `series[k]` belongs to `sections[k]` (ignored for a failed one).
void WritePart(const std::string& out,
               int index,
               int count,
               const std::vector<ReportSection>& sections,
               const std::vector<SpecimenSeries>& series);

struct Parts {
  std::vector<ReportSection> sections;   // by specimen name
  std::vector<SpecimenSeries> analysed;  // those not failed, same order
  std::vector<int> missing;              // shards with no part
  int count = 0;                         // shards of the audit
  std::vector<std::string> files;        // "parts/shard-1-of-3.json"
};

// An unsharded audit's record of its whole batch (parts/audit.json, the
// same form as a shard's part): a later run into the folder keeps the
// specimens it does not analyse again from it. ReadBatchRecord gives none
// when the folder holds no record; OutputError when it cannot be read.
constexpr const char* kBatchRecord = "audit.json";
void WriteBatchRecord(const std::string& out,
                      const std::vector<ReportSection>& sections,
                      const std::vector<SpecimenSeries>& series);
std::optional<Parts> ReadBatchRecord(const std::string& out);

// Every part in <out>/parts. Throws OutputError when there is none, when
// parts of audits with different shard counts are mixed, or when a part
// cannot be read.
Parts ReadParts(const std::string& out);

}  // namespace wearscar::report::internal
