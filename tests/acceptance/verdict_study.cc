// The verdict's acceptance study on the virtual tribometer (issue: a verdict
// that transfers between labs).
//
//   verdict_study grid  [--cycles N] [--seeds K] [--jobs J]
//     the paper's 12 cases x noise 0.25, 0.5, 1, 2, 4 (of the level
//     calibrated to the paper's J) x K seeds, each judged with and without
//     its scan; every case without an elastic part, plus S-RL-R with an
//     elastic part of 25% and 40% of the worn profile's amplitude. Counts
//     false flags and misses, and mu-hat's error. Exit status 1 when any
//     acceptance line fails.
//   verdict_study curve [--cycles N] [--seeds K] [--jobs J]
//     the detection curve: S-RL-R with an elastic part of 0-60% of the
//     profile amplitude at noise 1 and 2, fraction flagged.
//   verdict_study case NAME NOISE ELASTIC [--k cycle|ensemble]
//     one test, every figure of its verdict.
//
// A long program, not a unit test: a representative subset runs in
// fusion_test (tests/fusion/verdict_test.cc).

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/simulated.h"
#include "wearscar/fusion/fuse.h"

namespace {

using wearscar::fusion::AnalyzeTest;
using wearscar::fusion::FuseOptions;
using wearscar::fusion::TestResult;
using wearscar::samples::PaperCase;
using wearscar::samples::PaperCases;
using wearscar::samples::SimulationOptions;
using wearscar::sim::SimulatedTest;

struct Job {
  std::string name;
  double noise = 1;
  double elastic = 0;  // fraction of the worn profile's sd
  int seed = 0;
};

struct Outcome {
  Job job;
  bool flagged[2] = {false, false};  // without, with the scan
  bool flagged_paper = false;        // the paper's J > 0.4, k per cycle
  double cost = 0, floor = 0, excess = 0, excess_low = 0;
  double ratio = 0, ratio_low = 0;
  double mu_error = 0;  // median |mu-hat - mu| after running-in, k from P
  double mu_error_scan = 0;
  std::string reasons;
};

double Median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

Outcome Run(const Job& job, int cycles) {
  SimulationOptions o = PaperCase(job.name, false);
  o.cycles = cycles;
  o.noise_scale = job.noise;
  o.elastic_fraction = job.elastic;
  o.seed += 7919 * static_cast<std::uint64_t>(job.seed);
  const SimulatedTest t = wearscar::sim::Simulate(o);
  Outcome out;
  out.job = job;
  FuseOptions f;
  f.fit_lugre = false;
  for (int with_scan = 0; with_scan < 2; ++with_scan) {
    const TestResult r = with_scan ? AnalyzeTest(t.record, t.scan, f)
                                   : AnalyzeTest(t.record, std::nullopt, f);
    out.flagged[with_scan] = !r.verdict.explained;
    if (!r.verdict.explained) out.reasons += r.verdict.Summary() + " | ";
    const int first = r.force.running_in.cycles;
    std::vector<double> ef, es;
    for (int c = first; c < cycles; ++c) {
      const double mu = t.truth.mu_per_cycle[c];
      ef.push_back(std::abs(r.ForceFits().cycles[c].mu_hat - mu));
      if (r.scan)
        es.push_back(std::abs(r.ScanSlopeFits().cycles[c].mu_hat - mu));
    }
    if (with_scan) {
      out.mu_error_scan = Median(es);
      out.ratio = r.mismatch.amplitude_ratio;
      out.ratio_low = r.mismatch.amplitude_ratio_low;
    } else {
      out.mu_error = Median(ef);
      out.cost = r.mismatch.split_force.cost;
      out.floor = r.mismatch.split_force.floor;
      out.excess = r.mismatch.split_force.excess;
      out.excess_low = r.mismatch.split_force.excess_low;
    }
  }
  // The paper's criterion for comparison: k from each cycle's own P, J
  // itself against 0.4.
  FuseOptions p = f;
  p.analysis.friction.k_estimate = wearscar::fusion::KEstimate::kCycle;
  p.verdict.cost_criterion = wearscar::fusion::CostCriterion::kPaperJ;
  const TestResult rp = AnalyzeTest(t.record, std::nullopt, p);
  out.flagged_paper = rp.mismatch.cost_force.mean > p.verdict.max_cost;
  return out;
}

std::vector<Outcome> RunAll(const std::vector<Job>& jobs, int cycles, int n) {
  std::vector<Outcome> out(jobs.size());
  std::atomic<size_t> next{0};
  std::atomic<size_t> done{0};
  std::mutex print;
  auto worker = [&] {
    for (size_t i; (i = next++) < jobs.size();) {
      out[i] = Run(jobs[i], cycles);
      const size_t d = ++done;
      std::lock_guard<std::mutex> lock(print);
      fmt::print(stderr, "\r{}/{} tests", d, jobs.size());
    }
  };
  std::vector<std::thread> threads;
  for (int k = 0; k < n; ++k) threads.emplace_back(worker);
  for (auto& th : threads) th.join();
  fmt::print(stderr, "\n");
  return out;
}

struct Args {
  int cycles = 600, seeds = 3, jobs = 2;
  std::string k = "ensemble";
};

int Grid(const Args& a) {
  const double noises[] = {0.25, 0.5, 1, 2, 4};
  std::vector<Job> jobs;
  for (const auto& c : PaperCases(false)) {
    for (double n : noises) {
      for (int s = 0; s < a.seeds; ++s) jobs.push_back({c.name, n, 0.0, s});
    }
  }
  for (double e : {0.25, 0.4}) {
    for (double n : noises) {
      for (int s = 0; s < a.seeds; ++s) jobs.push_back({"S-RL-R", n, e, s});
    }
  }
  const std::vector<Outcome> out = RunAll(jobs, a.cycles, a.jobs);
  int false_flags = 0, clean = 0, misses = 0, elastic = 0, paper_false = 0;
  std::map<double, std::vector<double>> err_force, err_scan;
  fmt::print(
      "case     noise elastic seed | J      floor  excess [low]  | "
      "ratio [low]   | flagged w/o, with scan | paper's J>0.4\n");
  for (const Outcome& o : out) {
    const Job& j = o.job;
    fmt::print(
        "{:8} {:5.2f} {:5.2f}   {:2}   | {:.3f}  {:.3f}  {:.3f} [{:.3f}] | "
        "{:.3f} [{:.3f}] | {:d} {:d} | {:d}\n",
        j.name,
        j.noise,
        j.elastic,
        j.seed,
        o.cost,
        o.floor,
        o.excess,
        o.excess_low,
        o.ratio,
        o.ratio_low,
        o.flagged[0],
        o.flagged[1],
        o.flagged_paper);
    if (j.elastic == 0) {
      clean += 2;
      false_flags += o.flagged[0] + o.flagged[1];
      paper_false += o.flagged_paper;
      err_force[j.noise].push_back(o.mu_error);
      err_scan[j.noise].push_back(o.mu_error_scan);
      if (o.flagged[0] || o.flagged[1])
        fmt::print("  false flag: {}\n", o.reasons);
    } else {
      elastic += 2;
      misses += !o.flagged[0] + !o.flagged[1];
    }
  }
  fmt::print(
      "\nfalse flags: {} of {} clean judgements (with the paper's J > 0.4 "
      "and k per cycle: {} of {} tests)\n",
      false_flags,
      clean,
      paper_false,
      clean / 2);
  fmt::print(
      "elastic part >= 25% missed: {} of {} judgements\n", misses, elastic);
  bool accuracy_ok = true;
  for (const auto& [noise, v] : err_force) {
    const double f = Median(v), s = Median(err_scan[noise]);
    fmt::print(
        "noise {:4.2f}: median over cases of the median |mu-hat - mu| after "
        "running-in: k from P {:.5f} (max {:.5f}), k from the scan {:.5f} "
        "(max {:.5f})\n",
        noise,
        f,
        *std::max_element(v.begin(), v.end()),
        s,
        *std::max_element(err_scan[noise].begin(), err_scan[noise].end()));
    if (noise == 1 && (*std::max_element(v.begin(), v.end()) > 0.002 ||
                       *std::max_element(err_scan[noise].begin(),
                                         err_scan[noise].end()) > 0.004)) {
      accuracy_ok = false;
    }
  }
  return false_flags == 0 && misses == 0 && accuracy_ok ? 0 : 1;
}

int Curve(const Args& a) {
  std::vector<Job> jobs;
  for (double n : {1.0, 2.0}) {
    for (int e = 0; e <= 12; ++e) {
      for (int s = 0; s < a.seeds; ++s)
        jobs.push_back({"S-RL-R", n, 0.05 * e, s});
    }
  }
  const std::vector<Outcome> out = RunAll(jobs, a.cycles, a.jobs);
  fmt::print(
      "elastic part (of the profile sd) | flagged at noise 1 | at "
      "noise 2   (judgements: {} seeds x with/without scan)\n",
      a.seeds);
  for (int e = 0; e <= 12; ++e) {
    int flagged[2] = {0, 0}, total[2] = {0, 0};
    double excess[2] = {0, 0};
    for (const Outcome& o : out) {
      if (std::abs(o.job.elastic - 0.05 * e) > 1e-9) continue;
      const int k = o.job.noise == 1 ? 0 : 1;
      flagged[k] += o.flagged[0] + o.flagged[1];
      total[k] += 2;
      excess[k] += o.excess / a.seeds;
    }
    fmt::print(
        "{:>5.0f}% | {}/{} (J excess {:.3f}) | {}/{} (J excess {:.3f})\n",
        5.0 * e,
        flagged[0],
        total[0],
        excess[0],
        flagged[1],
        total[1],
        excess[1]);
  }
  return 0;
}

int OneCase(const std::string& name,
            double noise,
            double elastic,
            const Args& a) {
  SimulationOptions o = PaperCase(name, false);
  o.cycles = a.cycles;
  o.noise_scale = noise;
  o.elastic_fraction = elastic;
  const SimulatedTest t = wearscar::sim::Simulate(o);
  FuseOptions f;
  f.fit_lugre = false;
  if (!wearscar::fusion::ParseKEstimate(a.k, &f.analysis.friction.k_estimate))
    return 2;
  for (int with_scan = 0; with_scan < 2; ++with_scan) {
    const TestResult r = with_scan ? AnalyzeTest(t.record, t.scan, f)
                                   : AnalyzeTest(t.record, std::nullopt, f);
    const auto& m = r.mismatch;
    fmt::print(
        "{} noise {} elastic {} {} scan: J {:.3f}, floor {:.3f}, excess "
        "{:.3f} [{:.3f}, {:.3f}]; J scan {:.3f} floor {:.3f}; ratio {:.3f} "
        "[{:.3f}, {:.3f}]; mu-hat - mu_energy {:+.4f} [{:+.4f}, {:+.4f}]\n  "
        "{}\n  {}\n",
        name,
        noise,
        elastic,
        with_scan ? "with" : "without",
        m.split_force.cost,
        m.split_force.floor,
        m.split_force.excess,
        m.split_force.excess_low,
        m.split_force.excess_high,
        m.split_scan.cost,
        m.split_scan.floor,
        m.amplitude_ratio,
        m.amplitude_ratio_low,
        m.amplitude_ratio_high,
        m.method_difference.mean,
        m.method_difference.low,
        m.method_difference.high,
        r.ForceFits().slope_estimate,
        r.verdict.Summary());
    for (const auto& w : r.warnings) fmt::print("  warning: {}\n", w);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    fmt::print(stderr,
               "usage: verdict_study grid|curve [--cycles N] [--seeds K] "
               "[--jobs J] | case NAME NOISE ELASTIC [--k cycle|ensemble]\n");
    return 2;
  }
  const std::string mode = argv[1];
  Args a;
  std::vector<std::string> positional;
  for (int i = 2; i < argc; ++i) {
    const std::string s = argv[i];
    const bool has_value = i + 1 < argc;
    if (s == "--cycles" && has_value) {
      a.cycles = std::atoi(argv[++i]);
    } else if (s == "--seeds" && has_value) {
      a.seeds = std::atoi(argv[++i]);
    } else if (s == "--jobs" && has_value) {
      a.jobs = std::max(1, std::atoi(argv[++i]));
    } else if (s == "--k" && has_value) {
      a.k = argv[++i];
    } else {
      positional.push_back(s);
    }
  }
  if (mode == "grid") return Grid(a);
  if (mode == "curve") return Curve(a);
  if (mode == "case" && positional.size() == 3) {
    return OneCase(positional[0],
                   std::atof(positional[1].c_str()),
                   std::atof(positional[2].c_str()),
                   a);
  }
  fmt::print(stderr, "verdict_study: unknown mode or arguments\n");
  return 2;
}
