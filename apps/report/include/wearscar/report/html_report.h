#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "wearscar/fusion/groups.h"
#include "wearscar/report/figures.h"

namespace wearscar::report {

// One specimen's section of the report.
struct ReportSection {
  std::string name;
  nlohmann::json row;  // the summary row (ResultJson subset) or the error
  bool failed = false;
  bool flagged = false;  // not explained by wear-scar interaction
  FigureSet figures;
  // The specimen's loop_viewer.json ("" none): the report's cycle slider.
  std::string viewer;
};

// The report of an audit, plain files that open from file:// (no
// server): <out>/report.html, the index (the summary table with each
// specimen's test conditions and files, sortable and filterable, and the
// batch figures), and a page per analysed specimen,
// <out>/<specimen>/report.html (its verdict, numbers, figures and loop
// viewer). Figures are the image files beside the pages, loaded as they
// near the view: the index stays light at any batch size. OutputError
// when a page cannot be written.
void WriteReport(const std::string& out,
                 const std::string& title,
                 const std::vector<ReportSection>& sections,
                 const FigureSet& batch_figures,
                 const std::vector<fusion::GroupComparison>& groups = {});

// One test's page, <dir>/report.html, as an audit writes each specimen's
// (its headline, verdict, numbers, warnings, the figures drawn beside it,
// its loop viewer when <dir>/loop_viewer.json is there): what `fuse -o DIR`
// writes. `result` is its result.json.
void WriteTestPage(const std::string& dir,
                   const std::string& name,
                   const nlohmann::json& result,
                   const FigureSet& figures);

// The index's HTML (WriteReport writes it to <out>/report.html).
std::string RenderIndex(
    const std::string& out,
    const std::string& title,
    const std::vector<ReportSection>& sections,
    const FigureSet& batch_figures,
    const std::vector<fusion::GroupComparison>& groups = {});

// Base64 of bytes (RFC 4648).
std::string Base64(const std::string& bytes);

}  // namespace wearscar::report
