#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "wearscar/fusion/fuse.h"
#include "wearscar/samples/virtual_tribometer.h"
using namespace wearscar;
int main(int argc, char** argv) {
  std::string name = argv[1];
  double noise = atof(argv[2]);
  double el = atof(argv[3]);
  int cycles = argc > 4 ? atoi(argv[4]) : 600;
  int seed = argc > 5 ? atoi(argv[5]) : 0;
  std::string est = argc > 6 ? argv[6] : "ensemble";
  samples::SimulationOptions o = samples::PaperCase(name, false);
  o.cycles = cycles;
  o.noise_scale = noise;
  o.elastic_fraction = el;
  o.seed += 1000 * seed;
  auto t0 = std::chrono::steady_clock::now();
  auto t = samples::Simulate(o);
  auto t1 = std::chrono::steady_clock::now();
  fusion::FuseOptions f;
  f.fit_lugre = false;
  fusion::ParseKEstimate(est, &f.analysis.friction.k_estimate);
  for (int withscan = 0; withscan < 2; ++withscan) {
    auto r = withscan ? fusion::AnalyzeTest(t.record, t.scan, f)
                      : fusion::AnalyzeTest(t.record, std::nullopt, f);
    const auto& m = r.mismatch;
    const auto& sf = m.split_force;
    double truth = 0;
    for (int c = m.first_cycle; c <= m.last_cycle; ++c)
      truth += t.truth.mu_per_cycle[c];
    truth /= (m.last_cycle - m.first_cycle + 1);
    printf(
        "%s n%.2f el%.2f s%d scan%d | J %.3f floor %.3f exc %.3f [%.3f %.3f] | "
        "Jscan %.3f fl %.3f exc %.3f [%.3f] | ratio %.3f [%.3f %.3f] | dmu "
        "%.4f [%.4f %.4f] | muerr %.4f kSNR %.4f/%.4f | %s\n",
        name.c_str(),
        noise,
        el,
        seed,
        withscan,
        sf.cost,
        sf.floor,
        sf.excess,
        sf.excess_low,
        sf.excess_high,
        m.split_scan.cost,
        m.split_scan.floor,
        m.split_scan.excess,
        m.split_scan.excess_low,
        m.amplitude_ratio,
        m.amplitude_ratio_low,
        m.amplitude_ratio_high,
        m.method_difference.mean,
        m.method_difference.low,
        m.method_difference.high,
        m.mu_force.mean - truth,
        r.force.k_signal_rms,
        r.force.k_noise_rms,
        r.verdict.explained ? "explained" : r.verdict.Summary().c_str());
  }
  auto t2 = std::chrono::steady_clock::now();
  fprintf(stderr,
          "sim %.2f s, analyse %.2f s\n",
          std::chrono::duration<double>(t1 - t0).count(),
          std::chrono::duration<double>(t2 - t1).count());
}
