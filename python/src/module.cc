// wearscar._wearscar: the library for Python. The keyword arguments of the
// functions in wearscar/__init__.py are the libraries' settings
// (fusion::TestSettingList, samples::SimulationSettingList: the command
// line's options, with '_' for '-', the same defaults, checks and
// messages); they arrive here as (name, text) pairs. Files, figures and the
// audit's report are written by wearscar::report, as the command writes
// them.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "wearscar/force/block_joiner.h"
#include "wearscar/force/follow.h"
#include "wearscar/force/read_force.h"
#include "wearscar/fusion/batch.h"
#include "wearscar/fusion/error.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/groups.h"
#include "wearscar/fusion/live.h"
#include "wearscar/fusion/logging.h"
#include "wearscar/fusion/products.h"
#include "wearscar/fusion/provenance.h"
#include "wearscar/fusion/settings.h"
#include "wearscar/report/audit.h"
#include "wearscar/report/figures.h"
#include "wearscar/report/output_folder.h"
#include "wearscar/report/specimen_folder.h"
#include "wearscar/samples/simulation_settings.h"
#include "wearscar/samples/virtual_tribometer.h"
#include "wearscar/scan/read_scan.h"

namespace py = pybind11;

namespace wearscar::python {

// A bad value of a keyword argument (Python's ValueError OptionError).
class OptionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A keyword argument a function does not take (Python's TypeError).
class UnknownOption : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace {

namespace fs = std::filesystem;

using Given = std::vector<std::pair<std::string, std::string>>;

// A setting's name as a Python keyword: '_' for '-'.
std::string Keyword(std::string name) {
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

// Every keyword of `given` is a setting of `list` in `sections`; else the
// TypeError Python gives for a keyword a function does not take, with the
// closest keywords it does take.
template <class Target>
void CheckKeywords(const std::vector<support::Setting<Target>>& list,
                   unsigned sections,
                   const Given& given,
                   const std::string& function) {
  std::vector<std::string> keywords;
  for (const auto& s : list) {
    if (s.sections & sections) keywords.push_back(Keyword(s.name));
  }
  for (const auto& [name, text] : given) {
    const std::string keyword = Keyword(name);
    if (std::find(keywords.begin(), keywords.end(), keyword) != keywords.end())
      continue;
    const std::vector<std::string> close =
        support::ClosestNames(keywords, keyword);
    throw UnknownOption(
        function + "() got an unexpected keyword argument '" + keyword + "'" +
        (close.empty() ? std::string() : "; did you mean '" + close[0] + "'?"));
  }
}

// `make()`, a support::SettingFailed from it an OptionError naming the
// keyword as Python writes it: "fuse(spring=...): found 0; expected ...".
template <class Make>
auto WithKeywordNames(const std::string& function, Make make)
    -> decltype(make()) {
  try {
    return make();
  } catch (const support::SettingFailed& e) {
    throw OptionError(e.name.empty() ? function + "(): " + e.what()
                                     : function + "(" + Keyword(e.name) +
                                           "=...): " + e.what());
  }
}

// The test's settings from keyword arguments of `function`.
fusion::TestSettings Settings(const Given& given,
                              unsigned sections,
                              const std::string& function) {
  CheckKeywords(fusion::TestSettingList(), sections, given, function);
  return WithKeywordNames(function,
                          [&] { return fusion::MakeTestSettings(given); });
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
    report::FigureFormats formats;
    if (!figures.empty() && !report::FigureFormats::Parse(figures, &formats)) {
      throw OptionError(
          "write: figures: expected svg, png or svg,png; "
          "found '" +
          figures + "'");
    }
    report::EnsureDirectory(dir);
    std::vector<std::string> written;
    for (const auto& [file, text] : products.Files()) {
      if (file == products.result_name) continue;  // last, with every warning
      written.push_back((fs::path(dir) / file).string());
      report::WriteTextAtomically(written.back(), text);
    }
    fusion::TestProducts with;  // result.json alone, its warnings added
    with.result = products.result;
    with.result_name = products.result_name;
    report::FigureSet f;
    if (!figures.empty()) {
      f = report::DrawTestFigures(
          dir, name, *result, options, products, formats);
      if (!f.missing.empty()) with.result["warnings"].push_back(f.message);
    }
    report::WriteResult(dir, with);
    written.push_back((fs::path(dir) / products.result_name).string());
    written.insert(written.end(), f.files.begin(), f.files.end());
    return {written, f.message};
  }
};

// A force record from a path (read with the options) or given.
force::ForceRecord ForceOf(const py::object& force,
                           const fusion::TestSettings& a,
                           std::string* path) {
  if (py::isinstance<py::str>(force)) {
    *path = force.cast<std::string>();
    py::gil_scoped_release release;
    return force::ReadForceFile(*path, a.read_force);
  }
  if (!py::isinstance<force::ForceRecord>(force)) {
    throw py::type_error(
        "fuse(force=...): expected a path or a ForceRecord; found " +
        py::str(py::type::of(force).attr("__name__")).cast<std::string>());
  }
  return force.cast<force::ForceRecord>();
}

std::optional<scan::HeightMap> ScanOf(const py::object& scan,
                                      const fusion::TestSettings& a) {
  if (scan.is_none()) return std::nullopt;
  if (py::isinstance<py::str>(scan)) {
    const std::string path = scan.cast<std::string>();
    py::gil_scoped_release release;
    return scan::ReadScan(path, a.read_scan);
  }
  if (!py::isinstance<scan::HeightMap>(scan)) {
    throw py::type_error(
        "fuse(scan=...): expected a path, a HeightMap or None; found " +
        py::str(py::type::of(scan).attr("__name__")).cast<std::string>());
  }
  return scan.cast<scan::HeightMap>();
}

TestOutput Fuse(const py::object& force,
                const py::object& scan,
                const Given& given,
                const std::string& name,
                int detail_cycle,
                const std::vector<int>& loops) {
  fusion::TestSettings a = Settings(given, fusion::kFuseSettings, "fuse");
  fusion::ProductOptions products;
  if (detail_cycle < 0)
    throw OptionError("fuse(detail_cycle=...): cycles are counted from 1");
  a.fuse.detail_cycle = detail_cycle - 1;  // from 1 outside, from 0 inside
  for (int c : loops) {
    if (c < 1) throw OptionError("fuse(loops=...): cycles are counted from 1");
    products.loop_cycles.push_back(c - 1);
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
                        const fusion::TestSettings& a,
                        const fusion::BatchOptions& batch,
                        const std::vector<std::string>& shared_inputs) {
  nlohmann::json row = fusion::SpecimenIdentity(s, batch);
  try {
    const fusion::SpecimenAnalysis an =
        fusion::AnalyzeSpecimen(s, a.read_force, a.read_scan, a.fuse);
    nlohmann::json full =
        fusion::MakeTestProducts(s.name, an.record, an.result, a.fuse).result;
    // The batch's warnings, as `wearscar audit` adds them.
    if (s.scan_expected) full["warnings"].push_back(s.PairingWarning());
    for (const std::string& w : shared_inputs) full["warnings"].push_back(w);
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
                  const Given& given,
                  const std::string& name_pattern,
                  bool recursive,
                  int jobs,
                  const std::string& out,
                  const std::string& figures,
                  const std::vector<std::string>& factors) {
  fusion::TestSettings a = Settings(given, fusion::kFuseSettings, "audit");
  // Without figures, as `wearscar audit --no-figures`: no loops binned for
  // the report's cycle slider, no loop_viewer.json.
  if (figures.empty()) a.fuse.friction_map.loop_bins = 0;
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
    fusion::TestSettings worker_args = a;
    if (fusion::WorkersFillCores(specimens.size(), batch.jobs))
      worker_args.fuse.parallel = false;
    const auto shared = fusion::SharedInputsBefore(specimens, {}, {});
    const std::vector<std::string> kNone;
    fusion::ForEachSpecimen(
        specimens.size(),
        batch.jobs,
        [&](size_t i) {
          const auto found = shared.find(specimens[i].name);
          rows[i] = AuditOne(specimens[i],
                             worker_args,
                             batch,
                             found == shared.end() ? kNone : found->second);
        },
        [](long) {});
    fusion::GroupOptions g;
    g.factors = factors;
    return nlohmann::json(
               {{"rows", rows},
                {"summary_csv", fusion::SummaryCsv(rows, true)},
                {"groups", fusion::GroupsJson(fusion::CompareGroups(rows, g))}})
        .dump();
  }
  o.groups.factors = factors;
  o.read_force = a.read_force;
  o.read_scan = a.read_scan;
  o.fuse = a.fuse;
  o.figures = !figures.empty();
  if (o.figures && !report::FigureFormats::Parse(figures, &o.figure_formats)) {
    throw OptionError(
        "audit: figures: expected svg, png or svg,png; "
        "found '" +
        figures + "'");
  }
  const report::AuditResult r =
      report::Audit(specimens, out, "wearscar audit of " + input, o);
  for (size_t i = 0; i < rows.size(); ++i) rows[i] = r.specimens[i].row;
  return nlohmann::json({{"rows", rows}}).dump();
}

struct Simulated {
  force::ForceRecord force;
  scan::HeightMap scan;
  std::string truth_json;
};

std::vector<Simulated> Simulate(const Given& given) {
  const auto& list = samples::SimulationSettingList();
  CheckKeywords(list, ~0u, given, "simulate");
  const std::vector<samples::SimulationOptions> cases =
      WithKeywordNames("simulate", [&] {
        samples::SimulationRequest request;
        support::ApplySettings(list, given, &request);
        return samples::SimulationCases(request);
      });
  py::gil_scoped_release release;
  std::vector<Simulated> out;
  for (const samples::SimulationOptions& o : cases) {
    samples::SimulatedTest t = samples::Simulate(o);
    std::string truth = samples::TruthJson(o, t).dump();
    out.push_back({force::RecordFromChannels(std::move(t.record), "simulated"),
                   std::move(t.scan),
                   std::move(truth)});
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

void DefineForceRecord(py::module_& m) {
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
               throw OptionError(
                   "ForceRecord: time_s, x_mm, q_n and p_n must have one "
                   "length");
             }
             return force::RecordFromChannels(std::move(t),
                                              std::move(x),
                                              std::move(q),
                                              std::move(p),
                                              source,
                                              "python");
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
}

void DefineHeightMap(py::module_& m) {
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
               throw OptionError("HeightMap: dx_mm and dy_mm must be > 0");
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

// A force file followed as it is written (wearscar.watch): each look
// returns the cycles completed since the last, as dicts, and the events
// raised with them.
class Watcher {
 public:
  // With a `pattern`, `path` is the folder of a file per block, joined
  // into `joined` as they grow (force::BlockJoiner).
  Watcher(const std::string& path,
          const Given& given,
          int steady_cycles,
          double steady_band,
          int steady_hold,
          double max_depth_mm,
          const std::string& pattern,
          const std::string& joined)
      : settings_(Settings(given, fusion::kFuseSettings, "watch")),
        joiner_(pattern.empty() ? nullptr
                                : std::make_unique<force::BlockJoiner>(
                                      path, pattern, joined)),
        follower_(pattern.empty() ? path : joined, [&] {
          force::FollowOptions o;
          o.read = settings_.read_force;
          return o;
        }()) {
    live_options_.steady_cycles = steady_cycles;
    live_options_.steady_band = steady_band;
    live_options_.steady_hold_cycles = steady_hold;
    live_options_.max_depth_mm = max_depth_mm;
    std::string why;
    if (!live_options_.IsValid(&why)) throw OptionError("watch: " + why);
  }

  // (cycles, events, bytes taken): `idle` when the caller has seen the
  // file stop growing.
  py::tuple Poll(bool idle) {
    std::vector<fusion::LiveCycle> cycles;
    std::vector<fusion::LiveEvent> events;
    {
      py::gil_scoped_release release;
      const std::string block = joiner_ ? joiner_->Update() : std::string();
      if (!block.empty()) {
        const int seen = live_ ? static_cast<int>(live_->cycles().size()) : 0;
        events.push_back({"block", seen, 0.0, block});
      }
      force::FollowedRows got = follower_.Poll(idle);
      if (got.restarted && live_) live_->Restart(got.note, 0.0);
      if (!live_ && follower_.started()) {
        force::ForceRecord head;
        head.metadata = follower_.metadata();
        live_ = std::make_unique<fusion::LiveAnalysis>(
            fusion::WithStatedSpring(settings_.fuse, head), live_options_);
      }
      if (live_) {
        cycles = live_->Add(std::move(got.rows));
        for (fusion::LiveEvent& x : live_->TakeEvents())
          events.push_back(std::move(x));
      }
    }
    py::list c, e;
    for (const fusion::LiveCycle& x : cycles) {
      py::dict d;
      d["cycle"] = x.cycle;
      d["end_time_s"] = x.end_time_s;
      d["mu_hat"] = x.mu_hat;
      d["mu_hat_low"] = x.mu_low;
      d["mu_hat_high"] = x.mu_high;
      d["mu_mean"] = x.mu_mean;
      d["mu_energy"] = x.mu_energy;
      d["J"] = x.cost;
      d["J_floor"] = x.cost_floor;
      d["J_excess"] = x.cost_excess;
      d["depth_mm"] = x.depth_mm;
      d["running_in"] = x.running_in;
      c.append(d);
    }
    for (const fusion::LiveEvent& x : events) {
      py::dict d;
      d["kind"] = x.kind;
      d["cycle"] = x.cycle;
      d["message"] = x.message;
      d["good"] = x.good;
      e.append(d);
    }
    return py::make_tuple(c, e, follower_.offset());
  }

 private:
  fusion::TestSettings settings_;
  std::unique_ptr<force::BlockJoiner> joiner_;
  force::ForceFollower follower_;
  fusion::LiveOptions live_options_;
  std::unique_ptr<fusion::LiveAnalysis> live_;
};

void DefineFunctions(py::module_& m) {
  py::class_<Watcher>(m, "_Watcher")
      .def(py::init<const std::string&,
                    const Given&,
                    int,
                    double,
                    int,
                    double,
                    const std::string&,
                    const std::string&>())
      .def("poll", &Watcher::Poll);
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
  m.def("_read_force", [](const std::string& path, const Given& given) {
    const fusion::TestSettings a =
        Settings(given, fusion::kForceFileSettings, "read_force");
    py::gil_scoped_release release;
    return force::ReadForceFile(path, a.read_force);
  });
  m.def("_read_scan", [](const std::string& path, const Given& given) {
    const fusion::TestSettings a =
        Settings(given, fusion::kScanFileSettings, "read_scan");
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
  static py::exception<python::OptionError> option_error(
      m, "OptionError", PyExc_ValueError);
  static py::exception<report::OutputError> output_error(
      m, "OutputError", PyExc_OSError);
  // What each error means, for help() and the exception's __doc__.
  force_error.attr("__doc__") =
      "A force file that cannot be read: the file, the line or byte, what "
      "was found and what was expected (a ValueError).";
  scan_error.attr("__doc__") =
      "A height map that cannot be read: the file, the byte or field, what "
      "was found and what was expected (a ValueError).";
  fusion_error.attr("__doc__") =
      "A test that cannot be analysed as asked (too few cycles, no track in "
      "the scan, ...), with why (a ValueError).";
  option_error.attr("__doc__") =
      "A keyword argument with a bad value, named as Python writes it: "
      "\"fuse(spring=...): found 0; expected ...\" (a ValueError).";
  output_error.attr("__doc__") =
      "A folder or file that cannot be written (an OSError).";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const force::ForceError& e) {
      force_error(e.what());
    } catch (const scan::ScanError& e) {
      scan_error(e.what());
    } catch (const fusion::FusionError& e) {
      fusion_error(e.what());
    } catch (const python::OptionError& e) {
      option_error(e.what());
    } catch (const report::OutputError& e) {
      output_error(e.what());
    } catch (const python::UnknownOption& e) {
      PyErr_SetString(PyExc_TypeError, e.what());
    }
  });
  python::DefineForceRecord(m);
  python::DefineHeightMap(m);
  python::DefineFunctions(m);
}
