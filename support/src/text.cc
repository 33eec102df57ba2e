#include "wearscar/support/text.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "wearscar/support/numbers.h"

namespace wearscar::support {

std::string Upper(std::string_view s) {
  std::string out(s);
  for (char& c : out)
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  return out;
}

std::string Lower(std::string_view s) {
  std::string out(s);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const auto c = static_cast<unsigned char>(out[i]);
    const auto next =
        i + 1 < out.size() ? static_cast<unsigned char>(out[i + 1]) : 0u;
    if (c == 0xC3 && next >= 0x80 && next <= 0x9E && next != 0x97) {
      // The capitals of Latin-1 in UTF-8 (À-Þ but ×): ä for Ä.
      out[i + 1] = static_cast<char>(next + 0x20);
      ++i;
    } else {
      out[i] = static_cast<char>(std::tolower(c));
    }
  }
  return out;
}

std::string_view Trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\n\v\f\r");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\n\v\f\r");
  return s.substr(first, last - first + 1);
}

std::size_t PrintableUtf8Length(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) {
    return k < text.size() ? static_cast<unsigned char>(text[k]) : 0u;
  };
  const unsigned c = byte(i);
  const auto tail = [&](std::size_t k) { return (byte(k) & 0xC0u) == 0x80u; };
  if (c >= 0xC2 && c <= 0xDF)
    return tail(i + 1) && !(c == 0xC2 && byte(i + 1) < 0xA0) ? 2 : 0;
  if (c >= 0xE0 && c <= 0xEF) {
    const unsigned c1 = byte(i + 1);
    if ((c == 0xE0 && c1 < 0xA0) || (c == 0xED && c1 > 0x9F)) return 0;
    return tail(i + 1) && tail(i + 2) ? 3 : 0;
  }
  if (c >= 0xF0 && c <= 0xF4) {
    const unsigned c1 = byte(i + 1);
    if ((c == 0xF0 && c1 < 0x90) || (c == 0xF4 && c1 > 0x8F)) return 0;
    return tail(i + 1) && tail(i + 2) && tail(i + 3) ? 4 : 0;
  }
  return 0;
}

std::string Printable(std::string_view text, std::size_t max) {
  static const char kHex[] = "0123456789abcdef";
  std::string out;
  std::size_t i = 0;
  for (std::size_t shown = 0; i < text.size() && shown < max; ++shown) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
      ++i;
    } else if (const std::size_t n = PrintableUtf8Length(text, i); n > 0) {
      out.append(text.substr(i, n));
      i += n;
    } else {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
      ++i;
    }
  }
  if (i < text.size()) out += "...";
  return out;
}

namespace {

// a 10^s, rounded once (|s| <= 22: the power is exact).
double Scaled(double a, int s) {
  return s >= 0 ? a * kExactPowersOf10[s] : a / kExactPowersOf10[-s];
}

// The `precision` significant digits of a > 0 as an integer in
// [10^(precision - 1), 10^precision) and the decimal exponent of the
// first; false where one rounding of the scaled value might round the
// other way than the exact value would.
bool SignificantDigits(double a,
                       int precision,
                       std::uint64_t* digits,
                       int* exponent) {
  // floor(log10 a) is e or e + 1, from the binary exponent b:
  // floor(b log10 2) by a multiply and a shift.
  std::uint64_t bits;
  std::memcpy(&bits, &a, sizeof bits);
  const int b = static_cast<int>((bits >> 52) & 0x7ff) - 1023;
  int e = (b * 78913) >> 18;
  const double top = kExactPowersOf10[precision];
  int s = precision - 1 - e;
  if (s < -22 || s > 22) return false;
  double m = Scaled(a, s);
  if (m >= top) {
    ++e;
    if (--s < -22) return false;
    m = Scaled(a, s);
  }
  if (m < kExactPowersOf10[precision - 1]) return false;
  // m is the exact a 10^s within half its ulp (m 2^-53): the rounding to
  // an integer is the exact value's unless m lies that close to a half.
  // (m < 10^15: the conversion truncates, as floor for m > 0.)
  std::uint64_t d = static_cast<std::uint64_t>(m);
  const double fraction = m - static_cast<double>(d);  // exact
  if (std::abs(fraction - 0.5) <= m * 0x1p-51) return false;
  d += fraction > 0.5 ? 1 : 0;
  if (static_cast<double>(d) >= top) {  // 99.99..5 rounded up: 10^p
    d /= 10;
    ++e;
  }
  *digits = d;
  *exponent = e;
  return true;
}

}  // namespace

std::to_chars_result ToCharsGeneral(char* first,
                                    char* last,
                                    double value,
                                    int precision) {
  const double a = std::abs(value);
  std::uint64_t d = 0;
  int e = 0;
  if (precision < 1 || precision > 15 || last - first < 32 ||
      !(a >= 1e-15 && a < 1e15) || !SignificantDigits(a, precision, &d, &e))
    return std::to_chars(
        first, last, value, std::chars_format::general, precision);
  char digits[16];
  for (int i = precision - 1; i >= 0; --i, d /= 10)
    digits[i] = static_cast<char>('0' + d % 10);
  int n = precision;  // without the trailing zeros %g drops
  while (n > 1 && digits[n - 1] == '0') --n;
  char* out = first;
  if (value < 0) *out++ = '-';
  if (e >= -4 && e < precision) {
    if (e < 0) {
      *out++ = '0';
      *out++ = '.';
      for (int i = 0; i < -e - 1; ++i) *out++ = '0';
      std::memcpy(out, digits, static_cast<std::size_t>(n));
      out += n;
    } else {
      for (int i = 0; i <= e; ++i) *out++ = i < n ? digits[i] : '0';
      if (n > e + 1) {
        *out++ = '.';
        std::memcpy(out, digits + e + 1, static_cast<std::size_t>(n - e - 1));
        out += n - e - 1;
      }
    }
  } else {
    *out++ = digits[0];
    if (n > 1) {
      *out++ = '.';
      std::memcpy(out, digits + 1, static_cast<std::size_t>(n - 1));
      out += n - 1;
    }
    *out++ = 'e';
    *out++ = e < 0 ? '-' : '+';
    const int x = std::abs(e);  // < 16: two digits
    *out++ = static_cast<char>('0' + x / 10);
    *out++ = static_cast<char>('0' + x % 10);
  }
  return {out, std::errc()};
}

}  // namespace wearscar::support
