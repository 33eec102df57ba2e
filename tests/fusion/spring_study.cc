// A spring other than the one the analysis divides P by, given wrong or
// left at its default, on the simulator's rigs at noise 1 and 2 and three
// seeds (120 cycles, full-size scans): said as the stiffness it is, never
// as an effect the model misses nor as an elastic part; the right spring
// questioned on no clean run of the 12 cases; the paper's S-RL-R elastic
// part still named elastic. docs/method.md quotes the printed figures.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "common/simulated.h"
#include "wearscar/fusion/diagnose.h"
#include "wearscar/fusion/fuse.h"

namespace wearscar::fusion {
namespace {

constexpr double kDefault = 10.19;  // FrictionFitOptions' spring

samples::SimulationOptions Case(const std::string& name,
                                double noise,
                                int seed,
                                double rig_n_per_mm) {
  samples::SimulationOptions o = samples::PaperCase(name, false);
  o.cycles = 120;
  o.noise_scale = noise;
  o.seed = 1000 + seed;
  o.spring_n_per_mm = rig_n_per_mm;
  return o;
}

FuseOptions Used(double given_n_per_mm) {
  FuseOptions f;
  f.fit_lugre = false;
  if (given_n_per_mm > 0) {
    f.analysis.friction.slope.spring_n_per_mm = given_n_per_mm;
    f.spring_given = true;
  }
  return f;
}

// Whether anything the user reads blames the physics.
std::string BlamesThePhysics(const TestResult& r) {
  std::vector<std::string> said = r.warnings;
  said.push_back(Headline(r));
  said.insert(said.end(), r.verdict.reasons.begin(), r.verdict.reasons.end());
  for (const std::string& s : said) {
    for (const char* blame : {"misses an effect",
                              "elastic compliance",
                              "an elastic part of about",
                              "carries an elastic part"}) {
      if (s.find(blame) != std::string::npos) return s;
    }
  }
  return "";
}

struct Wrong {
  double used_over_rig;
  bool given;
};

// used / rig = 0.5, 2 and 2.5: a default of 10.19 N/mm on rigs of 20.4,
// 5.1 and 4.1 N/mm, or a given 5.1, 20.4 and 25.5 N/mm on a 10.19 N/mm
// rig.
TEST(SpringStudy, AWrongSpringIsSaidWithTheRigsStiffness) {
  int runs = 0, said = 0;
  double worst = 0;
  for (double noise : {1.0, 2.0}) {
    for (int seed = 0; seed < 3; ++seed) {
      for (const Wrong w : {Wrong{0.5, false},
                            Wrong{2.0, false},
                            Wrong{2.5, false},
                            Wrong{0.5, true},
                            Wrong{2.0, true},
                            Wrong{2.5, true}}) {
        const double rig = w.given ? kDefault : kDefault / w.used_over_rig;
        const double used = w.given ? kDefault * w.used_over_rig : kDefault;
        const sim::SimulatedTest t = sim::Simulate(
            Case(seed % 2 ? "S-RT-T" : "B-RT-R", noise, seed, rig));
        const TestResult r =
            AnalyzeTest(t.record, t.scan, Used(w.given ? used : 0));
        const SpringCheck& c = r.mismatch.Spring();
        const std::string what =
            fmt::format("noise {} seed {} rig {:.3g} used {:.3g} ({})",
                        noise,
                        seed,
                        rig,
                        used,
                        w.given ? "given" : "default");
        ++runs;
        said += c.contradicted;
        EXPECT_TRUE(c.contradicted) << what;
        const double error = c.ImpliedStiffness() / rig - 1;
        worst = std::max(worst, std::abs(error));
        EXPECT_NEAR(error, 0.0, 0.10) << what;
        EXPECT_EQ(BlamesThePhysics(r), "") << what;
        ASSERT_FALSE(r.warnings.empty()) << what;
        EXPECT_EQ(r.warnings[0].rfind("the spring's stiffness appears", 0), 0u)
            << what << ": " << r.warnings[0];
        fmt::print(
            "{}: implied {:.3g} N/mm ({:+.1f}%), elastic share {:.3f}, "
            "{}\n",
            what,
            c.ImpliedStiffness(),
            100 * error,
            c.elastic_share,
            Headline(r));
      }
    }
  }
  fmt::print("wrong springs said: {} of {}; worst stiffness error {:.1f}%\n",
             said,
             runs,
             100 * worst);
}

// The right spring, on every case at noise 1 and 2 and three seeds: never
// contradicted. S-RL-R carries the paper's elastic part: named elastic
// (the verdict's amplitude reason), its spring not questioned.
TEST(SpringStudy, TheRightSpringIsNotQuestionedAndTheElasticPartIsNamed) {
  int runs = 0, questioned = 0;
  for (const samples::SimulationOptions& paper : samples::PaperCases(true)) {
    for (double noise : {1.0, 2.0}) {
      for (int seed = 0; seed < 3; ++seed) {
        samples::SimulationOptions o = paper;
        o.cycles = 120;
        o.noise_scale = noise;
        o.seed = 2000 + seed;
        const sim::SimulatedTest t = sim::Simulate(o);
        const TestResult r = AnalyzeTest(t.record, t.scan, Used(0));
        const SpringCheck& c = r.mismatch.Spring();
        const std::string what =
            fmt::format("{} noise {} seed {}", o.name, noise, seed);
        ++runs;
        questioned += c.contradicted;
        EXPECT_FALSE(c.contradicted)
            << what << ": implied " << c.ImpliedStiffness();
        if (o.name == "S-RL-R") {
          EXPECT_TRUE(c.elastic) << what << ": share " << c.elastic_share;
          EXPECT_FALSE(r.verdict.explained) << what;
        }
      }
    }
  }
  fmt::print("right springs questioned: {} of {}\n", questioned, runs);
}

// The diagnosis names the spring's stiffness, with the rig's N/mm, where
// the track grew from nothing, and elastic compliance where P/S carried
// its part from the first cycle.
TEST(SpringStudy, TheDiagnosisNamesTheSpringOrTheElasticPartAsTheHistoryShows) {
  const sim::SimulatedTest t =
      sim::Simulate(Case("B-RT-R", 1, 0, kDefault * 2.5));
  const TestResult r = AnalyzeTest(t.record, t.scan, Used(0));
  const Diagnosis d = DiagnoseTest(t.record, r, Used(0));
  ASSERT_FALSE(d.named.empty()) << d.message;
  EXPECT_EQ(d.named.front(), "spring stiffness") << d.message;
  ASSERT_FALSE(d.model.empty());
  EXPECT_NEAR(d.model.front().parameters[0] * kDefault, kDefault * 2.5, 2.5)
      << d.message;
  EXPECT_NE(d.message.find("the rig's spring appears to be"), std::string::npos)
      << d.message;
  samples::SimulationOptions srlr = samples::PaperCase("S-RL-R", true);
  srlr.cycles = 120;
  const sim::SimulatedTest e = sim::Simulate(srlr);
  const TestResult re = AnalyzeTest(e.record, e.scan, Used(0));
  const Diagnosis de = DiagnoseTest(e.record, re, Used(0));
  ASSERT_FALSE(de.named.empty()) << de.message;
  EXPECT_EQ(de.named.front(), "elastic compliance of the track") << de.message;
}

}  // namespace
}  // namespace wearscar::fusion
