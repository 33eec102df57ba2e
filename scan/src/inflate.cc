#include "inflate.h"

#include <fmt/format.h>
#include <zstd.h>

#include <algorithm>
#include <memory>

#include "wearscar/scan/height_map.h"

namespace wearscar::scan::internal {

void InflateBudget::Check(std::uint64_t compressed,
                          std::uint64_t expanded,
                          std::uint64_t cap,
                          const std::string& where) const {
  const std::uint64_t member_limit = std::min(cap, o_.max_member_bytes);
  if (expanded > member_limit) {
    throw ScanError(fmt::format(
        "{}: expands to {} bytes or more; the limit is {} bytes (--large-maps "
        "raises it if the file is genuine)",
        where,
        expanded,
        member_limit));
  }
  if (expanded > o_.free_expansion_bytes &&
      static_cast<double>(expanded) >
          o_.max_expansion_ratio * static_cast<double>(compressed)) {
    throw ScanError(fmt::format(
        "{}: {} compressed bytes expand to {} or more, a ratio above {} "
        "(a decompression bomb? --large-maps accepts it); expected a height "
        "map",
        where,
        compressed,
        expanded,
        o_.max_expansion_ratio));
  }
  if (total_ + expanded > o_.max_total_bytes) {
    throw ScanError(fmt::format(
        "{}: the file's members expand to {} bytes or more in all; the limit "
        "is {} bytes",
        where,
        total_ + expanded,
        o_.max_total_bytes));
  }
}

std::string ZstdDecompress(const std::string& frame,
                           InflateBudget* budget,
                           std::uint64_t cap,
                           const std::string& where) {
  const unsigned long long stated =
      ZSTD_getFrameContentSize(frame.data(), frame.size());
  if (stated == ZSTD_CONTENTSIZE_ERROR) {
    throw ScanError(
        fmt::format("{}: not a zstd frame (KPK1 compresses every "
                    "member)",
                    where));
  }
  if (stated != ZSTD_CONTENTSIZE_UNKNOWN) {
    budget->Check(frame.size(), stated, cap, where);
    std::string out(static_cast<std::size_t>(stated), '\0');
    const std::size_t got =
        ZSTD_decompress(out.data(), out.size(), frame.data(), frame.size());
    if (ZSTD_isError(got) || got != stated) {
      throw ScanError(fmt::format(
          "{}: zstd error: {}",
          where,
          ZSTD_isError(got) ? ZSTD_getErrorName(got) : "short output"));
    }
    budget->Spend(out.size());
    return out;
  }
  // No stated size: stream, growing the output while the budget allows.
  std::unique_ptr<ZSTD_DStream, decltype(&ZSTD_freeDStream)> stream(
      ZSTD_createDStream(), &ZSTD_freeDStream);
  if (!stream) throw ScanError(where + ": zstd: out of memory");
  ZSTD_initDStream(stream.get());
  std::string out;
  ZSTD_inBuffer in{frame.data(), frame.size(), 0};
  std::size_t step = std::max<std::size_t>(ZSTD_DStreamOutSize(), 1 << 16);
  std::size_t last = 1;
  while (true) {
    const std::size_t at = out.size();
    budget->Check(frame.size(), at, cap, where);  // at most one step over
    out.resize(at + step);
    ZSTD_outBuffer o{out.data() + at, step, 0};
    last = ZSTD_decompressStream(stream.get(), &o, &in);
    out.resize(at + o.pos);
    if (ZSTD_isError(last)) {
      throw ScanError(fmt::format("{}: zstd error at compressed byte {}: {}",
                                  where,
                                  in.pos,
                                  ZSTD_getErrorName(last)));
    }
    if (last == 0) break;  // the frame is complete
    if (in.pos == in.size && o.pos < o.size) {
      throw ScanError(
          fmt::format("{}: the zstd frame is truncated at compressed byte {}",
                      where,
                      in.pos));
    }
    step = std::min<std::size_t>(2 * step, std::size_t{16} << 20);
  }
  budget->Check(frame.size(), out.size(), cap, where);
  budget->Spend(out.size());
  return out;
}

}  // namespace wearscar::scan::internal
