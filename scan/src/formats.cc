#include "wearscar/scan/formats.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "byte_reader.h"
#include "format_list.h"
#include "wearscar/support/compressed.h"

namespace wearscar::scan {

namespace internal {
#define WEARSCAR_DECLARE_FORMAT(F) ScanFormat F();
WEARSCAR_SCAN_FORMATS(WEARSCAR_DECLARE_FORMAT)
#undef WEARSCAR_DECLARE_FORMAT
}  // namespace internal

const std::vector<ScanFormat>& ScanFormats() {
#define WEARSCAR_LIST_FORMAT(F) internal::F(),
  static const std::vector<ScanFormat> formats{
      WEARSCAR_SCAN_FORMATS(WEARSCAR_LIST_FORMAT)};
#undef WEARSCAR_LIST_FORMAT
  return formats;
}

const ScanFormat* FindScanFormat(std::string_view name) {
  for (const ScanFormat& f : ScanFormats()) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

std::string LowerExtension(const std::string& path) {
  std::string ext =
      std::filesystem::path(support::WithoutCompressionSuffix(path))
          .extension()
          .string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](char c) {
    return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  });
  return ext;
}

namespace {

bool Claims(const ScanFormat& f, const std::string& ext) {
  return std::find(f.extensions.begin(), f.extensions.end(), ext) !=
         f.extensions.end();
}

// Text exports carry no NUL byte in their first kilobytes.
bool LooksLikeText(std::string_view head) {
  return head.substr(0, 4096).find('\0') == std::string_view::npos;
}

}  // namespace

const ScanFormat& DetectScanFormat(const std::string& bytes,
                                   const std::string& path) {
  const std::string ext = LowerExtension(path);
  const std::string_view head =
      std::string_view(bytes).substr(0, kDetectHeadBytes);
  const ScanFormat* best = nullptr;
  int best_score = 0;
  for (const ScanFormat& f : ScanFormats()) {
    const int score = f.detect(head, ext);
    if (score > best_score) best = &f, best_score = score;
  }
  // A file named like a format with a magic, without that magic: say so,
  // unless it is text and a text layout shares the extension (".dat").
  if (best_score < kDetectExtension) {
    bool text_may_read = false;
    for (const ScanFormat& f : ScanFormats()) {
      text_may_read |= f.magics.empty() && Claims(f, ext);
    }
    if (text_may_read && LooksLikeText(head)) return *best;
    for (const ScanFormat& f : ScanFormats()) {
      if (f.magics.empty() || !Claims(f, ext)) continue;
      std::string expected;
      for (const std::string& m : f.magics) {
        expected += (expected.empty() ? "" : " or ") +
                    fmt::format("'{}'", internal::Printable(m));
      }
      throw ScanError(fmt::format(
          "{}: byte 0: found '{}', which is not the magic of a {} file ({}); "
          "expected {}",
          path,
          internal::Printable(head.substr(0, 8), 8),
          ext,
          f.title,
          expected));
    }
  }
  if (best == nullptr) {
    throw ScanError(fmt::format(
        "{}: byte 0: no height-map format recognises this file; wearscar "
        "reads {}",
        path,
        ScanExtensionList()));
  }
  return *best;
}

const ScanFormat* ScanFormatOf(const std::string& path, int min_score) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return nullptr;
  std::string head(kDetectHeadBytes, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  const support::Compression packed = support::CompressionOf(head);
  if (packed != support::Compression::kNone) {
    // A compressed file's head: what its first MiB expands to (a cut
    // stream gives what it has).
    std::string some = head, rest, why;
    some.resize(std::size_t{1} << 20);
    in.read(some.data() + head.size(),
            static_cast<std::streamsize>(some.size() - head.size()));
    some.resize(head.size() + static_cast<std::size_t>(in.gcount()));
    support::Decompress(some, packed, kDetectHeadBytes, true, &rest, &why);
    if (rest.empty()) return nullptr;
    head = std::move(rest);
  }
  const std::string ext = LowerExtension(path);
  for (const ScanFormat& f : ScanFormats()) {
    if (f.detect(head, ext) >= min_score) return &f;
  }
  return nullptr;
}

const ScanFormat* BinaryScanFormatOf(const std::string& path) {
  return ScanFormatOf(path, kDetectExtension);
}

std::string ScanExtensionList() {
  std::vector<std::string> seen;
  for (const ScanFormat& f : ScanFormats()) {
    for (const std::string& e : f.extensions) {
      const std::string bare = e.substr(1);
      if (std::find(seen.begin(), seen.end(), bare) == seen.end()) {
        seen.push_back(bare);
      }
    }
  }
  std::string out;
  for (const std::string& s : seen) out += (out.empty() ? "" : ", ") + s;
  return out;
}

}  // namespace wearscar::scan
