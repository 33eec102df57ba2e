#include "wearscar/support/text.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace wearscar::support {
namespace {

TEST(Lower, AsciiAndLatinCapitalsOtherBytesAsTheyAre) {
  EXPECT_EQ(Lower("Fx (N) Time_S"), "fx (n) time_s");
  EXPECT_EQ(Lower("Weg [\xC2\xB5M]"), "weg [\xC2\xB5m]");
  EXPECT_EQ(Lower("OBERFL\xC3\x84"
                  "CHE \xC3\x89T\xC3\x89"),
            "oberfl\xC3\xA4"
            "che \xC3\xA9t\xC3\xA9");
  EXPECT_EQ(Lower("\xC3\x97 \xC3"), "\xC3\x97 \xC3");  // x sign; cut
  EXPECT_EQ(Lower(""), "");
}

TEST(Trim, EveryKindOfBlankAtBothEndsOnly) {
  EXPECT_EQ(Trim(" \t x  y \r\n"), "x  y");
  EXPECT_EQ(Trim("\v\f"), "");
  EXPECT_EQ(Trim("a"), "a");
}

TEST(PrintableUtf8Length, WellFormedSequencesOnly) {
  EXPECT_EQ(PrintableUtf8Length("\xC2\xB5", 0), 2u);  // micro sign
  EXPECT_EQ(PrintableUtf8Length("\xC2\x85", 0), 0u);  // C1 control
  EXPECT_EQ(PrintableUtf8Length("\xE2\x82\xAC", 0), 3u);
  EXPECT_EQ(PrintableUtf8Length("\xED\xA0\x80", 0), 0u);  // surrogate
  EXPECT_EQ(PrintableUtf8Length("\xF0\x9F\x98\x80", 0), 4u);
  EXPECT_EQ(PrintableUtf8Length("\xF0\x9F\x98", 0), 0u);  // cut
  EXPECT_EQ(PrintableUtf8Length("\xB5", 0), 0u);          // Latin-1
  EXPECT_EQ(PrintableUtf8Length("a", 0), 0u);             // ASCII is 1 byte
}

TEST(Printable, KeepsUtf8AndEscapesOtherBytes) {
  EXPECT_EQ(Printable("Weg [\xC2\xB5m]"), "Weg [\xC2\xB5m]");
  EXPECT_EQ(Printable("\xB5m"), "\\xb5m");
  EXPECT_EQ(Printable("a\x01\xC2\x85z"), "a\\x01\\xc2\\x85z");
  EXPECT_EQ(Printable("\xED\xA0\x80"), "\\xed\\xa0\\x80");  // surrogate
  EXPECT_EQ(Printable("\xF0\x9F\x98\x80!"), "\xF0\x9F\x98\x80!");
  EXPECT_EQ(Printable("\xC2\xB5\xC2\xB5\xC2\xB5", 2), "\xC2\xB5\xC2\xB5...");
  EXPECT_EQ(Printable(std::string(50, 'x')), std::string(40, 'x') + "...");
}

// ToCharsGeneral's text against printf's for `v`, at `precision`.
std::string Ours(double v, int precision) {
  char cell[32];
  const auto r = ToCharsGeneral(cell, cell + sizeof cell, v, precision);
  return std::string(cell, r.ptr);
}

std::string Printf(double v, int precision) {
  char cell[64];
  std::snprintf(cell, sizeof cell, "%.*g", precision, v);
  return cell;
}

TEST(ToCharsGeneral, WritesWhatPrintfWritesForTheTablesNumbers) {
  EXPECT_EQ(Ours(-0.00098439826, 8), "-0.00098439826");
  EXPECT_EQ(Ours(0.15060002, 8), "0.15060002");
  EXPECT_EQ(Ours(2.5, 8), "2.5");
  EXPECT_EQ(Ours(123456789.0, 8), "1.2345679e+08");
  EXPECT_EQ(Ours(9.99999999e-5, 8), "0.0001");
  EXPECT_EQ(Ours(1.23e-5, 8), "1.23e-05");
  EXPECT_EQ(Ours(99999999.7, 8), "1e+08");
  EXPECT_EQ(Ours(-7.0, 8), "-7");
  // A tie at the ninth digit, exact in binary: printf rounds it to even.
  EXPECT_EQ(Ours(1234567.25, 8), Printf(1234567.25, 8));
  EXPECT_EQ(Ours(1234567.75, 8), Printf(1234567.75, 8));
  for (const double v : {0.0,
                         -0.0,
                         1e-300,
                         3e300,
                         1e15,
                         1e-15,
                         std::numeric_limits<double>::denorm_min(),
                         std::numeric_limits<double>::infinity(),
                         -std::numeric_limits<double>::infinity(),
                         std::numeric_limits<double>::quiet_NaN()})
    EXPECT_EQ(Ours(v, 8), Printf(v, 8)) << v;
}

TEST(ToCharsGeneral, AgreesWithPrintfOnMillionsOfValues) {
  std::mt19937_64 rng(20261129);
  std::uniform_real_distribution<double> unit(1.0, 10.0);
  std::uniform_int_distribution<int> exponent(-18, 18), digits(1, 9);
  std::vector<double> values;
  for (int i = 0; i < 150000; ++i) {
    const double v = unit(rng) * std::pow(10.0, exponent(rng));
    values.push_back(i % 2 ? v : -v);
    // Short decimals (k / 10^j) and their halves: exact ties and near ties
    // of the last digit kept.
    const double k = std::floor(unit(rng) * std::pow(10.0, digits(rng)));
    const double scale = std::pow(10.0, exponent(rng));
    values.push_back(k * scale);
    values.push_back((k + 0.5) * scale);
    values.push_back(std::nextafter((k + 0.5) * scale, 0.0));
    values.push_back(std::nextafter((k + 0.5) * scale, 1e300));
  }
  for (int x = -16; x <= 16; ++x) {  // powers of ten and their neighbours
    double v = std::pow(10.0, x);
    for (int step = 0; step < 4; ++step) v = std::nextafter(v, 0.0);
    for (int step = 0; step < 8; ++step, v = std::nextafter(v, 1e300))
      values.push_back(v);
  }
  int wrong = 0;
  for (const int precision : {8, 6, 12, 15, 1}) {
    for (const double v : values) {
      if (Ours(v, precision) == Printf(v, precision)) continue;
      if (++wrong <= 5)
        ADD_FAILURE() << "%." << precision << "g of " << Printf(v, 17) << ": "
                      << Ours(v, precision) << " against "
                      << Printf(v, precision);
    }
  }
  EXPECT_EQ(wrong, 0);
}

}  // namespace
}  // namespace wearscar::support
