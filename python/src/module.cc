// wearscar._wearscar: the library for Python. The keyword arguments of the
// functions in wearscar/__init__.py are the command line's options (same
// names with '_' for '-', same defaults, same checks and messages): they
// arrive here as an argument list and are parsed by the command line's own
// option code (apps/options/common_options.h, simulate_options.h). Files,
// figures and the audit's report are written by wearscar::report, as the
// command writes them.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "common_options.h"
#include "simulate_options.h"
#include "usage_error.h"
#include "wearscar/force/read_force.h"
#include "wearscar/fusion/batch.h"
#include "wearscar/fusion/error.h"
#include "wearscar/fusion/logging.h"
#include "wearscar/fusion/products.h"
#include "wearscar/fusion/provenance.h"
#include "wearscar/report/audit.h"
#include "wearscar/report/figures.h"
#include "wearscar/report/output_folder.h"
#include "wearscar/report/test_folder.h"
#include "wearscar/samples/virtual_tribometer.h"
#include "wearscar/scan/read_scan.h"

namespace py = pybind11;

namespace wearscar::python {
namespace {

namespace fs = std::filesystem;

// Keyword arguments that are not options of this function.
class UnknownOption : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Every "--name" of `args` is an option of `parser`; else the TypeError
// Python gives for a keyword a function does not take.
void CheckKeywords(CLI::App& parser,
                   const std::vector<std::string>& args,
                   const std::string& function) {
  for (const std::string& arg : args) {
    if (arg.rfind("--", 0) != 0 || parser.get_option_no_throw(arg)) continue;
    std::string keyword = arg.substr(2);
    std::replace(keyword.begin(), keyword.end(), '-', '_');
    throw UnknownOption(function + "() got an unexpected keyword argument '" +
                        keyword + "'");
  }
}

// Parses `args` (["--spring", "8.5", ...]) with the options of `groups`.
app::CommonArgs ParseOptions(const std::vector<std::string>& args,
                             unsigned groups,
                             const std::string& function) {
  CLI::App parser{"", "wearscar." + function};
  app::CommonArgs a;
  app::AddCommonOptions(&parser, &a, groups);
  CheckKeywords(parser, args, function);
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    parser.parse(reversed);
  } catch (const CLI::ExtrasError& e) {
    throw UnknownOption(function + ": " + e.what());
  } catch (const CLI::ParseError& e) {
    throw app::UsageError(function + ": " + e.what());
  }
  app::FinaliseCommonOptions(&a);
  return a;
}

// One analysed test: its products (result.json and the tables) and what
// its figures are drawn from.
struct TestOutput {
  std::string name;
  fusion::TestProducts products;
  std::shared_ptr<const fusion::TestResult> result;
  fusion::FuseOptions options;

  std::string SummaryJson() const { return products.result.dump(); }

  // (file name, columns, values as rows x columns) of every table.
  std::vector<
      std::tuple<std::string, std::vector<std::string>, Eigen::MatrixXd>>
  Tables() const {
    std::vector<
        std::tuple<std::string, std::vector<std::string>, Eigen::MatrixXd>>
        out;
    for (const auto& [file, table] : products.tables) {
      Eigen::MatrixXd values(table.rows.size(), table.columns.size());
      for (size_t r = 0; r < table.rows.size(); ++r) {
        for (size_t c = 0; c < table.columns.size(); ++c) {
          values(r, c) = c < table.rows[r].size()
                             ? table.rows[r][c]
                             : std::numeric_limits<double>::quiet_NaN();
        }
      }
      out.emplace_back(file, table.columns, std::move(values));
    }
    return out;
  }

  // The files `wearscar fuse` writes, each atomically (with `figures`, the
  // figures too), and why figures asked for were not drawn ("" when they
  // were or were not asked for).
  std::pair<std::vector<std::string>, std::string> Write(
      const std::string& dir, const std::string& figures) const {
    report::EnsureDirectory(dir);
    std::vector<std::string> written;
    for (const auto& [file, text] : products.Files()) {
      written.push_back((fs::path(dir) / file).string());
      report::WriteTextAtomically(written.back(), text);
    }
    if (figures.empty()) return {written, ""};
    report::FigureFormats formats;
    if (!report::FigureFormats::Parse(figures, &formats)) {
      throw app::UsageError(
          "write: figures: expected svg, png or svg,png; "
          "found '" +
          figures + "'");
    }
    const report::FigureSet f =
        report::DrawTestFigures(dir, name, *result, options, products, formats);
    if (!f.missing.empty()) report::AddWarningToResult(dir, f.message);
    written.insert(written.end(), f.files.begin(), f.files.end());
    return {written, f.message};
  }
};

// A force record from a path (read with the options) or given.
force::ForceRecord ForceOf(const py::object& force,
                           const app::CommonArgs& a,
                           std::string* path) {
  if (py::isinstance<py::str>(force)) {
    *path = force.cast<std::string>();
    py::gil_scoped_release release;
    return force::ReadForceFile(*path, a.read_force);
  }
  return force.cast<force::ForceRecord>();
}

std::optional<scan::HeightMap> ScanOf(const py::object& scan,
                                      const app::CommonArgs& a) {
  if (scan.is_none()) return std::nullopt;
  if (py::isinstance<py::str>(scan)) {
    const std::string path = scan.cast<std::string>();
    py::gil_scoped_release release;
    return scan::ReadScan(path, a.read_scan);
  }
  return scan.cast<scan::HeightMap>();
}

TestOutput Fuse(const py::object& force,
                const py::object& scan,
                const std::vector<std::string>& args,
                const std::string& name,
                const std::vector<std::string>& product_args) {
  app::CommonArgs a = ParseOptions(args, app::kFuseOptions, "fuse");
  fusion::ProductOptions products;
  {
    CLI::App parser{"", "wearscar.fuse"};
    int detail = 0;
    std::vector<int> loops;
    parser.add_option("--detail-cycle", detail)->check(CLI::PositiveNumber);
    parser.add_option("--loops", loops)->check(CLI::PositiveNumber);
    std::vector<std::string> reversed(product_args.rbegin(),
                                      product_args.rend());
    try {
      parser.parse(reversed);
    } catch (const CLI::ParseError& e) {
      throw app::UsageError(std::string("fuse: ") + e.what());
    }
    a.fuse.detail_cycle = detail - 1;  // from 1 outside, from 0 inside
    for (int c : loops) products.loop_cycles.push_back(c - 1);
  }
  std::string path;
  const force::ForceRecord record = ForceOf(force, a, &path);
  std::optional<scan::HeightMap> map = ScanOf(scan, a);
  py::gil_scoped_release release;
  TestOutput out;
  out.name = !name.empty()   ? name
             : !path.empty() ? fusion::SpecimenName(path)
                             : "test";
  out.result = std::make_shared<const fusion::TestResult>(
      fusion::AnalyzeTest(record, std::move(map), a.fuse));
  out.options = a.fuse;
  out.products =
      fusion::MakeTestProducts(out.name, record, *out.result, a.fuse, products);
  return out;
}

// One row of the batch table: the specimen's result.json with its
// identity, or its error (nothing written).
nlohmann::json AuditOne(const fusion::Specimen& s,
                        const app::CommonArgs& a,
                        const fusion::BatchOptions& batch) {
  nlohmann::json row = fusion::SpecimenIdentity(s.name, batch.naming);
  try {
    const fusion::SpecimenAnalysis an =
        fusion::AnalyzeSpecimen(s, a.read_force, a.read_scan, a.fuse);
    nlohmann::json full =
        fusion::MakeTestProducts(s.name, an.record, an.result, a.fuse).result;
    full.update(row);
    return full;
  } catch (const std::exception& e) {
    row["error"] = e.what();
    return row;
  }
}

// With `out`, what `wearscar audit` writes there (report::Audit); without,
// the rows alone.
std::string Audit(const std::string& input,
                  const std::vector<std::string>& args,
                  const std::string& name_pattern,
                  bool recursive,
                  int jobs,
                  const std::string& out,
                  const std::string& figures) {
  const app::CommonArgs a = ParseOptions(args, app::kFuseOptions, "audit");
  report::AuditOptions o;
  fusion::BatchOptions& batch = o.batch;
  if (!name_pattern.empty()) batch.name_pattern = name_pattern;
  batch.recursive = recursive;
  batch.jobs = jobs;
  py::gil_scoped_release release;
  const std::vector<fusion::Specimen> specimens =
      fusion::FindSpecimens(input, batch);
  std::vector<nlohmann::json> rows(specimens.size());
  if (out.empty()) {
    // As wearscar audit: as many workers as cores analyse each specimen on
    // their own thread.
    app::CommonArgs worker_args = a;
    if (fusion::WorkersFillCores(specimens.size(), batch.jobs))
      worker_args.fuse.parallel = false;
    fusion::ForEachSpecimen(
        specimens.size(),
        batch.jobs,
        [&](size_t i) { rows[i] = AuditOne(specimens[i], worker_args, batch); },
        [](long) {});
    return nlohmann::json(rows).dump();
  }
  o.read_force = a.read_force;
  o.read_scan = a.read_scan;
  o.fuse = a.fuse;
  o.figures = !figures.empty();
  if (o.figures && !report::FigureFormats::Parse(figures, &o.figure_formats)) {
    throw app::UsageError(
        "audit: figures: expected svg, png or svg,png; "
        "found '" +
        figures + "'");
  }
  const report::AuditResult r =
      report::Audit(specimens, out, "wearscar audit of " + input, o);
  for (size_t i = 0; i < rows.size(); ++i) rows[i] = r.specimens[i].row;
  return nlohmann::json(rows).dump();
}

struct Simulated {
  force::ForceRecord force;
  scan::HeightMap scan;
  std::string truth_json;
};

std::vector<Simulated> Simulate(const std::vector<std::string>& args) {
  CLI::App parser{"", "wearscar.simulate"};
  app::SimulateArgs s;
  app::AddSimulationOptions(&parser, &s);
  CheckKeywords(parser, args, "simulate");
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    parser.parse(reversed);
  } catch (const CLI::ExtrasError& e) {
    throw UnknownOption(std::string("simulate: ") + e.what());
  } catch (const CLI::ParseError& e) {
    throw app::UsageError(std::string("simulate: ") + e.what());
  }
  const std::vector<samples::SimulationOptions> cases = app::SimulationCases(s);
  py::gil_scoped_release release;
  std::vector<Simulated> out;
  for (const samples::SimulationOptions& o : cases) {
    samples::SimulatedTest t = samples::Simulate(o);
    std::string truth = samples::TruthJson(o, t).dump();
    out.push_back({std::move(t.record), std::move(t.scan), std::move(truth)});
  }
  return out;
}

py::dict ForceMetadata(const force::ForceRecord& r) {
  const auto& m = r.metadata;
  py::dict d;
  d["source"] = m.source;
  d["layout"] = m.layout;
  d["sampling_rate_hz"] = m.sampling_rate_hz;
  d["channels"] = m.channel_names;
  d["units"] = m.channel_units;
  d["warnings"] = m.warnings;
  return d;
}

py::dict MapMetadata(const scan::HeightMap& h) {
  const auto& m = h.metadata;
  py::dict d;
  d["source"] = m.source;
  d["format"] = m.format;
  d["instrument"] = m.instrument;
  d["date"] = m.date;
  d["warnings"] = m.warnings;
  return d;
}

void DefineRecords(py::module_& m) {
  py::class_<force::ForceRecord>(m,
                                 "ForceRecord",
                                 "A force record in mm, N and s: time_s, "
                                 "x_mm, q_n (friction force Q), p_n (normal "
                                 "force P, compression positive)")
      .def(py::init([](Eigen::VectorXd t,
                       Eigen::VectorXd x,
                       Eigen::VectorXd q,
                       Eigen::VectorXd p,
                       const std::string& source) {
             if (x.size() != t.size() || q.size() != t.size() ||
                 p.size() != t.size()) {
               throw app::UsageError(
                   "ForceRecord: time_s, x_mm, q_n and p_n must have one "
                   "length");
             }
             force::ForceRecord r;
             r.time_s = std::move(t);
             r.x_mm = std::move(x);
             r.tangential_n = std::move(q);
             r.normal_n = std::move(p);
             r.metadata.source = source;
             r.metadata.layout = "python";
             return r;
           }),
           py::arg("time_s"),
           py::arg("x_mm"),
           py::arg("q_n"),
           py::arg("p_n"),
           py::arg("source") = "python")
      .def_property_readonly(
          "time_s", [](const force::ForceRecord& r) { return r.time_s; })
      .def_property_readonly("x_mm",
                             [](const force::ForceRecord& r) { return r.x_mm; })
      .def_property_readonly(
          "q_n", [](const force::ForceRecord& r) { return r.tangential_n; })
      .def_property_readonly(
          "p_n", [](const force::ForceRecord& r) { return r.normal_n; })
      .def_property_readonly("metadata", &ForceMetadata)
      .def("__len__", [](const force::ForceRecord& r) { return r.size(); });
  py::class_<scan::HeightMap>(m,
                              "HeightMap",
                              "A height map in mm: height_mm (rows x cols, "
                              "NaN where not measured), pitch dx_mm, dy_mm")
      .def(py::init([](const Eigen::Array<float,
                                          Eigen::Dynamic,
                                          Eigen::Dynamic,
                                          Eigen::RowMajor>& h,
                       double dx,
                       double dy,
                       const std::string& source) {
             if (!(dx > 0) || !(dy > 0))
               throw app::UsageError("HeightMap: dx_mm and dy_mm must be > 0");
             scan::HeightMap map;
             map.height_mm = h;
             map.dx_mm = dx;
             map.dy_mm = dy;
             map.metadata.source = source;
             map.metadata.format = "python";
             scan::SyncValidity(&map);
             return map;
           }),
           py::arg("height_mm"),
           py::arg("dx_mm"),
           py::arg("dy_mm"),
           py::arg("source") = "python")
      .def_property_readonly("height_mm",
                             [](const scan::HeightMap& h) {
                               scan::HeightMap::Heights z = h.height_mm;
                               for (Eigen::Index i = 0; i < z.size(); ++i)
                                 if (!h.valid(i))
                                   z(i) =
                                       std::numeric_limits<float>::quiet_NaN();
                               return z;
                             })
      .def_readonly("dx_mm", &scan::HeightMap::dx_mm)
      .def_readonly("dy_mm", &scan::HeightMap::dy_mm)
      .def_property_readonly("shape",
                             [](const scan::HeightMap& h) {
                               return py::make_tuple(h.rows(), h.cols());
                             })
      .def_property_readonly("metadata", &MapMetadata);
}

void DefineFunctions(py::module_& m) {
  py::class_<TestOutput>(m, "_TestOutput")
      .def_readonly("name", &TestOutput::name)
      .def("summary_json", &TestOutput::SummaryJson)
      .def("tables", &TestOutput::Tables)
      .def("write",
           &TestOutput::Write,
           py::call_guard<py::gil_scoped_release>());
  py::class_<Simulated>(m, "_Simulated")
      .def_readonly("force", &Simulated::force)
      .def_readonly("scan", &Simulated::scan)
      .def_readonly("truth_json", &Simulated::truth_json);
  m.def("_read_force",
        [](const std::string& path, const std::vector<std::string>& args) {
          const app::CommonArgs a =
              ParseOptions(args, app::kForceFileOptions, "read_force");
          py::gil_scoped_release release;
          return force::ReadForceFile(path, a.read_force);
        });
  m.def("_read_scan",
        [](const std::string& path, const std::vector<std::string>& args) {
          const app::CommonArgs a =
              ParseOptions(args, app::kScanFileOptions, "read_scan");
          py::gil_scoped_release release;
          return scan::ReadScan(path, a.read_scan);
        });
  m.def("_fuse", &Fuse);
  m.def("_audit", &Audit);
  m.def("_simulate", &Simulate);
  m.def("version", [] { return std::string(fusion::Version()); });
  m.def("git_commit", [] { return std::string(fusion::GitCommit()); });
}

}  // namespace
}  // namespace wearscar::python

PYBIND11_MODULE(_wearscar, m) {
  using namespace wearscar;
  m.doc() = "wearscar's C++ library (use the wearscar package)";
  fusion::QuietSolverLogging();
  // Errors carry the command line's messages.
  static py::exception<force::ForceError> force_error(
      m, "ForceError", PyExc_ValueError);
  static py::exception<scan::ScanError> scan_error(
      m, "ScanError", PyExc_ValueError);
  static py::exception<fusion::FusionError> fusion_error(
      m, "FusionError", PyExc_ValueError);
  static py::exception<app::UsageError> option_error(
      m, "OptionError", PyExc_ValueError);
  static py::exception<report::OutputError> output_error(
      m, "OutputError", PyExc_OSError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const force::ForceError& e) {
      force_error(e.what());
    } catch (const scan::ScanError& e) {
      scan_error(e.what());
    } catch (const fusion::FusionError& e) {
      fusion_error(e.what());
    } catch (const app::UsageError& e) {
      option_error(e.what());
    } catch (const report::OutputError& e) {
      output_error(e.what());
    } catch (const python::UnknownOption& e) {
      PyErr_SetString(PyExc_TypeError, e.what());
    }
  });
  python::DefineRecords(m);
  python::DefineFunctions(m);
}
