#pragma once

// One test's folder: the tables and result.json of fusion::MakeTestProducts,
// the diagnosis's files and its figure, each written atomically.

#include <nlohmann/json.hpp>
#include <string>

#include "wearscar/force/force_record.h"
#include "wearscar/fusion/diagnose.h"
#include "wearscar/fusion/diagnosis_files.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/products.h"
#include "wearscar/report/figures.h"

namespace wearscar::report {

// Writes the tables and documents of one test (fusion::MakeTestProducts)
// into `dir`, each atomically, one table's text at a time on each of two
// threads (with o.parallel), the inputs' checksums taken beside the
// writing (those the record does not hold already); returns them, with
// result.json's contents in `result` but not yet written: the caller adds
// what it learns after the tables (figures asked for and not drawn, a
// scan not paired) and writes it once with WriteResult.
fusion::TestProducts WriteTestTables(const std::string& dir,
                                     const std::string& name,
                                     const force::ForceRecord& record,
                                     const fusion::TestResult& result,
                                     const fusion::FuseOptions& options,
                                     const fusion::ProductOptions& write = {});

// result.json (products.result_name) in `dir`, atomically.
void WriteResult(const std::string& dir, const fusion::TestProducts& products);

// WriteTestTables then WriteResult: a test's folder with nothing to add.
fusion::TestProducts WriteTestResults(const std::string& dir,
                                      const std::string& name,
                                      const force::ForceRecord& record,
                                      const fusion::TestResult& result,
                                      const fusion::FuseOptions& options,
                                      const fusion::ProductOptions& write = {});

// diagnosis.json, residual_map_before.csv / after.csv and (with figures)
// the diagnosis's figures (.svg / .png) in `dir`. Returns the figures to
// show with their titles (FigureSet::shown, titles; empty when none was
// drawn): the residual map, its split by direction, and friction along the
// track when named.
FigureSet WriteDiagnosis(const std::string& dir,
                         const std::string& name,
                         const fusion::Diagnosis& d,
                         bool figures,
                         const FigureFormats& formats = {});

}  // namespace wearscar::report
