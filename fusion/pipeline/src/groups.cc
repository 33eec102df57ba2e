#include "wearscar/fusion/groups.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <Eigen/Dense>
#include <algorithm>
#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/non_central_t.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <map>
#include <set>

namespace wearscar::fusion {
namespace {

struct Unit {
  std::string name;
  double value = NAN;
  std::map<std::string, std::string> levels;
};

double TQuantile975(double df) {
  return boost::math::quantile(boost::math::students_t(df), 0.975);
}

double TwoSidedP(double t, double df) {
  return 2 * boost::math::cdf(boost::math::complement(
                 boost::math::students_t(df), std::fabs(t)));
}

const nlohmann::json* Find(const nlohmann::json& j,
                           std::initializer_list<const char*> path) {
  const nlohmann::json* at = &j;
  for (const char* key : path) {
    if (!at->is_object() || !at->contains(key)) return nullptr;
    at = &(*at)[key];
  }
  return at;
}

std::string Level(const nlohmann::json& row, const std::string& factor) {
  const nlohmann::json* f = Find(row, {"factors"});
  if (f && f->contains(factor) && (*f)[factor].is_string())
    return (*f)[factor].get<std::string>();
  if (row.contains(factor) && row[factor].is_string())
    return row[factor].get<std::string>();
  return "";
}

// Every factor a row names, in first appearance.
std::vector<std::string> FactorNames(const std::vector<nlohmann::json>& rows) {
  std::vector<std::string> names = {"species", "plane", "direction"};
  for (const nlohmann::json& row : rows) {
    const nlohmann::json* f = Find(row, {"factors"});
    if (!f || !f->is_object()) continue;
    for (const auto& [name, level] : f->items())
      if (std::find(names.begin(), names.end(), name) == names.end())
        names.push_back(name);
  }
  return names;
}

LevelStatistic Describe(const std::string& factor,
                        const std::string& level,
                        const std::vector<double>& v) {
  LevelStatistic s;
  s.factor = factor;
  s.level = level;
  s.n = static_cast<int>(v.size());
  s.values = v;
  double sum = 0;
  for (double x : v) sum += x;
  s.mean = s.n ? sum / s.n : NAN;
  double ss = 0;
  for (double x : v) ss += (x - s.mean) * (x - s.mean);
  s.sd = s.n > 1 ? std::sqrt(ss / (s.n - 1)) : NAN;
  const double half =
      s.n > 1 ? TQuantile975(s.n - 1) * s.sd / std::sqrt(s.n) : NAN;
  s.low = s.mean - half;
  s.high = s.mean + half;
  return s;
}

LevelDifference Welch(const std::string& factor,
                      const LevelStatistic& a,
                      const LevelStatistic& b) {
  LevelDifference d;
  d.factor = factor;
  d.level_a = a.level;
  d.level_b = b.level;
  d.test = "Welch";
  d.difference = b.mean - a.mean;
  const double va = a.sd * a.sd / a.n, vb = b.sd * b.sd / b.n;
  const double se = std::sqrt(va + vb);
  d.df = (va + vb) * (va + vb) / (va * va / (a.n - 1) + vb * vb / (b.n - 1));
  if (!(se > 0) || !std::isfinite(d.df)) {
    d.t = NAN;
    d.p = NAN;
    d.low = d.high = NAN;
    return d;
  }
  d.t = d.difference / se;
  d.p = TwoSidedP(d.t, d.df);
  const double half = TQuantile975(d.df) * se;
  d.low = d.difference - half;
  d.high = d.difference + half;
  return d;
}

// The levels of each factor among the specimens, sorted.
std::map<std::string, std::vector<std::string>> LevelsOf(
    const std::vector<Unit>& specimens,
    const std::vector<std::string>& factors) {
  std::map<std::string, std::vector<std::string>> out;
  for (const std::string& f : factors) {
    std::set<std::string> seen;
    for (const Unit& s : specimens) seen.insert(s.levels.at(f));
    out[f].assign(seen.begin(), seen.end());
  }
  return out;
}

// The premise of main effects alone checked against the groups' own
// means (a lack-of-fit F test: what the groups' means explain beyond the
// main effects, against the spread within groups): "" when they add
// nothing or cannot be told (a group with one specimen, no degrees of
// freedom within groups), else the sentence.
std::string Interaction(const std::vector<Unit>& specimens,
                        const std::vector<std::string>& factors,
                        double ss_main,
                        double df_main) {
  std::map<std::string, std::vector<double>> cells;
  for (const Unit& s : specimens) {
    std::string key;
    for (const std::string& f : factors) key += s.levels.at(f) + "\x1f";
    cells[key].push_back(s.value);
  }
  double ss_within = 0;
  for (const auto& [key, v] : cells) {
    double mean = 0;
    for (double x : v) mean += x / v.size();
    for (double x : v) ss_within += (x - mean) * (x - mean);
  }
  const double df_within =
      static_cast<double>(specimens.size()) - static_cast<double>(cells.size());
  const double df_extra = df_main - df_within;
  if (df_within < 1 || df_extra < 1 || !(ss_within > 0)) return "";
  const double f = ((ss_main - ss_within) / df_extra) / (ss_within / df_within);
  const double p = boost::math::cdf(boost::math::complement(
      boost::math::fisher_f(df_extra, df_within), std::max(f, 0.0)));
  if (p >= 0.05) return "";
  return fmt::format(
      "; but the factors interact (the groups' means differ beyond the main "
      "effects, F = {:.3g}, p = {:.2g}): each difference is an average over "
      "the other factors' levels, and the groups' table says where it "
      "holds",
      f,
      p);
}

// A term of the linear model: the factors (indices into the factor list)
// whose product it is; one factor: its main effect.
using Term = std::vector<size_t>;

// The terms of the model: the main effects, and with `interactions` the
// product of every set of factors that is crossed among the specimens
// (each combination of those factors' levels holds one; two factors:
// a x b; three: the pairs crossed and the triple if crossed).
std::vector<Term> Terms(
    const std::vector<Unit>& specimens,
    const std::vector<std::string>& factors,
    const std::map<std::string, std::vector<std::string>>& levels,
    bool interactions) {
  std::vector<Term> terms;
  for (size_t f = 0; f < factors.size(); ++f) terms.push_back({f});
  if (!interactions || factors.size() > 8) return terms;
  for (size_t size = 2; size <= factors.size(); ++size) {
    for (unsigned mask = 0; mask < (1u << factors.size()); ++mask) {
      if (static_cast<size_t>(__builtin_popcount(mask)) != size) continue;
      Term t;
      size_t combinations = 1;
      for (size_t f = 0; f < factors.size(); ++f)
        if (mask & (1u << f))
          t.push_back(f), combinations *= levels.at(factors[f]).size();
      std::set<std::string> seen;
      for (const Unit& s : specimens) {
        std::string key;
        for (size_t f : t) key += s.levels.at(factors[f]) + "\x1f";
        seen.insert(key);
      }
      if (seen.size() == combinations) terms.push_back(t);
    }
  }
  return terms;
}

// The design matrix in sum-to-zero (effects) coding: a factor of L levels
// gives L-1 columns, its level j < L-1 +1 in column j and its last level
// -1 in each; an interaction's columns are the products of its factors'.
// Then a level's main effect is its column's coefficient (the last level's
// minus their sum), and the difference of two levels' effects is the
// difference of their marginal means averaged evenly over the other
// factors' levels, with or without the interactions in the model.
struct Design {
  Eigen::MatrixXd x;
  std::vector<std::pair<int, int>> columns;  // per term: first, count
};

Design BuildDesign(
    const std::vector<Unit>& specimens,
    const std::vector<std::string>& factors,
    const std::map<std::string, std::vector<std::string>>& levels,
    const std::vector<Term>& terms) {
  Design d;
  int p = 1;
  for (const Term& t : terms) {
    int count = 1;
    for (size_t f : t)
      count *= static_cast<int>(levels.at(factors[f]).size()) - 1;
    d.columns.push_back({p, count});
    p += count;
  }
  const Eigen::Index n = static_cast<Eigen::Index>(specimens.size());
  d.x = Eigen::MatrixXd::Zero(n, p);
  for (Eigen::Index i = 0; i < n; ++i) {
    d.x(i, 0) = 1;
    for (size_t k = 0; k < terms.size(); ++k) {
      std::vector<double> v = {1.0};
      for (size_t f : terms[k]) {
        const auto& lv = levels.at(factors[f]);
        const size_t at = static_cast<size_t>(
            std::find(
                lv.begin(), lv.end(), specimens[i].levels.at(factors[f])) -
            lv.begin());
        std::vector<double> coded(lv.size() - 1, 0.0);
        for (size_t j = 0; j < coded.size(); ++j)
          coded[j] = at == j ? 1.0 : at + 1 == lv.size() ? -1.0 : 0.0;
        std::vector<double> product;
        for (double a : v)
          for (double b : coded) product.push_back(a * b);
        v = std::move(product);
      }
      for (size_t j = 0; j < v.size(); ++j)
        d.x(i, d.columns[k].first + static_cast<int>(j)) = v[j];
    }
  }
  return d;
}

double ResidualSquares(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) {
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(x);
  return (y - x * qr.solve(y)).squaredNorm();
}

// Each interaction term tested against the full model (the term's columns
// dropped: its F on the residual spread); "" when none is in the model.
std::string InteractionTests(const Design& d,
                             const Eigen::VectorXd& y,
                             const std::vector<std::string>& factors,
                             const std::vector<Term>& terms,
                             double rss,
                             double df,
                             GroupComparison* c) {
  std::vector<std::string> said, interacting;
  for (size_t k = 0; k < terms.size(); ++k) {
    if (terms[k].size() < 2) continue;
    const auto [first, count] = d.columns[k];
    Eigen::MatrixXd reduced(d.x.rows(), d.x.cols() - count);
    reduced << d.x.leftCols(first), d.x.rightCols(d.x.cols() - first - count);
    TermTest t;
    for (size_t f : terms[k])
      t.term += (t.term.empty() ? "" : " x ") + factors[f];
    t.df1 = count;
    t.df2 = df;
    t.f = ((ResidualSquares(reduced, y) - rss) / count) / (rss / df);
    t.p = boost::math::cdf(boost::math::complement(
        boost::math::fisher_f(t.df1, t.df2), std::max(t.f, 0.0)));
    said.push_back(fmt::format("{} F = {:.3g}, p = {:.2g}", t.term, t.f, t.p));
    if (t.p < 0.05) interacting.push_back(t.term);
    c->interactions.push_back(t);
  }
  if (said.empty()) return "";
  std::string s = fmt::format("; interactions: {}", fmt::join(said, "; "));
  if (!interacting.empty())
    s += fmt::format(
        "; the factors interact ({}): each difference is an average over "
        "the other factors' levels, and the groups' table says where it "
        "holds",
        fmt::join(interacting, ", "));
  return s;
}

// The factors' effects fitted by least squares, with the interactions of
// the factors crossed among the specimens (Terms) where the design
// identifies them and leaves two degrees of freedom for the spread, else
// main effects alone: the
// differences between every two levels of a factor (their marginal means,
// averaged evenly over the other factors' levels), tested on the residual
// spread. Returns false (the design does not identify the effects, or
// leaves too few degrees of freedom) so that the caller falls back to
// Welch.
bool LinearModel(const std::vector<Unit>& specimens,
                 const std::vector<std::string>& factors,
                 bool interactions,
                 GroupComparison* c) {
  const auto levels = LevelsOf(specimens, factors);
  const std::vector<Term> terms =
      Terms(specimens, factors, levels, interactions);
  interactions = terms.size() > factors.size();
  const Design design = BuildDesign(specimens, factors, levels, terms);
  const Eigen::MatrixXd& x = design.x;
  const int n = static_cast<int>(specimens.size());
  const int p = static_cast<int>(x.cols());
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(x);
  if (n - p < 2 || qr.rank() < p)  // main effects alone, or Welch
    return interactions && LinearModel(specimens, factors, false, c);
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) y(i) = specimens[i].value;
  const Eigen::VectorXd beta = qr.solve(y);
  const double df = n - p;
  const double rss = (y - x * beta).squaredNorm(), s2 = rss / df;
  const Eigen::MatrixXd cov = (x.transpose() * x).inverse() * s2;
  std::vector<std::string> products;
  for (const Term& t : terms) {
    if (t.size() < 2) continue;
    std::vector<std::string> names;
    for (size_t f : t) names.push_back(factors[f]);
    products.push_back(fmt::format("{}", fmt::join(names, " x ")));
  }
  const bool all =
      products.size() == (size_t{1} << factors.size()) - factors.size() - 1;
  c->test = fmt::format(
      "linear model of the specimens' values on {} ({}; residual spread "
      "{:.3g} on {} degrees of freedom){}",
      fmt::join(factors, all ? " * " : " + "),
      !interactions ? std::string("main effects")
      : all ? std::string("main effects and their interactions, the design "
                          "crossed")
            : fmt::format("main effects and the interactions of the factors "
                          "crossed: {}",
                          fmt::join(products, ", ")),
      std::sqrt(s2),
      n - p,
      interactions ? InteractionTests(design, y, factors, terms, rss, df, c)
                   : Interaction(specimens, factors, rss, df));
  c->plan.sd_between = std::sqrt(s2);
  for (size_t f = 0; f < factors.size(); ++f) {
    const auto& lv = levels.at(factors[f]);
    const int first = design.columns[f].first;
    // A level's main effect as a combination of the coefficients.
    auto effect = [&](size_t l) {
      Eigen::VectorXd w = Eigen::VectorXd::Zero(p);
      if (l + 1 < lv.size())
        w(first + static_cast<int>(l)) = 1;
      else
        w.segment(first, static_cast<int>(lv.size()) - 1).setConstant(-1);
      return w;
    };
    for (size_t a = 0; a < lv.size(); ++a) {
      for (size_t b = a + 1; b < lv.size(); ++b) {
        const Eigen::VectorXd w = effect(b) - effect(a);
        LevelDifference d;
        d.factor = factors[f];
        d.level_a = lv[a];
        d.level_b = lv[b];
        d.test = "linear model";
        d.difference = w.dot(beta);
        const double se = std::sqrt(w.dot(cov * w));
        d.df = df;
        d.t = se > 0 ? d.difference / se : NAN;
        d.p = se > 0 ? TwoSidedP(d.t, df) : NAN;
        d.low = d.difference - TQuantile975(df) * se;
        d.high = d.difference + TQuantile975(df) * se;
        c->differences.push_back(d);
      }
    }
  }
  return true;
}

void WelchDifferences(const std::vector<Unit>& specimens,
                      const std::vector<std::string>& factors,
                      GroupComparison* c) {
  c->test =
      "Welch's t test between each two levels of a factor (over the "
      "other factors' levels together)";
  double pooled = 0;
  int pooled_df = 0;
  for (const LevelStatistic& s : c->levels) {
    if (s.factor != factors.front() || s.n < 2) continue;
    pooled += s.sd * s.sd * (s.n - 1);
    pooled_df += s.n - 1;
  }
  c->plan.sd_between = pooled_df > 0 ? std::sqrt(pooled / pooled_df) : NAN;
  for (const std::string& f : factors) {
    std::vector<const LevelStatistic*> lv;
    for (const LevelStatistic& s : c->levels)
      if (s.factor == f) lv.push_back(&s);
    for (size_t a = 0; a < lv.size(); ++a)
      for (size_t b = a + 1; b < lv.size(); ++b)
        if (lv[a]->n > 1 && lv[b]->n > 1)
          c->differences.push_back(Welch(f, *lv[a], *lv[b]));
  }
  (void)specimens;
}

void Plan(const GroupOptions& o, ReplicatePlan* plan) {
  plan->difference = o.plan_difference;
  plan->power = o.plan_power;
  if (!(plan->sd_between > 0)) {
    plan->said =
        "no replicates planned: the specimens' spread could not be measured "
        "(each group needs two specimens)";
    return;
  }
  for (int n = 2; n <= 1000; ++n) {
    if (TwoGroupPower(o.plan_difference, plan->sd_between, n) >= o.plan_power) {
      plan->replicates = n;
      break;
    }
  }
  plan->said =
      plan->replicates > 0
          ? fmt::format(
                "to find a difference of {:g} in mu between two groups "
                "with {:.0f}% power (two-sided, 5% level) at the spread "
                "measured between specimens ({:.2g}): {} specimens per "
                "group",
                o.plan_difference,
                100 * o.plan_power,
                plan->sd_between,
                plan->replicates)
          : fmt::format(
                "a difference of {:g} in mu cannot be found with {:.0f}% "
                "power with 1000 specimens per group at the spread measured "
                "({:.2g})",
                o.plan_difference,
                100 * o.plan_power,
                plan->sd_between);
}

GroupComparison Compare(const std::vector<nlohmann::json>& rows,
                        const GroupOptions& o,
                        const std::string& quantity,
                        std::initializer_list<const char*> path) {
  GroupComparison c;
  c.quantity = quantity;
  std::vector<Unit> specimens;
  for (const nlohmann::json& row : rows) {
    const std::string name = row.value("specimen", std::string("?"));
    const nlohmann::json* v = Find(row, path);
    // NaN (no value) is a number to the JSON in memory, null once written.
    if (!v || !v->is_number() || !std::isfinite(v->get<double>())) {
      const nlohmann::json* reason = Find(row, {"quote", "status"});
      c.left_out.push_back(fmt::format(
          "{} ({})",
          name,
          row.contains("error")       ? "failed"
          : quantity != "mu_to_quote" ? "no wear rate: no usable scan"
          : reason && reason->is_string()
              ? "no mu to quote: " + reason->get<std::string>()
              : "no mu to quote"));
      continue;
    }
    Unit s{name, v->get<double>(), {}};
    for (const std::string& f : FactorNames(rows)) s.levels[f] = Level(row, f);
    specimens.push_back(std::move(s));
  }
  // The factors: those asked for, else every one with two levels or more.
  std::vector<std::string> factors = o.factors;
  if (factors.empty()) {
    for (const std::string& f : FactorNames(rows)) {
      std::set<std::string> seen;
      for (const Unit& s : specimens)
        if (!s.levels.at(f).empty()) seen.insert(s.levels.at(f));
      if (seen.size() > 1) factors.push_back(f);
    }
  }
  c.factors = factors;
  std::vector<Unit> kept;
  for (Unit& s : specimens) {
    std::string missing;
    for (const std::string& f : factors)
      if (s.levels[f].empty()) missing = f;
    if (missing.empty())
      kept.push_back(std::move(s));
    else
      c.left_out.push_back(fmt::format("{} (no {})", s.name, missing));
  }
  if (factors.empty() || kept.size() < 2) {
    c.abstained =
        factors.empty()
            ? "no factor has two levels among the specimens (the name "
              "pattern's named groups, a manifest's columns or --factors "
              "name them)"
            : "fewer than two specimens to compare";
    if (quantity == "mu_to_quote") Plan(o, &c.plan);
    return c;
  }
  std::map<std::string, std::map<std::string, std::vector<double>>> by;
  std::map<std::string, std::vector<double>> cells;
  for (const Unit& s : kept) {
    std::vector<std::string> cell;
    for (const std::string& f : factors) {
      by[f][s.levels.at(f)].push_back(s.value);
      cell.push_back(s.levels.at(f));
    }
    cells[fmt::format("{}", fmt::join(cell, ", "))].push_back(s.value);
  }
  for (const std::string& f : factors)
    for (const auto& [level, v] : by[f])
      c.levels.push_back(Describe(f, level, v));
  if (factors.size() > 1)
    for (const auto& [cell, v] : cells)
      c.levels.push_back(Describe("group", cell, v));
  if (factors.size() < 2 || !LinearModel(kept, factors, true, &c))
    WelchDifferences(kept, factors, &c);
  if (quantity == "mu_to_quote") Plan(o, &c.plan);
  return c;
}

std::string Number(double v, const char* format = "{:.6g}") {
  return std::isfinite(v) ? fmt::format(fmt::runtime(format), v)
                          : std::string();
}

std::string Cell(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string Tex(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '_' || c == '%' || c == '&' || c == '#') out += '\\';
    out += c;
  }
  return out;
}

}  // namespace

bool GroupOptions::IsValid(std::string* why) const {
  if (!(plan_difference > 0)) {
    if (why) *why = "the planned difference must be above 0";
    return false;
  }
  if (!(plan_power > 0.05 && plan_power < 1)) {
    if (why) *why = "the planned power must be between 0.05 and 1";
    return false;
  }
  return true;
}

double TwoGroupPower(double difference, double sd, int n) {
  if (n < 2 || !(sd > 0)) return NAN;
  const double df = 2.0 * n - 2;
  const double delta = std::fabs(difference) / (sd * std::sqrt(2.0 / n));
  const double t = TQuantile975(df);
  const boost::math::non_central_t nct(df, delta);
  return boost::math::cdf(boost::math::complement(nct, t)) +
         boost::math::cdf(nct, -t);
}

std::vector<GroupComparison> CompareGroups(
    const std::vector<nlohmann::json>& rows, const GroupOptions& o) {
  return {Compare(rows, o, "mu_to_quote", {"quote", "mu"}),
          Compare(rows,
                  o,
                  "specific_wear_rate_mm3_per_N_m",
                  {"wear", "specific_wear_rate_mm3_per_n_m"})};
}

std::string GroupsCsv(const std::vector<GroupComparison>& comparisons) {
  std::string csv =
      "quantity,factor,level,specimens,mean,sd_between_specimens,mean_low95,"
      "mean_high95\n";
  for (const GroupComparison& c : comparisons) {
    for (const LevelStatistic& s : c.levels) {
      csv += fmt::format("{},{},{},{},{},{},{},{}\n",
                         c.quantity,
                         Cell(s.factor),
                         Cell(s.level),
                         s.n,
                         Number(s.mean),
                         Number(s.sd),
                         Number(s.low),
                         Number(s.high));
    }
  }
  return csv;
}

std::string GroupDifferencesCsv(
    const std::vector<GroupComparison>& comparisons) {
  std::string csv =
      "quantity,factor,level_a,level_b,difference_b_minus_a,low95,high95,"
      "df,t,p,different_at_5pct,test\n";
  for (const GroupComparison& c : comparisons) {
    for (const LevelDifference& d : c.differences) {
      csv += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{}\n",
                         c.quantity,
                         Cell(d.factor),
                         Cell(d.level_a),
                         Cell(d.level_b),
                         Number(d.difference),
                         Number(d.low),
                         Number(d.high),
                         Number(d.df, "{:.4g}"),
                         Number(d.t, "{:.4g}"),
                         Number(d.p, "{:.3g}"),
                         d.Different() ? "true" : "false",
                         Cell(d.test == "Welch" ? d.test : c.test));
    }
  }
  return csv;
}

std::string GroupsLatex(const std::vector<GroupComparison>& comparisons) {
  std::string t =
      "% wearscar audit: groups compared with the specimen as the unit\n";
  for (const GroupComparison& c : comparisons) {
    if (c.levels.empty()) continue;
    const bool mu = c.quantity == "mu_to_quote";
    const char* f = mu ? "{:.4f}" : "{:.3g}";
    t += fmt::format(
        "\\begin{{table}}\n\\centering\n\\caption{{{}: mean over the "
        "specimens, spread between them (SD) and the mean's 95\\% "
        "interval.}}\n\\begin{{tabular}}{{llrrrl}}\n\\hline\nFactor & Level & "
        "$n$ & Mean & SD & 95\\% interval \\\\\n\\hline\n",
        mu ? "Coefficient of friction $\\hat\\mu$"
           : "Specific wear rate (mm$^3$/(N\\,m))");
    for (const LevelStatistic& s : c.levels) {
      t += fmt::format("{} & {} & {} & {} & {} & {}--{} \\\\\n",
                       Tex(s.factor),
                       Tex(s.level),
                       s.n,
                       Number(s.mean, f),
                       Number(s.sd, "{:.2g}"),
                       Number(s.low, f),
                       Number(s.high, f));
    }
    t += "\\hline\n\\end{tabular}\n\\end{table}\n";
    if (c.differences.empty()) continue;
    t += fmt::format(
        "\\begin{{table}}\n\\centering\n\\caption{{Differences in {} between "
        "levels ({}).}}\n\\begin{{tabular}}{{lllrrr}}\n\\hline\nFactor & A & "
        "B & B$-$A & 95\\% interval & $p$ \\\\\n\\hline\n",
        mu ? "$\\hat\\mu$" : "wear rate",
        Tex(c.test));
    for (const LevelDifference& d : c.differences) {
      t += fmt::format("{} & {} & {} & {} & {}--{} & {} \\\\\n",
                       Tex(d.factor),
                       Tex(d.level_a),
                       Tex(d.level_b),
                       Number(d.difference, f),
                       Number(d.low, f),
                       Number(d.high, f),
                       Number(d.p, "{:.2g}"));
    }
    t += "\\hline\n\\end{tabular}\n\\end{table}\n";
  }
  return t;
}

nlohmann::json GroupsJson(const std::vector<GroupComparison>& comparisons) {
  nlohmann::json out = nlohmann::json::array();
  for (const GroupComparison& c : comparisons) {
    nlohmann::json levels = nlohmann::json::array(),
                   diffs = nlohmann::json::array();
    for (const LevelStatistic& s : c.levels)
      levels.push_back({{"factor", s.factor},
                        {"level", s.level},
                        {"specimens", s.n},
                        {"mean", s.mean},
                        {"sd", s.sd},
                        {"interval95", {s.low, s.high}}});
    for (const LevelDifference& d : c.differences)
      diffs.push_back({{"factor", d.factor},
                       {"level_a", d.level_a},
                       {"level_b", d.level_b},
                       {"difference", d.difference},
                       {"interval95", {d.low, d.high}},
                       {"df", d.df},
                       {"p", d.p},
                       {"different", d.Different()}});
    nlohmann::json one = {{"quantity", c.quantity},
                          {"factors", c.factors},
                          {"levels", levels},
                          {"differences", diffs},
                          {"test", c.test},
                          {"left_out", c.left_out},
                          {"abstained", c.abstained}};
    one["interactions"] = nlohmann::json::array();
    for (const TermTest& t : c.interactions)
      one["interactions"].push_back({{"term", t.term},
                                     {"f", t.f},
                                     {"df", {t.df1, t.df2}},
                                     {"p", t.p},
                                     {"interacting", t.p < 0.05}});
    if (c.quantity == "mu_to_quote")
      one["plan"] = {{"sd_between_specimens", c.plan.sd_between},
                     {"difference", c.plan.difference},
                     {"power", c.plan.power},
                     {"replicates_per_group", c.plan.replicates},
                     {"said", c.plan.said}};
    out.push_back(std::move(one));
  }
  return out;
}

}  // namespace wearscar::fusion
