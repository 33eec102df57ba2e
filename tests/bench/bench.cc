// Speed of wearscar's stages, and the paper's procedure done the simple way
// (Nelder-Mead per cycle, as MATLAB's fminsearch) next to ours, in one run.
// Run with scripts/bench; figures and targets are in docs/performance.md.
#include <benchmark/benchmark.h>
#include <fast_float/fast_float.h>
#include <malloc.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "common/simulated.h"
#include "wearscar/force/periodic.h"
#include "wearscar/force/read_force.h"
#include "wearscar/fusion/analysis.h"
#include "wearscar/fusion/forward_model.h"
#include "wearscar/fusion/friction_map.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/live.h"
#include "wearscar/fusion/track_history.h"
#include "wearscar/scan/gsf.h"
#include "wearscar/scan/level.h"
#include "wearscar/scan/track.h"

namespace {

namespace fs = std::filesystem;
using namespace wearscar;

const std::string& Scratch() {
  static const std::string dir = [] {
    const fs::path d = fs::temp_directory_path() / "wearscar-bench";
    fs::create_directories(d);
    return d.string();
  }();
  return dir;
}

// The paper's test: 600 cycles at 2 kHz (1.2 million samples), full scan.
const sim::SimulatedTest& Test600() {
  static const sim::SimulatedTest t =
      sim::Simulate(samples::PaperCase("S-RT-R"));
  return t;
}

const std::string& Csv600() {
  static const std::string path = [] {
    const std::string p = Scratch() + "/S-RT-R.force.csv";
    force::WriteForceCsv(Test600().record, p);
    return p;
  }();
  return path;
}

const force::CycleSet& Cycles600() {
  static const force::CycleSet c = [] {
    force::CycleSet s = force::SegmentCycles(Test600().record.x_mm);
    force::FindGrossSlip(Test600().record, &s);
    return s;
  }();
  return c;
}

// Peak memory of reading the CSV over the numeric data it holds (4 channels
// of doubles): measured in a forked child as the growth of its peak resident
// set while reading (target <= 1.5).
// Resident or peak resident memory of this process from /proc, bytes.
double ProcStatusBytes(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key, 0) == 0)
      return 1024.0 * std::stod(line.substr(std::strlen(key)));
  }
  return std::nan("");
}

double IngestMemoryRatio(const std::string& path,
                         const force::ReadForceOptions& options) {
  int fd[2];
  if (pipe(fd) != 0) return std::nan("");
  const pid_t pid = fork();
  if (pid == 0) {
    malloc_trim(0);  // freed memory of the parent no longer counts
    std::ofstream("/proc/self/clear_refs") << "5";  // reset the peak RSS
    const double before = ProcStatusBytes("VmRSS:");
    const force::ForceRecord r = force::ReadForceFile(path, options);
    const double grown = ProcStatusBytes("VmHWM:") - before;
    const double ratio = grown / (4.0 * 8.0 * static_cast<double>(r.size()));
    if (write(fd[1], &ratio, sizeof ratio) != sizeof ratio) _exit(1);
    _exit(0);
  }
  close(fd[1]);
  double ratio = std::nan("");
  if (read(fd[0], &ratio, sizeof ratio) != sizeof ratio) ratio = std::nan("");
  close(fd[0]);
  waitpid(pid, nullptr, 0);
  return ratio;
}

void BM_CsvIngest(benchmark::State& state) {
  const std::string& path = Csv600();
  const auto bytes = static_cast<int64_t>(fs::file_size(path));
  force::ReadForceOptions options;
  for (auto _ : state) {
    const force::ForceRecord r = force::ReadForceFile(path, options);
    benchmark::DoNotOptimize(r.normal_n.data());
  }
  state.SetBytesProcessed(state.iterations() * bytes);
  state.counters["rows"] = static_cast<double>(Test600().record.size());
  state.counters["peak_memory_ratio"] = IngestMemoryRatio(path, options);
}
BENCHMARK(BM_CsvIngest)->Unit(benchmark::kMillisecond)->MinTime(2.0);

// The machine's floor for the same ingest: the CSV, already in the page
// cache, read into memory that is already mapped, and its four columns
// parsed by fast_float into arrays that are already mapped (no layout
// detection, no checks, no units); then one pass over the parsed numbers.
// docs/performance.md gives the ingest's and the fuse's ratio to these.
void BM_FloorParseWarm(benchmark::State& state) {
  const std::string& path = Csv600();
  std::string text(static_cast<size_t>(fs::file_size(path)), '\0');
  std::vector<double> columns(4 * Test600().record.size() + 64);
  for (auto _ : state) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    const size_t got = std::fread(text.data(), 1, text.size(), f);
    std::fclose(f);
    const char* p = text.data();
    const char* const end = p + got;
    p = static_cast<const char*>(std::memchr(p, '\n', end - p)) + 1;
    size_t n = 0;
    while (p < end && n + 4 <= columns.size()) {
      auto r = fast_float::from_chars(p, end, columns[n++]);
      p = r.ptr + 1;  // past ',' or '\n'
    }
    benchmark::DoNotOptimize(columns.data());
  }
  state.SetBytesProcessed(state.iterations() *
                          static_cast<int64_t>(text.size()));
}
BENCHMARK(BM_FloorParseWarm)->Unit(benchmark::kMillisecond);

void BM_FloorOnePass(benchmark::State& state) {
  const auto& r = Test600().record;
  for (auto _ : state) {
    double sum = 0;
    for (Eigen::Index i = 0; i < r.size(); ++i)
      sum += r.x_mm[i] * r.tangential_n[i] + r.normal_n[i] * r.time_s[i];
    benchmark::DoNotOptimize(sum);
  }
}
BENCHMARK(BM_FloorOnePass)->Unit(benchmark::kMillisecond);

// The command as a user runs it, on the 45 MB CSV and a 1024 x 768 GSF:
// without figures (arg 0) and with its figures in SVG, the default (arg 1).
void BM_FuseCommand(benchmark::State& state) {
  const std::string scan = Scratch() + "/S-RT-R.scan.gsf";
  scan::WriteGsf(Test600().scan, scan);
  const std::string cmd = std::string(WEARSCAR_BINARY) + " fuse " + Csv600() +
                          " --scan " + scan + " -q -o " + Scratch() + "/fuse" +
                          (state.range(0) ? "" : " --no-figures");
  for (auto _ : state) {
    if (std::system(cmd.c_str()) != 0) state.SkipWithError("fuse failed");
  }
}
BENCHMARK(BM_FuseCommand)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(3.0);

// The start of the command alone (`wearscar version`): loading its shared
// libraries and their relocations, a floor under every command's time.
void BM_CommandStart(benchmark::State& state) {
  const std::string cmd = std::string(WEARSCAR_BINARY) + " version > /dev/null";
  for (auto _ : state) {
    if (std::system(cmd.c_str()) != 0) state.SkipWithError("version failed");
  }
}
BENCHMARK(BM_CommandStart)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(1.0);

void BM_SegmentCycles(benchmark::State& state) {
  const auto& r = Test600().record;
  for (auto _ : state) {
    force::CycleSet s = force::SegmentCycles(r.x_mm);
    force::FindGrossSlip(r, &s);
    benchmark::DoNotOptimize(s.cycles.data());
  }
  state.SetItemsProcessed(state.iterations() * r.size());
}
BENCHMARK(BM_SegmentCycles)->Unit(benchmark::kMillisecond);

void BM_MuHat600Cycles(benchmark::State& state) {
  const auto& r = Test600().record;
  for (auto _ : state) {
    const auto fits = fusion::FitFrictionPerCycle(
        r, Cycles600(), fusion::SlopeSource::kForce);
    benchmark::DoNotOptimize(fits.data());
  }
  state.SetItemsProcessed(state.iterations() * 600);
}
BENCHMARK(BM_MuHat600Cycles)->Unit(benchmark::kMillisecond);

// Baseline: the paper's procedure the simple way. The slope is the same
// (moving average 10 + three-point difference); mu per cycle by Nelder-Mead
// from mu = 0.5 with fminsearch's defaults (TolX = TolFun = 1e-4, expansion
// 2, contraction 0.5, initial step 5%), the wear-scar law evaluated with
// Eqs. 1-2 as written (N from Eq. 2, then Q from Eq. 1).
double PaperCost(const fusion::CycleSamples& s, double mu) {
  double cost = 0;
  for (const fusion::SlipSamples* d : {&s.forward, &s.reverse}) {
    double num = 0, den = 0;
    for (Eigen::Index i = 0; i < d->q_n.size(); ++i) {
      const double k = d->k[i], root = std::sqrt(1 + k * k);
      const double n = d->p_n[i] * root / (1 - d->direction * mu * k);  // Eq. 2
      const double q = k * n / root + d->direction * mu * n / root;     // Eq. 1
      num += (d->q_n[i] - q) * (d->q_n[i] - q);
      den += d->q_n[i] * d->q_n[i];
    }
    cost += std::sqrt(num) / std::sqrt(den);
  }
  return cost;
}

double NelderMead1D(const fusion::CycleSamples& s) {
  double x[2] = {0.5, 0.5 * 1.05},
         f[2] = {PaperCost(s, x[0]), PaperCost(s, x[1])};
  for (int it = 0; it < 200; ++it) {
    if (f[1] < f[0]) {
      std::swap(x[0], x[1]);
      std::swap(f[0], f[1]);
    }
    if (std::abs(x[1] - x[0]) <= 1e-4 && std::abs(f[1] - f[0]) <= 1e-4) break;
    const double xr = 2 * x[0] - x[1], fr = PaperCost(s, xr);
    if (fr < f[0]) {
      const double xe = 3 * x[0] - 2 * x[1], fe = PaperCost(s, xe);
      if (fe < fr) {
        x[1] = xe;
        f[1] = fe;
      } else {
        x[1] = xr;
        f[1] = fr;
      }
    } else {
      const double xc = 0.5 * (x[0] + x[1]), fc = PaperCost(s, xc);
      if (fc < f[1]) {
        x[1] = xc;
        f[1] = fc;
      } else {
        x[1] = x[0] + 0.5 * (x[1] - x[0]);
        f[1] = PaperCost(s, x[1]);
      }
    }
  }
  return f[0] < f[1] ? x[0] : x[1];
}

void BM_MuHat600CyclesPaperNelderMead(benchmark::State& state) {
  const auto& r = Test600().record;
  fusion::FrictionFitOptions o;
  o.slope.min_span_mm = 0;  // the paper's stencil exactly
  for (auto _ : state) {
    double sum = 0;
    for (const auto& c : Cycles600().cycles) {
      sum += NelderMead1D(
          fusion::GatherCycle(r, c, fusion::SlopeSource::kForce, o));
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * 600);
}
BENCHMARK(BM_MuHat600CyclesPaperNelderMead)->Unit(benchmark::kMillisecond);

// The virtual tribometer and scanner: one 600-cycle test at 2 kHz with its
// 1024 x 768 scan (target: under 2 s).
void BM_Simulate600CyclesWithScan(benchmark::State& state) {
  const samples::SimulationOptions o = samples::PaperCase("S-RT-R");
  for (auto _ : state) {
    const sim::SimulatedTest t = sim::Simulate(o);
    benchmark::DoNotOptimize(t.scan.height_mm.data());
  }
}
BENCHMARK(BM_Simulate600CyclesWithScan)->Unit(benchmark::kMillisecond);

// A simulated 4:3 scan `cols` wide (the paper's 7.6 mm field) as GSF,
// written once.
std::string ScanGsf(int cols) {
  const std::string path = Scratch() + "/scan_" + std::to_string(cols) + ".gsf";
  if (!fs::exists(path)) {
    samples::SimulationOptions o = samples::PaperCase("B-RT-R");
    o.cycles = 2;
    o.scan_cols = cols;
    o.scan_rows = cols * 3 / 4;
    o.scan_pitch_mm = 0.0074 * 1024.0 / cols;
    scan::WriteGsf(sim::Simulate(o).scan, path);
  }
  return path;
}

// Read + level + spikes + track + centreline of a scan written as GSF.
void BM_ScanPipeline(benchmark::State& state) {
  const int cols = static_cast<int>(state.range(0)), rows = cols * 3 / 4;
  const std::string path = ScanGsf(cols);
  for (auto _ : state) {
    scan::HeightMap m = scan::ReadGsf(path);
    scan::LevelHeightMap(&m);
    scan::RemoveSpikes(&m);
    const scan::Track t = scan::FindTrack(m);
    const scan::WearProfile p = scan::ExtractCentreline(m, t);
    benchmark::DoNotOptimize(p.height_mm.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(cols) *
                          rows);
}
BENCHMARK(BM_ScanPipeline)->Arg(1024)->Arg(4096)->Unit(benchmark::kMillisecond);

// The same through the command (`wearscar scan FILE -q`: read, level,
// spikes, track, centreline and cross-sections, nothing written), as a
// user's process with the command's allocator.
void BM_ScanCommand(benchmark::State& state) {
  const std::string cmd = std::string(WEARSCAR_BINARY) + " scan " +
                          ScanGsf(static_cast<int>(state.range(0))) + " -q";
  for (auto _ : state) {
    if (std::system(cmd.c_str()) != 0) state.SkipWithError("scan failed");
  }
}
BENCHMARK(BM_ScanCommand)
    ->Arg(1024)
    ->Arg(4096)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

void BM_Fuse600Cycles(benchmark::State& state) {
  const auto& t = Test600();
  fusion::FuseOptions o;
  o.fit_lugre = false;
  for (auto _ : state) {
    const fusion::TestResult r = fusion::AnalyzeTest(t.record, t.scan, o);
    benchmark::DoNotOptimize(r.verdict.explained);
  }
}
BENCHMARK(BM_Fuse600Cycles)->Unit(benchmark::kMillisecond);

// The live analysis of the same test (`wearscar watch`'s work past reading
// the rows), handed its rows in blocks of 0.05 s as a follower would: its
// time over BM_Fuse600Cycles' is the live phase's share of the watch's CPU
// (docs/watch.md).
void BM_Live600Cycles(benchmark::State& state) {
  const force::ForceRecord& r = Test600().record;
  const Eigen::Index block = 100;  // 0.05 s at 2 kHz
  std::vector<force::ForceRecord> blocks;
  for (Eigen::Index at = 0; at < r.size(); at += block) {
    const Eigen::Index n = std::min(block, r.size() - at);
    force::ForceRecord b;
    b.time_s = r.time_s.segment(at, n);
    b.x_mm = r.x_mm.segment(at, n);
    b.tangential_n = r.tangential_n.segment(at, n);
    b.normal_n = r.normal_n.segment(at, n);
    b.metadata = r.metadata;
    blocks.push_back(std::move(b));
  }
  for (auto _ : state) {
    fusion::LiveAnalysis live(fusion::FuseOptions{});
    std::size_t reported = 0;
    for (const force::ForceRecord& b : blocks) reported += live.Add(b).size();
    if (reported < 590) state.SkipWithError("cycles were not all reported");
  }
}
BENCHMARK(BM_Live600Cycles)->Unit(benchmark::kMillisecond);

// The friction map and the track's history are parts of BM_Fuse600Cycles:
// their share of it is their time over its (issue: at most 20%).
void BM_FrictionMap600Cycles(benchmark::State& state) {
  const auto& r = Test600().record;
  fusion::FrictionMapOptions o;
  o.slope_polynomial_order = static_cast<int>(state.range(0));
  for (auto _ : state) {
    const fusion::FrictionMap m =
        fusion::ComputeFrictionMap(r, Cycles600(), {}, 60, o);
    benchmark::DoNotOptimize(m.spatial_sd_corrected);
  }
}
// Arg: the local polynomial's degree for the map's k (3 the default, 2 the
// fit's quadratic).
BENCHMARK(BM_FrictionMap600Cycles)
    ->Arg(3)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond);

void BM_TrackHistory600Cycles(benchmark::State& state) {
  const auto& r = Test600().record;
  for (auto _ : state) {
    const fusion::TrackHistory h =
        fusion::ComputeTrackHistory(r, Cycles600(), 10.19);
    benchmark::DoNotOptimize(h.final_waviness_sd_mm);
  }
}
BENCHMARK(BM_TrackHistory600Cycles)->Unit(benchmark::kMillisecond);

// The force side's own stages of BM_Fuse600Cycles: the fit with k from P
// (the ensemble slope, mu-hat per cycle, the noise split) and the search
// for periodic lines in Q and P.
void BM_FitForceSide600Cycles(benchmark::State& state) {
  const auto& r = Test600().record;
  fusion::AnalysisOptions o;
  const fusion::ForceAnalysis segmented = fusion::SegmentForce(r, o);
  for (auto _ : state) {
    const fusion::SlopeFits a = fusion::FitForceSide(r, o, segmented);
    benchmark::DoNotOptimize(a.mu_hat.mean);
  }
}
BENCHMARK(BM_FitForceSide600Cycles)->Unit(benchmark::kMillisecond);

void BM_PeriodicLines600Cycles(benchmark::State& state) {
  const auto& r = Test600().record;
  for (auto _ : state) {
    const auto lines = force::FindPeriodicLines(r, 1.0);
    benchmark::DoNotOptimize(lines.data());
  }
}
BENCHMARK(BM_PeriodicLines600Cycles)->Unit(benchmark::kMillisecond);

// The whole command line on the paper's 12 cases (600 cycles, 2 kHz,
// 1024 x 768 scans), figures and report included.
void BM_Audit12(benchmark::State& state) {
  const std::string in = Scratch() + "/twelve";
  const std::string bin = WEARSCAR_BINARY;
  {  // regenerated every run: the simulator may have changed since
    const std::string cmd = bin + " simulate --all --formats csv,gsf -o " + in +
                            " > /dev/null 2>&1";
    if (std::system(cmd.c_str()) != 0) state.SkipWithError("simulate failed");
  }
  for (auto _ : state) {
    const std::string cmd =
        bin + " audit " + in + " -o " + Scratch() + "/audit > /dev/null 2>&1";
    if (std::system(cmd.c_str()) != 0) state.SkipWithError("audit failed");
  }
}
BENCHMARK(BM_Audit12)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
