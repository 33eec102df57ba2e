#pragma once
// A specimen's page of an audit's report, <out>/<specimen>/report.html:
// its verdict, files, assumptions, numbers, warnings, figures (the image
// files of its folder, loaded as they near the view), its loop viewer
// (the specimen's loop_viewer.json embedded: the page works from file://)
// and provenance, with links to the index and the specimens beside it.

#include <string>

#include "wearscar/report/html_report.h"

namespace wearscar::report::internal {

// Links relative to the page ("" for none).
struct SpecimenLinks {
  std::string index;
  std::string previous, previous_name;
  std::string next, next_name;
};

std::string RenderSpecimenPage(const ReportSection& s,
                               const std::string& page_dir,
                               const SpecimenLinks& links);

// The page written to `path` (temporary name, then rename); OutputError
// when it cannot be written.
void WriteSpecimenPage(const ReportSection& s,
                       const std::string& path,
                       const SpecimenLinks& links);

}  // namespace wearscar::report::internal
