// A lab's own program on the installed package. Without arguments: levels a
// tilted plane (wearscar::scan, PCL inside) and fits mu on samples made by
// the wear-scar model (wearscar::fusion), exit 0 when both come back.
// With FORCE SCAN NAME OUT: what `wearscar fuse --no-figures` writes, through
// the public API only; with audit INPUT OUT, what `wearscar audit --no-figures`
// writes (tests/install_consumer.sh compares the folders).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "wearscar/force/read_force.h"
#include "wearscar/fusion/fit_mu.h"
#include "wearscar/fusion/forward_model.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/products.h"
#include "wearscar/report/audit.h"
#include "wearscar/scan/level.h"
#include "wearscar/scan/read_scan.h"

namespace {

int LevelAndFit() {
  wearscar::scan::HeightMap map;
  map.dx_mm = map.dy_mm = 0.01;
  map.height_mm.resize(64, 96);
  for (int r = 0; r < 64; ++r)
    for (int c = 0; c < 96; ++c)
      map.height_mm(r, c) =
          static_cast<float>(0.002 * c * 0.01 - 0.001 * r * 0.01);
  wearscar::scan::SyncValidity(&map);
  const auto level = wearscar::scan::LevelHeightMap(&map);

  wearscar::fusion::CycleSamples s;
  const double mu = 0.12;
  for (auto* d : {&s.forward, &s.reverse}) {
    d->direction = d == &s.forward ? +1 : -1;
    d->q_n.resize(200);
    d->p_n.resize(200);
    d->k.resize(200);
    d->x_mm.resize(200);
    for (int i = 0; i < 200; ++i) {
      d->x_mm[i] = -2.5 + 5.0 * i / 199;
      d->k[i] = 0.1 * std::cos(d->x_mm[i] * 4);
      d->p_n[i] = 30;
      d->q_n[i] = wearscar::fusion::WearScarTangentialForce(
          d->p_n[i], d->k[i], mu, d->direction);
    }
  }
  const auto fit = wearscar::fusion::FitMu(s);
  std::printf("dz/dx %.5f, dz/dy %.5f; %s\n",
              level.dzdx(),
              level.dzdy(),
              fit.BriefReport().c_str());
  const bool ok = std::abs(level.dzdx() - 0.002) < 1e-6 &&
                  std::abs(level.dzdy() + 0.001) < 1e-6 &&
                  std::abs(fit.mu_hat - mu) < 1e-6;
  return ok ? 0 : 1;
}

// What `wearscar fuse --force FORCE --scan SCAN --no-figures -o OUT` writes.
int Fuse(const std::string& force_file,
         const std::string& scan_file,
         const std::string& name,
         const std::string& out) {
  namespace ws = wearscar;
  const ws::force::ForceRecord record = ws::force::ReadForceFile(force_file);
  ws::scan::HeightMap map = ws::scan::ReadScan(scan_file);
  ws::fusion::FuseOptions options;
  options.friction_map.loop_bins = 0;  // --no-figures: no loop viewer
  const ws::fusion::TestResult result =
      ws::fusion::AnalyzeTest(record, std::move(map), options);
  for (const auto& [file, text] :
       ws::fusion::MakeTestProducts(name, record, result, options).Files()) {
    std::ofstream(out + "/" + file, std::ios::binary) << text;
  }
  std::printf("%s: %s\n", name.c_str(), result.verdict.Summary().c_str());
  return 0;
}

// What `wearscar audit INPUT --no-figures -o OUT` writes.
int Audit(const std::string& input, const std::string& out) {
  namespace ws = wearscar;
  ws::report::AuditOptions options;
  options.figures = false;
  options.fuse.friction_map.loop_bins = 0;  // --no-figures: no loop viewer
  const auto specimens = ws::fusion::FindSpecimens(input, options.batch);
  const auto audit =
      ws::report::Audit(specimens, out, "wearscar audit of " + input, options);
  std::printf("%zu specimens, %d not explained, %d failed: %s\n",
              audit.specimens.size(),
              audit.flagged,
              audit.failed,
              audit.report_path.c_str());
  return audit.failed == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 5) return Fuse(argv[1], argv[2], argv[3], argv[4]);
  if (argc == 4 && std::string(argv[1]) == "audit")
    return Audit(argv[2], argv[3]);
  return LevelAndFit();
}
