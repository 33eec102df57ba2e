#include "wearscar/support/text.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace wearscar::support
