#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

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

// A self-contained HTML page (images embedded as data URIs): the summary
// table with flagged and failed specimens highlighted, the batch figures,
// then a section per specimen.
std::string RenderReport(const std::string& title,
                         const std::vector<ReportSection>& sections,
                         const FigureSet& batch_figures);

// The page's part after the batch figures: a section per specimen, its
// figures embedded (most of the page's bytes and of its time to render).
std::string RenderSpecimenSections(const std::vector<ReportSection>& sections);

// RenderReport's page written to `path` (temporary name, then rename),
// its specimens' part already rendered (an audit renders it while gnuplot
// draws the batch figures). OutputError when it cannot be written.
void WriteReport(const std::string& path,
                 const std::string& title,
                 const std::vector<ReportSection>& sections,
                 const FigureSet& batch_figures,
                 const std::string& specimen_sections);

// Base64 of bytes (RFC 4648).
std::string Base64(const std::string& bytes);

}  // namespace wearscar::report
