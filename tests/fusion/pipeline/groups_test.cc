#include "wearscar/fusion/groups.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "wearscar/fusion/batch.h"
#include "wearscar/fusion/pairing.h"

namespace wearscar::fusion {
namespace {

// A summary row as an audit writes it: identity, factors, the quote and
// the wear rate.
nlohmann::json Row(const std::string& name,
                   const std::string& species,
                   const std::string& plane,
                   double mu,
                   double wear = NAN) {
  nlohmann::json row = {{"specimen", name},
                        {"species", species},
                        {"plane", plane},
                        {"direction", ""}};
  row["factors"] = {{"species", species}, {"plane", plane}, {"direction", ""}};
  // NaN as the analysis holds it in memory (null once written).
  row["quote"] = {{"status", std::isfinite(mu) ? "explained" : "not explained"},
                  {"mu", mu}};
  row["wear"] = {{"specific_wear_rate_mm3_per_n_m", wear}};
  return row;
}

const LevelDifference* Find(const GroupComparison& c, const std::string& f) {
  for (const auto& d : c.differences)
    if (d.factor == f) return &d;
  return nullptr;
}

// Many simulated batches of a crossed design (species x plane, n a cell)
// whose truth differs by `species_effect` between species only: the 95%
// intervals of the species' difference hold the truth about 95% of the
// time, and the plane's difference (none) is called different about 5% of
// the time.
TEST(Groups, IntervalsHoldTheTruthAndTheTestHoldsItsLevel) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 0.002);
  const double effect = 0.004;
  int covered = 0, plane_called = 0, species_found = 0;
  const int batches = 1000;
  for (int b = 0; b < batches; ++b) {
    std::vector<nlohmann::json> rows;
    for (const char* sp : {"beech", "spruce"})
      for (const char* pl : {"RT", "TL"})
        for (int r = 0; r < 4; ++r)
          rows.push_back(Row(
              "x", sp, pl, 0.12 + (sp[0] == 's' ? effect : 0) + noise(rng)));
    const GroupComparison mu = CompareGroups(rows, {})[0];
    ASSERT_EQ(mu.factors, (std::vector<std::string>{"species", "plane"}));
    const LevelDifference* s = Find(mu, "species");
    const LevelDifference* p = Find(mu, "plane");
    ASSERT_TRUE(s && p);
    // Crossed and replicated: the model holds the interaction, 16
    // specimens less 4 parameters (one per combination).
    EXPECT_EQ(s->df, 12);
    covered += s->low <= effect && effect <= s->high;
    species_found += s->Different();
    plane_called += p->Different();
  }
  EXPECT_NEAR(covered / double(batches), 0.95, 0.02);
  EXPECT_NEAR(plane_called / double(batches), 0.05, 0.02);
  // 8 specimens a species, spread 0.002, difference 0.004: power about 0.9.
  EXPECT_GT(species_found / double(batches), 0.8);
}

// The replicates planned find the difference at the power asked for in a
// simulation of that many, and one fewer does not.
TEST(Groups, ThePlannedReplicatesFindTheDifferenceAtThePowerAsked) {
  const double sd = 0.003, difference = 0.005;
  std::vector<nlohmann::json> rows;
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0, sd);
  for (const char* sp : {"beech", "spruce"})
    for (int r = 0; r < 40; ++r)
      rows.push_back(Row("x", sp, "", 0.1 + noise(rng)));
  GroupOptions o;
  o.plan_difference = difference;
  const GroupComparison mu = CompareGroups(rows, o)[0];
  const int n = mu.plan.replicates;
  ASSERT_GT(n, 2) << mu.plan.said;
  EXPECT_NEAR(mu.plan.sd_between, sd, 0.15 * sd);
  EXPECT_NE(mu.plan.said.find(std::to_string(n) + " specimens per group"),
            std::string::npos);
  // Batches of n a group at the measured spread: Welch finds the
  // difference at least as often as asked, n - 1 less often.
  auto found = [&](int per_group) {
    int hits = 0;
    const int batches = 2000;
    std::normal_distribution<double> spread(0, mu.plan.sd_between);
    for (int b = 0; b < batches; ++b) {
      std::vector<nlohmann::json> batch;
      for (int r = 0; r < per_group; ++r) {
        batch.push_back(Row("a", "beech", "", 0.1 + spread(rng)));
        batch.push_back(Row("b", "spruce", "", 0.1 + difference + spread(rng)));
      }
      hits += Find(CompareGroups(batch, o)[0], "species")->Different();
    }
    return hits / double(batches);
  };
  EXPECT_GT(found(n), 0.8 - 0.03);
  EXPECT_LT(found(n - 1), 0.8 + 0.01);
  EXPECT_NEAR(TwoGroupPower(difference, sd, n), 0.8, 0.08);
}

TEST(Groups, SpecimensWithoutAMuToQuoteAreLeftOutAndNamed) {
  std::vector<nlohmann::json> rows = {Row("a", "beech", "", 0.11, 0.03),
                                      Row("b", "beech", "", 0.112, 0.031),
                                      Row("c", "spruce", "", 0.13, 0.05),
                                      Row("d", "spruce", "", 0.131),
                                      Row("e", "spruce", "", NAN, 0.06)};
  rows.push_back({{"specimen", "f"}, {"error", "cannot read"}});
  const auto groups = CompareGroups(rows, {});
  const GroupComparison& mu = groups[0];
  EXPECT_EQ(mu.left_out,
            (std::vector<std::string>{"e (no mu to quote: not explained)",
                                      "f (failed)"}));
  ASSERT_EQ(mu.levels.size(), 2u);
  EXPECT_EQ(mu.levels[1].level, "spruce");
  EXPECT_EQ(mu.levels[1].n, 2);
  EXPECT_DOUBLE_EQ(mu.levels[1].mean, (0.13 + 0.131) / 2);
  EXPECT_EQ(Find(mu, "species")->test, "Welch");
  const GroupComparison& wear = groups[1];
  EXPECT_EQ(wear.quantity, "specific_wear_rate_mm3_per_N_m");
  EXPECT_EQ(wear.levels[1].n, 2);  // c and e
  // One factor only and its level for every specimen: no groups beyond it.
  const std::string csv = GroupsCsv(groups);
  EXPECT_NE(csv.find("mu_to_quote,species,spruce,2,0.1305,"), std::string::npos)
      << csv;
  EXPECT_NE(GroupsLatex(groups).find("spruce & 2 & 0.1305"), std::string::npos);
}

TEST(Groups, NothingToCompareIsSaid) {
  const auto groups = CompareGroups(
      {Row("a", "beech", "RT", 0.11), Row("b", "beech", "RT", 0.111)}, {});
  EXPECT_NE(groups[0].abstained.find("no factor has two levels"),
            std::string::npos);
  EXPECT_TRUE(groups[0].differences.empty());
}

TEST(Groups, AnInteractionIsSaid) {
  // Species matter on RT only.
  std::vector<nlohmann::json> rows;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.0005);
  for (const char* sp : {"beech", "spruce"})
    for (const char* pl : {"RT", "TL"})
      for (int r = 0; r < 4; ++r)
        rows.push_back(
            Row("x",
                sp,
                pl,
                0.12 + (sp[0] == 's' && pl[0] == 'R' ? 0.01 : 0) + noise(rng)));
  const GroupComparison mu = CompareGroups(rows, {})[0];
  EXPECT_NE(mu.test.find("the factors interact (species x plane)"),
            std::string::npos)
      << mu.test;
  ASSERT_EQ(mu.interactions.size(), 1u);
  EXPECT_EQ(mu.interactions[0].term, "species x plane");
  EXPECT_EQ(mu.interactions[0].df2, 12);
  EXPECT_LT(mu.interactions[0].p, 1e-6);
}

// Where the species differ on one plane only, the model with the
// interaction gives the species' difference averaged evenly over the
// planes (0.005 here) with an interval that holds it about 95% of the
// time; main effects alone would leave the interaction in the residual
// spread (intervals too wide, about 100% coverage). Unbalanced cells (3
// and 5 specimens) make the even average differ from the pooled one.
TEST(Groups, AnInteractionIsFittedAndTheEffectsAveragedOverTheOtherLevels) {
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0, 0.002);
  int covered = 0, found = 0, plane_covered = 0;
  const int batches = 1000;
  for (int b = 0; b < batches; ++b) {
    std::vector<nlohmann::json> rows;
    for (const char* sp : {"beech", "spruce"})
      for (const char* pl : {"RT", "TL"}) {
        const int n = sp[0] == 'b' && pl[0] == 'R' ? 3 : 5;
        for (int r = 0; r < n; ++r)
          rows.push_back(Row(
              "x",
              sp,
              pl,
              0.12 + (sp[0] == 's' && pl[0] == 'R' ? 0.01 : 0) + noise(rng)));
      }
    const GroupComparison mu = CompareGroups(rows, {})[0];
    const LevelDifference* s = Find(mu, "species");
    const LevelDifference* p = Find(mu, "plane");
    ASSERT_TRUE(s && p);
    EXPECT_EQ(s->df, 14);  // 18 specimens less 4 combinations
    covered += s->low <= 0.005 && 0.005 <= s->high;
    // TL minus RT: -0.005 averaged over the species.
    plane_covered += p->low <= -0.005 && -0.005 <= p->high;
    found += !mu.interactions.empty() && mu.interactions[0].p < 0.05;
  }
  EXPECT_NEAR(covered / double(batches), 0.95, 0.02);
  EXPECT_NEAR(plane_covered / double(batches), 0.95, 0.02);
  EXPECT_GT(found / double(batches), 0.95);
  // A design not crossed (no spruce on TL): main effects, and the
  // lack-of-fit check cannot run (no combination to compare with).
  std::vector<nlohmann::json> rows;
  for (int r = 0; r < 3; ++r) {
    rows.push_back(Row("a", "beech", "RT", 0.12 + 0.001 * r));
    rows.push_back(Row("b", "beech", "TL", 0.125 + 0.001 * r));
    rows.push_back(Row("c", "spruce", "RT", 0.13 + 0.001 * r));
  }
  const GroupComparison mu = CompareGroups(rows, {})[0];
  EXPECT_NE(mu.test.find("species + plane (main effects;"), std::string::npos)
      << mu.test;
  EXPECT_TRUE(mu.interactions.empty());
  EXPECT_NEAR(Find(mu, "species")->difference, 0.01, 1e-12);
}

TEST(Naming, NamedGroupsAndManifestColumnsFillTheFactors) {
  const NamedPattern p =
      ParseNamedPattern(R"((?<species>oak|ash)_(?:run)(\d+)_(?<load>\d+N)[(])");
  EXPECT_EQ(p.regex, R"((oak|ash)_(?:run)(\d+)_(\d+N)[(])");
  EXPECT_EQ(p.names, (std::vector<std::string>{"species", "", "load"}));
  BatchOptions o;
  o.name_pattern = R"((?<species>oak|ash)_run\d+_(?<load>\d+N))";
  Specimen s;
  s.name = "ash_run03_30N";
  nlohmann::json id = SpecimenIdentity(s, o);
  EXPECT_EQ(id["species"], "ash");
  EXPECT_EQ(id["factors"]["load"], "30N");
  s.factors = {{"load", "35 N"}, {"operator", "AB"}};
  id = SpecimenIdentity(s, o);
  EXPECT_EQ(id["factors"]["load"], "35 N");  // the manifest's column wins
  EXPECT_EQ(id["factors"]["operator"], "AB");
  EXPECT_EQ(ExtraFactors({id}), (std::vector<std::string>{"load", "operator"}));
  // The paper's naming and a lab's in words, without a pattern.
  BatchOptions plain;
  for (const auto& [name, species, plane, direction] :
       std::vector<std::array<std::string, 4>>{
           {"B-RT-R_rep1", "beech", "RT", "R"},
           {"Buche_RT-R_probe01", "beech", "RT", "R"},
           {"fichte-tl-l", "spruce", "TL", "L"},
           {"S-RL-Rx", "", "", ""}}) {
    Specimen t;
    t.name = name;
    const nlohmann::json j = SpecimenIdentity(t, plain);
    EXPECT_EQ(j["species"], species) << name;
    EXPECT_EQ(j["plane"], plane) << name;
    EXPECT_EQ(j["direction"], direction) << name;
  }
}

}  // namespace
}  // namespace wearscar::fusion
