#include "encoding.h"

#include <fmt/format.h>
#include <iconv.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <vector>

#include "wearscar/force/force_record.h"

namespace wearscar::force::internal {
namespace {

// An iconv descriptor, closed when it goes.
class Converter {
 public:
  Converter(const char* encoding, const std::string& name)
      : cd_(iconv_open("UTF-8", encoding)) {
    if (cd_ == reinterpret_cast<iconv_t>(-1)) {
      throw ForceError(
          fmt::format("{}: {} text, which this system cannot convert: {}",
                      name,
                      encoding,
                      std::strerror(errno)));
    }
  }
  ~Converter() { iconv_close(cd_); }
  Converter(const Converter&) = delete;
  Converter& operator=(const Converter&) = delete;

  // Converts what it can of [*in, *in + *left) onto `out`: false at a
  // sequence cut by the block's end (the rest left in *left), throws at an
  // ill-formed one (`done` the bytes converted before the block).
  void Convert(char** in,
               std::size_t* left,
               std::string* out,
               char* block_start,
               std::uintmax_t done,
               const char* encoding,
               const std::string& name) {
    std::vector<char>& converted = buffer_;
    converted.resize(2 * std::max<std::size_t>(*left, 16));
    while (*left > 0) {
      char* op = converted.data();
      std::size_t room = converted.size();
      const std::size_t r = iconv(cd_, in, left, &op, &room);
      out->append(converted.data(), converted.size() - room);
      if (r != static_cast<std::size_t>(-1) || errno == E2BIG) continue;
      if (errno == EINVAL) return;  // cut by the block: the next read ends it
      throw ForceError(fmt::format(
          "{}: byte {}: not valid {} text (an unpaired surrogate or an "
          "ill-formed unit); expected UTF-16, or save the file as UTF-8",
          name,
          done + static_cast<std::uintmax_t>(*in - block_start),
          encoding));
    }
  }

 private:
  iconv_t cd_;
  std::vector<char> buffer_;
};

ForceError TooLarge(const std::string& name,
                    std::uintmax_t bytes,
                    const char* encoding) {
  return ForceError(fmt::format(
      "{}: more than {} bytes of {} text; expected at most {} MiB of "
      "UTF-16 (convert it to UTF-8 first, e.g. iconv -f UTF-16 -t UTF-8)",
      name,
      bytes,
      encoding,
      kWholeTextMaxBytes >> 20));
}

}  // namespace

const char* Utf16Encoding(std::string_view first) {
  const auto b = [&](std::size_t i) {
    return i < first.size() ? static_cast<unsigned char>(first[i]) : 0u;
  };
  if (first.size() >= 2 && b(0) == 0xFF && b(1) == 0xFE) return "UTF-16LE";
  if (first.size() >= 2 && b(0) == 0xFE && b(1) == 0xFF) return "UTF-16BE";
  const auto ascii = [](unsigned c) { return c >= 0x09 && c < 0x7F; };
  if (first.size() < 4) return nullptr;
  if (ascii(b(0)) && b(1) == 0 && ascii(b(2)) && b(3) == 0) return "UTF-16LE";
  if (b(0) == 0 && ascii(b(1)) && b(2) == 0 && ascii(b(3))) return "UTF-16BE";
  return nullptr;
}

std::string Utf16ToUtf8(
    const std::function<std::size_t(char*, std::size_t)>& read,
    const char* encoding,
    const std::string& name,
    std::uintmax_t size_hint,
    const std::function<void(const char*, std::size_t)>& on_bytes) {
  if (size_hint > kWholeTextMaxBytes) throw TooLarge(name, size_hint, encoding);
  Converter converter(encoding, name);
  std::string out;
  out.reserve(static_cast<std::size_t>(size_hint / 2 + 16));
  // Blocks of 1 MiB (less for a small text; 16 bytes at least, room for a
  // cut sequence and one whole).
  std::vector<char> in(static_cast<std::size_t>(
      std::clamp<std::uintmax_t>(size_hint + 16, 16, std::uintmax_t{1} << 20)));
  std::size_t carry = 0;    // bytes of a sequence cut by the block's end
  std::uintmax_t done = 0;  // bytes converted before `in`
  for (;;) {
    const std::size_t got = read(in.data() + carry, in.size() - carry);
    if (got > 0 && on_bytes) on_bytes(in.data() + carry, got);
    if (done + carry + got > kWholeTextMaxBytes)
      throw TooLarge(name, done + carry + got, encoding);
    if (got == 0) {
      if (carry == 0) return out;
      throw ForceError(fmt::format(
          "{}: byte {}: the {} text ends inside a character; expected whole "
          "2-byte units",
          name,
          done,
          encoding));
    }
    char* ip = in.data();
    std::size_t left = carry + got;
    converter.Convert(&ip, &left, &out, in.data(), done, encoding, name);
    done += static_cast<std::uintmax_t>(ip - in.data());
    carry = left;
    std::memmove(in.data(), ip, carry);
  }
}

void RefuseWorkbook(std::string_view first, const std::string& name) {
  const char* what = nullptr;
  if (first.substr(0, 4) == std::string_view("PK\x03\x04", 4)) {
    what = "a ZIP container (an Excel .xlsx or OpenDocument .ods workbook?)";
  } else if (first.substr(0, 8) ==
             std::string_view("\xD0\xCF\x11\xE0\xA1\xB1\x1A\xE1", 8)) {
    what = "an OLE2 compound file (an Excel .xls workbook?)";
  } else if (first.substr(0, 5) == "%PDF-") {
    what = "a PDF document";
  }
  if (what == nullptr) return;
  throw ForceError(fmt::format(
      "{}: byte 0: found {}; expected a delimited text export (save the "
      "sheet as CSV, or export text from the instrument's software)",
      name,
      what));
}

bool EndsLinesWithCrAlone(std::string_view first) {
  first = first.substr(0, std::size_t{64} << 10);
  return first.find('\r') != std::string_view::npos &&
         first.find('\n') == std::string_view::npos;
}

}  // namespace wearscar::force::internal
