#pragma once

// Groups and factors of a batch compared with the specimen as the unit: a
// test's cycles are not independent replicates, so each specimen gives one
// value (its mu to quote, its specific wear rate) and the spread between
// specimens is the error. Per factor level and per group (a combination
// of the levels) the number of specimens, the mean, the spread and a 95%
// interval; the difference between each two levels of a factor with its
// interval and a test that fits the design; the replicates a difference
// needs to be found at a given power.
//
// Premises, checked and said: the specimens are independent replicates of
// their group (one value each); the spread between specimens is about the
// same in every group (the linear model's; Welch's test for one factor
// does not need it). Where the design is crossed and replicated the model
// holds the factors' interactions, each tested, and a level's effect is
// its marginal mean averaged evenly over the other factors' levels;
// otherwise the factors are taken to act additively (main effects), which
// the groups' own means check (a lack-of-fit F test, said).

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace wearscar::fusion {

struct GroupOptions {
  // The factors compared; empty: every factor (species, plane, direction,
  // a name pattern's groups, a manifest's columns) with two levels or more
  // among the specimens compared.
  std::vector<std::string> factors;
  // The planning line: the replicates per group that find this difference
  // in mu (two-sided, 5% level) with this power.
  double plan_difference = 0.005;
  double plan_power = 0.8;
  bool IsValid(std::string* why) const;
};

struct LevelStatistic {
  std::string factor;  // "species"; "group" for a combination of levels
  std::string level;   // "beech"; "beech, RT, R" for a group
  int n = 0;           // specimens
  double mean = 0, sd = 0, low = 0, high = 0;  // low/high: the mean's 95%
  std::vector<double> values;                  // the specimens'
};

struct LevelDifference {
  std::string factor, level_a, level_b;
  double difference = 0;  // b minus a
  double low = 0, high = 0, df = 0, t = 0, p = 1;
  std::string test;  // "Welch" or "linear model (species + plane + ...)"
  bool Different() const { return p < 0.05; }
};

// An interaction of factors in the linear model, tested against the full
// model (its columns dropped).
struct TermTest {
  std::string term;  // "species x plane"
  double f = NAN, df1 = 0, df2 = 0, p = NAN;
};

struct ReplicatePlan {
  double sd_between = 0;  // the spread between specimens the plan uses
  double difference = 0, power = 0;
  int replicates = 0;  // per group; 0 when it cannot be planned
  std::string said;    // the sentence
};

struct GroupComparison {
  std::string quantity;  // "mu_to_quote", "specific_wear_rate_mm3_per_N_m"
  std::vector<std::string> factors;
  std::vector<LevelStatistic> levels;  // per factor level, then per group
  std::vector<LevelDifference> differences;
  std::vector<std::string> left_out;   // "name (why)"
  std::string test;                    // how the differences were tested
  std::vector<TermTest> interactions;  // where the model holds them
  std::string abstained;  // why nothing was compared ("" when it was)
  ReplicatePlan plan;     // mu only
};

// The comparisons of the batch's rows (summary rows: result.json with
// the specimen's identity and factors, "error" for a failed one): mu to
// quote, then the specific wear rate.
std::vector<GroupComparison> CompareGroups(
    const std::vector<nlohmann::json>& rows, const GroupOptions& options);

// The power of a two-sided t test (5% level) between two groups of n
// specimens each whose means differ by `difference`, spread `sd`.
double TwoGroupPower(double difference, double sd, int n);

// groups.csv (levels and groups), group_differences.csv and groups.tex.
std::string GroupsCsv(const std::vector<GroupComparison>& comparisons);
std::string GroupDifferencesCsv(
    const std::vector<GroupComparison>& comparisons);
std::string GroupsLatex(const std::vector<GroupComparison>& comparisons);
nlohmann::json GroupsJson(const std::vector<GroupComparison>& comparisons);

}  // namespace wearscar::fusion
