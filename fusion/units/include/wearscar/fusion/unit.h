#pragma once
// An analysis unit: one per-test analysis that declares, in one place,
// what it reads, when it can run, the premises it rests on and what it
// writes (its tables, its section of result.json, its figures, what it
// says in the warnings). The pipeline runs the registry (AnalysisUnits) in
// the order of its stages, beside the rest where the test has cores; the
// products, the figures and result.json ask each unit that ran for its
// part. TestResult::units holds their results by kind; nothing else knows
// a unit. Adding an analysis: its files here, one line of registry.cc,
// its tests and docs (docs/development.md, "Adding an analysis").

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "wearscar/force/force_record.h"
#include "wearscar/fusion/premise.h"
#include "wearscar/fusion/result.h"
#include "wearscar/fusion/table.h"
#include "wearscar/fusion/unit_results.h"

namespace wearscar::fusion {

// When a unit can run: what of the test exists by then.
enum class UnitStage {
  // The record's cycles and gross slip, before the running-in, which the
  // pipeline then detects on what these units find (the classic COFs).
  kSegmented,
  // The record, its cycles and the running-in (no slope fitted): beside
  // the profile's decision.
  kCycles,
  // The force side analysed with k where the decision put it: beside the
  // scan side.
  kDecided,
  // The scan aligned with the decided profile and its slope over the
  // stroke (the result so far holds it; the sides not yet compared).
  kScanned,
  // The two sides compared over the compared cycles (the result's window
  // and mismatch), before the verdict, which reads what these units find
  // (the spring check).
  kCompared,
  // The whole result: the scan side, the comparison and the verdict.
  kJudged,
};

// What a unit reads when it runs.
struct UnitInput {
  const force::ForceRecord& record;
  // At kSegmented the cycles and gross slip, at kCycles the running-in
  // too; later the decided force analysis.
  const ForceAnalysis& force;
  // The options as its stage has them: at kCycles the given ones (with a
  // spring the file states), before the decision puts k.
  const FuseOptions& options;
  // From kScanned on the result so far; null before.
  const TestResult* judged;
  // The results of the units it reads (UnitSpec::reads).
  const UnitResults& units;
};

// A figure as data, drawn by the report (series of the unit's tables by
// column name; a grid of values painted as an image).
struct UnitSeries {
  enum class Role { kForce, kScan, kMeasured, kClassic, kLimit };
  UnitSeries(std::string table_name,
             std::string x_column,
             std::string y_column,
             std::string key_title = "",
             Role colour = Role::kForce,
             double line_width = 1.5,
             int line_dash = 1)
      : table(std::move(table_name)),
        x(std::move(x_column)),
        y(std::move(y_column)),
        title(std::move(key_title)),
        role(colour),
        width(line_width),
        dash(line_dash) {}
  std::string table, x, y;
  std::string title;  // the key's entry; "" none
  Role role = Role::kForce;
  double width = 1.5;
  int dash = 1;                 // 1 solid, 2 dashed
  std::string style = "lines";  // or "points"
  double y_scale = 1;
  // Only the rows whose column `select` holds `select_value`.
  std::string select;
  double select_value = 0;
};
struct UnitGrid {
  std::string file;  // the image's data file ("friction_map_raw.f32")
  std::vector<double> x_mm;
  int rows = 0;               // cycles, from 1
  std::vector<float> values;  // row-major, rows x x_mm.size()
};
struct UnitPanel {
  std::string title, xlabel, ylabel;
  std::string setup;  // gnuplot commands before the plot (ranges)
  std::optional<UnitGrid> grid;
  std::string cblabel;
  std::vector<UnitSeries> series;
};
struct UnitFigure {
  std::string stem, title;
  std::vector<UnitPanel> panels;
};
// A statistic in result.json: mean, sd, count; with the mean's 95%
// interval and the effective number of independent cycles where they were
// estimated.
nlohmann::json StatisticJson(const Statistic& s);

// A grid's panel setup: gnuplot's ranges of bins centred on x_mm over
// cycles from 1.
std::string GridRanges(const std::vector<double>& x_mm, int cycles);

struct UnitTable {
  std::string file;
  Table table;
};

// What a unit makes (its tables, its figures) as a list, each moved in: a
// braced list copies them (an initializer_list's elements are const), and
// a table of 100 000 rows copied doubles its memory for the while.
template <typename T, typename... More>
std::vector<T> MovedList(T first, More... more) {
  std::vector<T> out;
  out.reserve(1 + sizeof...(more));
  out.push_back(std::move(first));
  (out.push_back(std::move(more)), ...);
  return out;
}

// A choice a unit makes that the options give and the data may override,
// recorded as given and as used (as Ceres' Solver::Summary records its
// *_given and *_used): the detail cycle LuGre ran on, the slope span the
// friction map's fit took, the first cycles the scan's shape was pooled
// over. result.json's "units" lists them.
struct UnitChoice {
  std::string name;  // "detail_cycle"
  // Where none was given, `given` names what stands in for it ("last",
  // "the force side's").
  nlohmann::json given, used;
  std::string why;  // why used differs from given ("" same)
};

// Columns a unit adds to a table of the pipeline's core (cycles.csv: one
// row per cycle), set after the column `after` there, so the table reads
// as one whoever computed its columns.
struct UnitColumns {
  std::string table;  // "cycles.csv"
  std::string after;  // a column of the core's, or of a unit's before it
  std::vector<std::string> names;
};

// What a unit declares about itself.
struct UnitSpec {
  const char* kind;  // result.json's key and the registry's name
  const char* what;  // in a line (result.json "units", the docs)
  // What it reads: "the record", "the cycles", "the decision", "the
  // scan", "the verdict", or another unit's kind (run before it).
  std::vector<std::string> reads;
  // The tables it may write (TestTableSchemas lists them).
  std::vector<TableSchema> tables;
  // The columns it adds to the core's tables (empty where it did not run).
  std::vector<UnitColumns> columns = {};
  // The result.json object its Json joins, where its figures stood before
  // they were a unit's ("after_running_in"); null: its own, under its kind.
  const char* json_section = nullptr;
};

class AnalysisUnit {
 public:
  virtual ~AnalysisUnit() = default;
  virtual const UnitSpec& Spec() const = 0;
  const char* Kind() const { return Spec().kind; }
  // When it can run on `record` (a map whose k a depth channel may give
  // waits for the decision; without one it runs beside it).
  virtual UnitStage Stage(const force::ForceRecord& record) const = 0;
  // Whether the options ask for it; a unit not wanted writes nothing.
  virtual bool Wanted(const FuseOptions&) const { return true; }
  // Whether it gains a core on a thread of its own: a unit whose work
  // takes milliseconds and whose result nothing awaits at once (the
  // periodic lines, LuGre, the friction map, the track's history, beside
  // the profile's decision). Every other runs on the thread that awaits or
  // collects it: one that shares its work out over the cores itself (the
  // mu fits), one awaited as soon as it starts (the classic COFs), one
  // that takes a fraction of a millisecond (the checks on the comparison).
  // A thread costs its start, a fresh heap and its stack's pages.
  virtual bool WorthAThread() const { return false; }

  // The typed interface through TypedUnit.
  virtual std::shared_ptr<const void> RunErased(const UnitInput& in) const = 0;
  virtual void Store(std::shared_ptr<const void> result,
                     UnitResults* units) const = 0;
  virtual void SayErased(const void* result, TestResult* r) const = 0;
  virtual std::vector<Premise> PremisesErased(const void* result,
                                              const TestResult& r) const = 0;
  virtual std::vector<UnitChoice> ChoicesErased(const void* result,
                                                const TestResult& r) const = 0;
  virtual nlohmann::json JsonErased(const void* result,
                                    const TestResult& r) const = 0;
  virtual std::vector<UnitTable> TablesErased(const void* result,
                                              const force::ForceRecord& record,
                                              const TestResult& r) const = 0;
  virtual std::vector<std::vector<double>> ColumnsErased(
      const void* result,
      const UnitColumns& columns,
      const TestResult& r) const = 0;
  virtual std::vector<UnitFigure> FiguresErased(const void* result,
                                                const std::string& name,
                                                const TestResult& r) const = 0;
};

// A unit whose result is an R: what each unit implements.
template <typename R>
class TypedUnit : public AnalysisUnit {
 public:
  virtual R Run(const UnitInput& in) const = 0;
  // What the result says in the test's warnings and verdict (once the
  // verdict is made).
  virtual void Say(const R&, TestResult*) const {}
  // The premises it rested on, each as checked (result.json premises).
  virtual std::vector<Premise> Premises(const R&, const TestResult&) const {
    return {};
  }
  // Its choices, as given and as used (UnitChoice).
  virtual std::vector<UnitChoice> Choices(const R&, const TestResult&) const {
    return {};
  }
  virtual nlohmann::json Json(const R& result, const TestResult& r) const = 0;
  virtual std::vector<UnitTable> Tables(const R&,
                                        const force::ForceRecord&,
                                        const TestResult&) const {
    return {};
  }
  // The values of `columns` (one of UnitSpec::columns), a row of
  // columns.names.size() values for each row of the core's table.
  virtual std::vector<std::vector<double>> Columns(const R&,
                                                   const UnitColumns&,
                                                   const TestResult&) const {
    return {};
  }
  virtual std::vector<UnitFigure> Figures(const R&,
                                          const std::string&,
                                          const TestResult&) const {
    return {};
  }

  std::shared_ptr<const void> RunErased(const UnitInput& in) const final {
    return std::make_shared<const R>(Run(in));
  }
  void Store(std::shared_ptr<const void> result,
             UnitResults* units) const final {
    units->Put<R>(Kind(), std::static_pointer_cast<const R>(result));
  }
  void SayErased(const void* result, TestResult* r) const final {
    Say(*static_cast<const R*>(result), r);
  }
  std::vector<Premise> PremisesErased(const void* result,
                                      const TestResult& r) const final {
    return Premises(*static_cast<const R*>(result), r);
  }
  std::vector<UnitChoice> ChoicesErased(const void* result,
                                        const TestResult& r) const final {
    return Choices(*static_cast<const R*>(result), r);
  }
  nlohmann::json JsonErased(const void* result,
                            const TestResult& r) const final {
    return Json(*static_cast<const R*>(result), r);
  }
  std::vector<UnitTable> TablesErased(const void* result,
                                      const force::ForceRecord& record,
                                      const TestResult& r) const final {
    return Tables(*static_cast<const R*>(result), record, r);
  }
  std::vector<std::vector<double>> ColumnsErased(
      const void* result,
      const UnitColumns& columns,
      const TestResult& r) const final {
    return Columns(*static_cast<const R*>(result), columns, r);
  }
  std::vector<UnitFigure> FiguresErased(const void* result,
                                        const std::string& name,
                                        const TestResult& r) const final {
    return Figures(*static_cast<const R*>(result), name, r);
  }
};

// Every unit, in the order they run within a stage and write their
// products (registry.cc: one line each).
const std::vector<const AnalysisUnit*>& AnalysisUnits();

// The units that ran on `r`, each with its stored result, in the
// registry's order.
std::vector<std::pair<const AnalysisUnit*, const void*>> UnitsThatRan(
    const TestResult& r);

// Runs the registry's units stage by stage for one test: Start launches
// the units of a stage (on threads of their own where `parallel`, else
// when collected), Collect waits for every unit started and stores their
// results. A unit waits for the units it reads. Destroying the runner
// waits for what still runs, so it must not outlive what it was given.
class UnitRunner {
 public:
  UnitRunner(const force::ForceRecord& record, bool parallel);
  ~UnitRunner();
  UnitRunner(const UnitRunner&) = delete;
  UnitRunner& operator=(const UnitRunner&) = delete;

  // `options` is copied: the decision may change the caller's while the
  // units run. `force` and `judged` must live until Collect.
  void Start(UnitStage stage,
             const ForceAnalysis& force,
             const FuseOptions& options,
             const TestResult* judged = nullptr);
  void Collect(UnitResults* units);
  // Waits for the unit `kind` started before and stores its result now,
  // in `units` and for the units started after: for the core, which reads
  // the force side's fits before the stage is collected. False where it
  // was not started.
  bool CollectOne(std::string_view kind, UnitResults* units);
  // The result of the unit `kind` (of type R) once it is done, waiting for
  // it: for the pipeline's core where it reads a unit before the stage is
  // collected (the track's history). Null when it was not started.
  template <typename R>
  std::shared_ptr<const R> Await(std::string_view kind) const {
    return std::static_pointer_cast<const R>(AwaitErased(kind));
  }

 private:
  std::shared_ptr<const void> AwaitErased(std::string_view kind) const;
  struct Running;
  const force::ForceRecord& record_;
  bool parallel_;
  std::vector<std::shared_ptr<Running>> running_;
  UnitResults done_;
};

// What every unit that ran says in the warnings and the verdict, in the
// registry's order (once the verdict is made).
void SayWhatTheUnitsFound(TestResult* r);

}  // namespace wearscar::fusion
