// The same test written the ways real exports write it: text columns the
// method does not use, spreadsheets' missing-value markers, a micro sign in
// Latin-1 or Shift-JIS, UTF-16 text, German and French column names, and a
// time column of dates and times of day. Each is read to the numbers of the
// plain UTF-8 file (or refused with the place and what was expected).

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "wearscar/force/read_force.h"
#include "wearscar/support/text.h"

namespace wearscar::force {
namespace {

// 2 s of a 1 Hz, +-2.85 mm stroke at 2 kHz (4000 rows), mu = 0.12 on a
// wavy P: the cells of each row (time, x, Q, P) as plain decimals.
struct Row {
  double t, x, q, p;
};
std::vector<Row> Rows(int n = 4000, double rate = 2000) {
  std::vector<Row> rows;
  for (int i = 0; i < n; ++i) {
    const double t = i / rate, x = 2.85 * std::sin(2 * M_PI * t);
    const double p = 30 + 0.3 * std::sin(2 * M_PI * x / 1.7);
    rows.push_back({t, x, 0.12 * p * (std::cos(2 * M_PI * t) > 0 ? 1 : -1), p});
  }
  return rows;
}

// A file of the rows: `header`, then per row `format(row)`.
std::string Text(const std::string& header,
                 const std::function<std::string(const Row&, int)>& format,
                 int n = 4000) {
  std::string text = header + "\n";
  const std::vector<Row> rows = Rows(n);
  for (int i = 0; i < n; ++i) text += format(rows[i], i) + "\n";
  return text;
}

std::string Plain(const Row& r) {
  return fmt::format("{:.4f},{:.6f},{:.5f},{:.4f}", r.t, r.x, r.q, r.p);
}

std::string WriteFile(const std::string& name, const std::string& bytes) {
  const std::string path = ::testing::TempDir() + "/wearscar-variant-" + name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

// The channels equal to the bit (x within `x_tolerance`: a unit's factor
// rounds), row by row; NaN where the reference is NaN.
void ExpectSameChannels(const ForceRecord& a,
                        const ForceRecord& b,
                        double x_tolerance = 0.0,
                        double time_tolerance = 0.0) {
  ASSERT_EQ(a.size(), b.size());
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    ASSERT_NEAR(a.time_s[i], b.time_s[i], time_tolerance) << "row " << i;
    if (x_tolerance > 0) {
      ASSERT_NEAR(a.x_mm[i], b.x_mm[i], x_tolerance) << "row " << i;
    } else {
      ASSERT_EQ(a.x_mm[i], b.x_mm[i]) << "row " << i;
    }
    for (const auto c : {&ForceRecord::tangential_n, &ForceRecord::normal_n}) {
      const double u = (a.*c)[i], v = (b.*c)[i];
      if (std::isnan(u)) {
        ASSERT_TRUE(std::isnan(v)) << "row " << i;
      } else {
        ASSERT_EQ(u, v) << "row " << i;
      }
    }
  }
}

ForceRecord Reference() {
  return ReadForceText(
      Text("time_s,x_mm,Q_N,P_N", [](const Row& r, int) { return Plain(r); }),
      "plain.csv");
}

std::string ErrorOf(const std::function<void()>& read) {
  try {
    read();
  } catch (const ForceError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ExportVariants, TextColumnsTheMethodDoesNotUseAreSkipped) {
  const ForceRecord reference = Reference();
  // A status column last, a comment with the delimiter inside quotes, and
  // a step name first with a footer after the data.
  const ForceRecord last =
      ReadForceText(Text("time_s,x_mm,Q_N,P_N,Status",
                         [](const Row& r, int) { return Plain(r) + ",OK"; }),
                    "status-last.csv");
  ExpectSameChannels(reference, last);
  const ForceRecord quoted = ReadForceText(
      Text("time_s,x_mm,Q_N,P_N,Comment",
           [](const Row& r, int) { return Plain(r) + ",\"run 1, dry\""; }),
      "comment.csv");
  ExpectSameChannels(reference, quoted);
  const ForceRecord first = ReadForceText(
      Text("Step name,time_s,x_mm,Q_N,P_N",
           [](const Row& r, int) { return "Sliding," + Plain(r); }) +
          "End of data\n",
      "status-first.csv");
  ExpectSameChannels(reference, first);
  ASSERT_EQ(first.metadata.warnings.size(), 1u);
  EXPECT_EQ(first.metadata.warnings[0], "ignored a footer of 1 text lines");
  // Metadata lines with numbers are not data rows, whether text or numbers
  // are the more of their cells: the header under them still names the
  // columns.
  for (const char* metadata : {"Stroke,5.7,mm,Frequency,1,Hz",
                               "Load (N),30,10",
                               "Created,2024,05,01",
                               "30,1"}) {
    SCOPED_TRACE(metadata);
    const ForceRecord meta =
        ReadForceText(Text(std::string(metadata) + "\ntime_s,x_mm,Q_N,P_N",
                           [](const Row& r, int) { return Plain(r); }),
                      "metadata.csv");
    ExpectSameChannels(reference, meta);
  }
  // A text cell in a column the method reads is still an error, naming it.
  const std::string bad =
      Text("time_s,x_mm,Q_N,P_N,Status", [](const Row& r, int i) {
        return i == 2500
                   ? fmt::format("{:.4f},{:.6f},high,{:.4f},OK", r.t, r.x, r.p)
                   : Plain(r) + ",OK";
      });
  EXPECT_NE(ErrorOf([&] { ReadForceText(bad, "bad.csv"); })
                .find("bad.csv: line 2502, column 3 ('Q'): found 'high', "
                      "expected a number"),
            std::string::npos)
      << ErrorOf([&] { ReadForceText(bad, "bad.csv"); });
}

TEST(ExportVariants, SpreadsheetMissingValueMarkersAreGaps) {
  const std::vector<std::string> markers = {
      "#N/A", "#NV", "NA", "n/a", "null", "", "nan", "-nan(ind)", "1.#QNAN"};
  const auto with = [&](bool blank) {
    return Text("time_s,x_mm,Q_N,P_N", [&](const Row& r, int i) {
      if (i % 400 != 200) return Plain(r);  // rows 200, 600, ..., 3800
      const std::string& m =
          blank ? std::string() : markers[(i / 400) % markers.size()];
      return fmt::format("{:.4f},{:.6f},{},{:.4f}", r.t, r.x, m, r.p);
    });
  };
  const ForceRecord blanks = ReadForceText(with(true), "blanks.csv");
  ASSERT_TRUE(std::isnan(blanks.tangential_n[200]));
  const ForceRecord marked = ReadForceText(with(false), "markers.csv");
  ExpectSameChannels(blanks, marked);
  for (int i = 200; i < 4000; i += 400)
    EXPECT_TRUE(std::isnan(marked.tangential_n[i])) << i;
}

TEST(ExportVariants, MicroSignInAnyEncodingIsMicrometres) {
  const ForceRecord reference = Reference();
  const auto micrometres = [](const std::string& unit) {
    return Text("Time [s];Position [" + unit + "];Friction [N];Normal [N]",
                [](const Row& r, int) {
                  std::string s = fmt::format(
                      "{:.4f};{:.3f};{:.5f};{:.4f}", r.t, 1e3 * r.x, r.q, r.p);
                  for (char& c : s) c = c == '.' ? ',' : c;
                  return s;
                });
  };
  // UTF-8 micro sign, Greek mu, Latin-1 / Windows-1252, Shift-JIS mu, "um".
  for (const char* unit :
       {"\xC2\xB5m", "\xCE\xBCm", "\xB5m", "\x83\xCAm", "um"}) {
    SCOPED_TRACE(support::Printable(unit));
    const ForceRecord r = ReadForceText(micrometres(unit), "um.csv");
    ExpectSameChannels(reference, r, 1e-12);
    EXPECT_TRUE(r.metadata.warnings.empty());
  }
  // A unit it does not know is refused, its bytes shown as they are where
  // they are UTF-8 and escaped where not.
  EXPECT_NE(ErrorOf([&] { ReadForceText(micrometres("\xE4m"), "a.csv"); })
                .find("a.csv: column 'Position' has unit '\\xe4m'; expected a "
                      "length unit"),
            std::string::npos)
      << ErrorOf([&] { ReadForceText(micrometres("\xE4m"), "a.csv"); });
  EXPECT_NE(ErrorOf([&] {
              ReadForceText(micrometres("\xC3\xA4m"), "a.csv");
            }).find("has unit '\xC3\xA4m'"),
            std::string::npos);
}

std::string Utf16(const std::string& ascii, bool big_endian, bool bom) {
  std::string out;
  const auto unit = [&](unsigned v) {
    const char hi = static_cast<char>(v >> 8), lo = static_cast<char>(v & 255);
    out += big_endian ? hi : lo;
    out += big_endian ? lo : hi;
  };
  if (bom) unit(0xFEFF);
  for (unsigned char c : ascii) unit(c);
  return out;
}

TEST(ExportVariants, Utf16TextReadsAsItsUtf8AndIsChecksummedAsWritten) {
  const std::string text = Text(
      "Time [s]\tPosition [mm]\tFriction force "
      "[N]\tNormal force [N]",
      [](const Row& r, int) {
        return fmt::format(
            "{:.4f}\t{:.6f}\t{:.5f}\t{:.4f}", r.t, r.x, r.q, r.p);
      });
  const ForceRecord reference = ReadForceText(text, "utf8.txt");
  ASSERT_EQ(reference.size(), 4000);
  struct Form {
    const char* name;
    bool big_endian, bom;
  };
  for (const Form f : {Form{"le-bom", false, true},
                       Form{"be-bom", true, true},
                       Form{"le", false, false},
                       Form{"be", true, false}}) {
    SCOPED_TRACE(f.name);
    const std::string bytes = Utf16(text, f.big_endian, f.bom);
    const std::string path = WriteFile(std::string(f.name) + ".txt", bytes);
    ReadForceOptions o;
    std::string seen;
    o.on_bytes = [&](const char* b, std::size_t n) { seen.append(b, n); };
    const ForceRecord r = ReadForceFile(path, o);
    ExpectSameChannels(reference, r);
    EXPECT_EQ(r.metadata.layout, reference.metadata.layout);
    EXPECT_EQ(seen, bytes);  // the checksum is of the file as it is
    ExpectSameChannels(reference, ReadForceText(bytes, "in-memory.txt"));
    std::remove(path.c_str());
  }
  // Cut inside a unit, and an unpaired surrogate: refused at their byte.
  std::string cut = Utf16(text, false, true);
  cut.pop_back();
  const std::string cut_path = WriteFile("cut.txt", cut);
  EXPECT_NE(ErrorOf([&] { ReadForceFile(cut_path); })
                .find(fmt::format("{}: byte {}: the UTF-16LE text ends inside "
                                  "a character",
                                  cut_path,
                                  cut.size() - 1)),
            std::string::npos)
      << ErrorOf([&] { ReadForceFile(cut_path); });
  std::string lone = Utf16(text, false, true);
  const std::size_t at = 2 * 3000;  // an even offset inside the data
  lone[at] = '\x00';
  lone[at + 1] = '\xD8';  // U+D800 with no low surrogate after it
  const std::string lone_path = WriteFile("lone.txt", lone);
  EXPECT_NE(ErrorOf([&] { ReadForceFile(lone_path); })
                .find(fmt::format(
                    "{}: byte {}: not valid UTF-16LE text", lone_path, at)),
            std::string::npos)
      << ErrorOf([&] { ReadForceFile(lone_path); });
  std::remove(cut_path.c_str());
  std::remove(lone_path.c_str());
}

TEST(ExportVariants, GermanAndFrenchColumnNames) {
  const ForceRecord reference = Reference();
  for (const char* header :
       {"Zeit [s];Weg [mm];Reibkraft [N];Normalkraft [N]",
        "Zeit [s];Verschiebung [mm];Reibungskraft [N];Auflast [N]",
        "Temps [s];D\xC3\xA9placement [mm];Force de frottement [N];Force "
        "normale [N]"}) {
    SCOPED_TRACE(header);
    const ForceRecord r = ReadForceText(Text(header,
                                             [](const Row& row, int) {
                                               std::string s = Plain(row);
                                               for (char& c : s)
                                                 c = c == ',' ? ';' : c;
                                               return s;
                                             }),
                                        "de.csv");
    ExpectSameChannels(reference, r);
  }
}

// "2024-05-01T23:59:58.0005"-style cells: the row's time from `start`.
std::string Clock(double start_s, double t, const char* format, int digits) {
  const double at = start_s + t;
  const std::time_t whole = static_cast<std::time_t>(std::floor(at));
  std::tm tm{};
  gmtime_r(&whole, &tm);
  char buffer[64];
  std::strftime(buffer, sizeof buffer, format, &tm);
  const long fraction =
      std::lround((at - std::floor(at)) * std::pow(10, digits));
  return fmt::format("{}{:0{}d}", buffer, fraction, digits);
}

TEST(ExportVariants, ClockTimesReadAsSecondsFromTheFirstRow) {
  const ForceRecord reference = Reference();
  // 1 s before midnight on 2024-02-29 (a leap day), so every form crosses
  // into the next day.
  const double start = 1709251199.0;
  struct Form {
    const char* header;
    const char* format;
    char delimiter, decimal;
  };
  for (const Form f : {Form{"Timestamp", "%Y-%m-%dT%H:%M:%S.", ',', '.'},
                       Form{"Timestamp", "%Y-%m-%d %H:%M:%S.", ',', '.'},
                       Form{"Zeit", "%d.%m.%Y %H:%M:%S,", ';', ','},
                       Form{"Time", "%H:%M:%S.", '\t', '.'}}) {
    SCOPED_TRACE(f.format);
    const std::string d(1, f.delimiter);
    const std::string text =
        Text(fmt::format("{}{}x_mm{}Q_N{}P_N", f.header, d, d, d),
             [&](const Row& r, int) {
               std::string cells =
                   fmt::format("{:.6f}{}{:.5f}{}{:.4f}", r.x, d, r.q, d, r.p);
               if (f.decimal == ',') {
                 for (char& c : cells) c = c == '.' ? ',' : c;
               }
               return Clock(start, r.t, f.format, 4) + d + cells;
             });
    const ForceRecord r = ReadForceText(text, "clock.csv");
    ExpectSameChannels(reference, r, 0.0, 1e-9);
    EXPECT_NEAR(r.metadata.sampling_rate_hz, 2000.0, 1e-6);
  }
  // A date with '/' (day and month in either order) is refused, naming the
  // column; without the time column, the rate rebuilds the clock.
  const std::string slashed =
      Text("Timestamp,x_mm,Q_N,P_N", [&](const Row& r, int) {
        return Clock(start, r.t, "%m/%d/%Y %H:%M:%S.", 4) +
               Plain(r).substr(Plain(r).find(','));
      });
  EXPECT_NE(
      ErrorOf([&] { ReadForceText(slashed, "us.csv"); })
          .find("us.csv: line 2, column 1 ('Timestamp', taken as time): found "
                "text '02/29/2024 23:59:59.0000'; expected a number"),
      std::string::npos)
      << ErrorOf([&] { ReadForceText(slashed, "us.csv"); });
  ReadForceOptions o;
  o.time_column = "none";
  o.sampling_rate_hz = 2000;
  ExpectSameChannels(reference, ReadForceText(slashed, "us.csv", o), 0, 1e-12);
}

// A clock-timed file passing midnight (20 s and 45 s in) reads from a file,
// block by block, as from memory, on one clock without a step back.
TEST(ExportVariants, AClockPassingMidnightReadsFromAFileAsFromMemory) {
  for (double start : {1709251200.0 - 20, 1709251200.0 - 45}) {
    SCOPED_TRACE(start);
    const std::string text = Text(
        "Time,x_mm,Q_N,P_N",
        [&](const Row& r, int) {
          return Clock(start, r.t, "%H:%M:%S.", 4) +
                 Plain(r).substr(Plain(r).find(','));
        },
        120000);  // 60 s, 4.5 MB
    const std::string path = WriteFile("clock-midnight.csv", text);
    const ForceRecord a = ReadForceFile(path),
                      b = ReadForceText(text, "clock-midnight.csv");
    ExpectSameChannels(a, b);
    EXPECT_NEAR(a.time_s[119999] - a.time_s[0], 119999 / 2000.0, 1e-9);
    std::remove(path.c_str());
  }
}

TEST(ExportVariants, LinesEndedByCrAloneAndNoHeaderRow) {
  const ForceRecord reference = Reference();
  std::string text =
      Text("time_s,x_mm,Q_N,P_N", [](const Row& r, int) { return Plain(r); });
  std::replace(text.begin(), text.end(), '\n', '\r');
  ExpectSameChannels(reference, ReadForceText(text, "mac.csv"));
  const std::string path = WriteFile("mac.csv", text);
  ReadForceOptions o;
  std::string seen;
  o.on_bytes = [&](const char* b, std::size_t n) { seen.append(b, n); };
  ExpectSameChannels(reference, ReadForceFile(path, o));
  EXPECT_EQ(seen, text);
  std::remove(path.c_str());
  // No header row: the columns are named by number.
  const std::string bare =
      Text("", [](const Row& r, int) { return Plain(r); }).substr(1);
  EXPECT_NE(ErrorOf([&] { ReadForceText(bare, "bare.csv"); })
                .find("(no header row) (name the columns by number, e.g. "
                      "--columns time=#1,x=#2,q=#3,p=#4)"),
            std::string::npos)
      << ErrorOf([&] { ReadForceText(bare, "bare.csv"); });
  ReadForceOptions named;
  named.time_column = "#1";
  named.x_column = "#2";
  named.tangential_column = "#3";
  named.normal_column = "#4";
  ExpectSameChannels(reference, ReadForceText(bare, "bare.csv", named));
}

TEST(ExportVariants, AWorkbookIsRefusedSayingWhatItIs) {
  const ForceRecord reference = Reference();
  struct Case {
    std::string bytes;
    const char* what;
  };
  for (const Case& c :
       {Case{std::string("PK\x03\x04\x14\x00\x06\x00", 8) + "[Content_Types]",
             "a ZIP container (an Excel .xlsx"},
        Case{std::string("\xD0\xCF\x11\xE0\xA1\xB1\x1A\xE1\0\0", 10),
             "an OLE2 compound file (an Excel .xls"},
        Case{"%PDF-1.7\n1,2,3\n", "a PDF document"}}) {
    const std::string path = WriteFile("workbook", c.bytes);
    for (const std::string& m :
         {ErrorOf([&] { ReadForceFile(path); }),
          ErrorOf([&] { ReadForceText(c.bytes, path); })}) {
      EXPECT_NE(m.find(path + ": byte 0: found " + c.what), std::string::npos)
          << m;
      EXPECT_NE(m.find("save the sheet as CSV"), std::string::npos) << m;
    }
    std::remove(path.c_str());
  }
}

// Q and P swapped in the header (the load under the friction's name), or
// a "load" that reverses with the motion: refused with the fix, unless the
// channels are to be read as given.
TEST(ExportVariants, SwappedChannelsAreRefusedWithTheFix) {
  const std::string swapped =
      Text("time_s,x_mm,Load_N,Friction_N", [](const Row& r, int) {
        return fmt::format(
            "{:.4f},{:.6f},{:.4f},"
            "{:.5f}",
            r.t,
            r.x,
            r.p,
            r.q);
      });
  ReadForceOptions o;
  o.tangential_column = "Load_N";
  o.normal_column = "Friction_N";
  EXPECT_EQ(ErrorOf([&] { ReadForceText(swapped, "swap.csv", o); }),
            "swap.csv: the friction force Q 'Load' exceeds the normal force "
            "P 'Friction' in magnitude on 100% of the samples: the two look "
            "swapped; expected |Q| below |P| (mu below 1): name the columns "
            "with --columns q=NAME,p=NAME, or give --force-channels-as-given "
            "to read them as they are");
  // A friction force read as the load: it changes sign with the motion
  // (|Q| is set small here so that only the sign speaks).
  const std::string reversing =
      Text("time_s,x_mm,Q_N,P_N", [](const Row& r, int) {
        return fmt::format(
            "{:.4f},{:.6f},{:.5f},{:.5f}", r.t, r.x, 0.01 * r.q, r.q);
      });
  const std::string reversed =
      ErrorOf([&] { ReadForceText(reversing, "rev.csv"); });
  EXPECT_NE(reversed.find("rev.csv: the normal force P 'P' changes sign on "
                          "50% of the samples: it reverses like a friction "
                          "force"),
            std::string::npos)
      << reversed;
  o.channels_as_given = true;
  const ForceRecord as_given = ReadForceText(swapped, "swap.csv", o);
  EXPECT_NEAR(as_given.tangential_n[10], Rows()[10].p, 1e-4);
}

// Test conditions stated above the data, in the ways exports write them:
// each kind once, in mm, a count, N and Hz; the sampling rate is not the
// drive's frequency, an elapsed time holds no "laps".
TEST(ExportVariants, StatedTestConditionsAreRead) {
  const std::string text =
      "Sampling rate: 2000 Hz\nTime elapsed: 2 s\n"
      "Track length 5 mm, Cycles 3000\nNormal load [N]: 30\n"
      "Amplitude (um) = 2850\nFrequency: 1 Hz\n" +
      Text("time_s,x_mm,Q_N,P_N", [](const Row& r, int) { return Plain(r); });
  const ForceRecord r = ReadForceText(text, "stated.csv");
  std::map<std::string, std::pair<double, int>> got;
  for (const StatedFact& f : r.metadata.stated)
    got[f.what] = {f.value, f.line_number};
  ASSERT_EQ(got.size(), 4u) << text.substr(0, 200);
  EXPECT_DOUBLE_EQ(got["stroke"].first, 5.0);  // the first stated
  EXPECT_EQ(got["stroke"].second, 3);
  EXPECT_DOUBLE_EQ(got["cycles"].first, 3000);
  EXPECT_DOUBLE_EQ(got["load"].first, 30);
  EXPECT_DOUBLE_EQ(got["frequency"].first, 1);
  // Each fact quoted as written, not its whole line.
  EXPECT_EQ(r.metadata.stated[0].line, "Track length 5 mm");
  EXPECT_EQ(r.metadata.stated[1].line, "Cycles 3000");
  // A home-built rig's one header line of several facts.
  const ForceRecord one = ReadForceText(
      "Sampling fequency [Hz]: 100 x-velocity [mm/s]: 10 Track length [mm]: "
      "5 Cycles: 600\n" +
          Text("time_s,x_mm,Q_N,P_N",
               [](const Row& row, int) { return Plain(row); }),
      "home.txt");
  ASSERT_EQ(one.metadata.stated.size(), 2u);
  EXPECT_EQ(one.metadata.stated[0].line, "Track length [mm]: 5");
  EXPECT_EQ(one.metadata.stated[1].line, "Cycles: 600");
  EXPECT_EQ(r.metadata.sampling_rate_hz, 2000);
  // The loading spring, in N/mm, N/m, kN/m or N/um.
  for (const auto& [line, n_per_mm] :
       std::vector<std::pair<std::string, double>>{
           {"Spring stiffness [N/mm]: 25", 25},
           {"Spring constant = 25000 N/m", 25},
           {"Loading spring: 7.5 kN/m", 7.5},
           {"spring rate 0.1 N/um", 100}}) {
    const ForceRecord s =
        ReadForceText(line + "\n" +
                          Text("time_s,x_mm,Q_N,P_N",
                               [](const Row& row, int) { return Plain(row); }),
                      "spring.csv");
    ASSERT_EQ(s.metadata.stated.size(), 1u) << line;
    EXPECT_EQ(s.metadata.stated[0].what, "spring") << line;
    EXPECT_DOUBLE_EQ(s.metadata.stated[0].value, n_per_mm) << line;
  }
}

// The first sample beyond the bounds is the one named, however far into
// the file (past the first stretches searched together), a force before an
// x on the same row; a friction channel of zeros with gaps is still zeros.
TEST(ExportVariants, TheFirstSampleBeyondTheBoundsIsNamed) {
  const auto with = [](int at, const char* q, const char* x) {
    return Text(
        "time_s,x_mm,Q_N,P_N",
        [=](const Row& r, int i) {
          return i == at ? fmt::format("{:.6f},{},{},{:.6f}", r.t, x, q, r.p)
                 : i == at + 3
                     ? fmt::format("{:.6f},{:.6f},2e5,{:.6f}", r.t, r.x, r.p)
                     : Plain(r);
        },
        12000);
  };
  EXPECT_NE(ErrorOf([&] {
              ReadForceText(with(9001, "1", "20000"), "far.csv");
            }).find("far.csv: sample 9002 (t = 4.5005 s): x = 2e+04 mm"),
            std::string::npos);
  EXPECT_NE(
      ErrorOf([&] {
        ReadForceText(with(9001, "-3e5", "20000"), "both.csv");
      }).find("both.csv: sample 9002 (t = 4.5005 s): a force of -3e+05 N"),
      std::string::npos);
  const std::string gaps = Text("time_s,x_mm,Q_N,P_N", [](const Row& r, int i) {
    return fmt::format(
        "{:.6f},{:.6f},{},{:.6f}", r.t, r.x, i % 7 == 3 ? "" : "0", r.p);
  });
  EXPECT_NE(ErrorOf([&] {
              ReadForceText(gaps, "gaps.csv");
            }).find("gaps.csv: no friction force recorded"),
            std::string::npos);
}

// A friction channel with no friction in it is refused as what it is,
// naming the column; a rotary (pin-on-disk) export, whose position does
// not reciprocate and whose header states a radius, is named a rotary
// test rather than a stroke of 0 mm with a unit to check.
TEST(ExportVariants, NoFrictionAndARotaryTestAreSaidForWhatTheyAre) {
  const std::string zero = Text("time_s,x_mm,Q_N,P_N", [](const Row& r, int) {
    return fmt::format("{:.6f},{:.6f},0,{:.6f}", r.t, r.x, r.p);
  });
  try {
    ReadForceText(zero, "zero.csv");
    FAIL() << "a friction channel of zeros was read";
  } catch (const ForceError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "zero.csv: no friction force recorded: the friction "
                  "channel 'Q' is 0 N in every one of the "),
              std::string::npos)
        << e.what();
  }
  const std::string rotary =
      "Created by CETR UMT Data Viewer ver. 1.138.266\nRun # 1\n"
      "Radius = 3.9493\nVelocity = 240\n\n" +
      Text("time_s,x_mm,Q_N,P_N", [](const Row& r, int) {
        return fmt::format("{:.6f},0.00000,{:.6f},{:.6f}", r.t, r.q, r.p);
      });
  try {
    ReadForceText(rotary, "rotary.csv");
    FAIL() << "a rotary test was read";
  } catch (const ForceError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "rotary.csv: a rotary test (pin-on-disk): the position does "
                  "not reciprocate (a stroke of 0 mm) and line 3 states the "
                  "track's radius ('Radius = 3.9493')"),
              std::string::npos)
        << e.what();
  }
  // A ball's radius is no rotary test: a flat position is the stroke's
  // refusal, naming the x unit.
  std::string ball = rotary;
  ball.replace(ball.find("Radius = 3.9493"), 15, "Ball radius = 3 mm");
  try {
    ReadForceText(ball, "ball.csv");
    FAIL() << "a flat position was read";
  } catch (const ForceError& e) {
    EXPECT_EQ(std::string(e.what()).find("rotary"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("ball.csv: a stroke of 0 mm"),
              std::string::npos)
        << e.what();
  }
}

// An export cut in its last row (the file ends inside it): the row is
// dropped with a warning that says so; a short row inside the file stays
// an error.
TEST(ExportVariants, ACutLastRowIsDroppedAndSaid) {
  std::string text =
      Text("time_s,x_mm,Q_N,P_N", [](const Row& r, int) { return Plain(r); });
  text.resize(text.size() - 20);  // "1.9995,-0.0" and no line break
  const ForceRecord r = ReadForceText(text, "cut.csv");
  EXPECT_EQ(r.size(), 3999);
  ASSERT_FALSE(r.metadata.warnings.empty());
  EXPECT_EQ(r.metadata.warnings.back(),
            "the last row is cut and was dropped (line 4001: ragged row: "
            "found 2 fields, expected 4): was the export interrupted?");
  size_t tenth = 0;
  for (int i = 0; i < 10; ++i) tenth = text.find('\n', tenth) + 1;
  const std::string short_inside =
      text.substr(0, tenth) + "0.5,1\n" + text.substr(tenth);
  EXPECT_NE(ErrorOf([&] {
              ReadForceText(short_inside, "mid.csv");
            }).find("mid.csv: line 11: ragged row: found 2 fields"),
            std::string::npos);
}

}  // namespace
}  // namespace wearscar::force
