#include "wearscar/support/compressed.h"

#include <fmt/format.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <limits>
#include <memory>

#include "wearscar/support/text.h"

namespace wearscar::support {
namespace {

constexpr std::size_t kStep = std::size_t{1} << 20;

bool Fail(std::string* why, std::string message) {
  if (why) *why = std::move(message);
  return false;
}

// gzip members one after the other (as `cat a.gz b.gz` makes them).
bool Gunzip(std::string_view data,
            std::uint64_t max_bytes,
            bool partial,
            std::string* out,
            std::string* why) {
  z_stream z{};
  // 15 + 16: a gzip header and trailer, checked.
  if (inflateInit2(&z, 15 + 16) != Z_OK)
    return Fail(why, "the gzip decoder could not start");
  std::unique_ptr<z_stream, int (*)(z_stream*)> end(&z, &inflateEnd);
  std::size_t in = 0;
  int rc = Z_OK;
  for (;;) {
    const std::size_t chunk = std::min<std::size_t>(
        data.size() - in, std::numeric_limits<uInt>::max());
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data() + in));
    z.avail_in = static_cast<uInt>(chunk);
    const std::size_t had = out->size();
    const std::uint64_t room = max_bytes - had;
    if (room == 0) break;
    out->resize(had +
                static_cast<std::size_t>(std::min<std::uint64_t>(kStep, room)));
    z.next_out = reinterpret_cast<Bytef*>(out->data() + had);
    z.avail_out = static_cast<uInt>(out->size() - had);
    rc = inflate(&z, Z_NO_FLUSH);
    out->resize(out->size() - z.avail_out);
    in += chunk - z.avail_in;
    if (rc == Z_STREAM_END) {
      // Another member may follow; trailing zero padding is allowed.
      const std::string_view rest = data.substr(in);
      if (rest.find_first_not_of('\0') == std::string_view::npos) return true;
      if (inflateReset(&z) != Z_OK)
        return Fail(why, "the gzip decoder could not restart");
      continue;
    }
    if (rc == Z_BUF_ERROR && in == data.size() && z.avail_out > 0)
      return Fail(why,
                  fmt::format("the gzip data end after {} bytes, cut short",
                              data.size()));
    if (rc != Z_OK && rc != Z_BUF_ERROR)
      return Fail(why,
                  fmt::format("corrupt gzip data ({}) near byte {}",
                              z.msg ? z.msg : "no message",
                              in));
  }
  if (partial) return true;
  return Fail(why,
              fmt::format("expands to more than {} MiB; expected at most "
                          "that",
                          max_bytes >> 20));
}

bool Unzstd(std::string_view data,
            std::uint64_t max_bytes,
            bool partial,
            std::string* out,
            std::string* why) {
  std::unique_ptr<ZSTD_DStream, std::size_t (*)(ZSTD_DStream*)> s(
      ZSTD_createDStream(), &ZSTD_freeDStream);
  if (!s || ZSTD_isError(ZSTD_initDStream(s.get())))
    return Fail(why, "the zstd decoder could not start");
  ZSTD_inBuffer in{data.data(), data.size(), 0};
  std::size_t last = 1;  // 0 when a frame is complete
  while (in.pos < in.size) {
    const std::size_t had = out->size();
    const std::uint64_t room = max_bytes - had;
    if (room == 0) {
      if (partial) return true;
      return Fail(why,
                  fmt::format("expands to more than {} MiB; expected at "
                              "most that",
                              max_bytes >> 20));
    }
    out->resize(had +
                static_cast<std::size_t>(std::min<std::uint64_t>(kStep, room)));
    ZSTD_outBuffer o{out->data() + had, out->size() - had, 0};
    last = ZSTD_decompressStream(s.get(), &o, &in);
    out->resize(had + o.pos);
    if (ZSTD_isError(last))
      return Fail(why,
                  fmt::format("corrupt zstd data ({}) near byte {}",
                              ZSTD_getErrorName(last),
                              in.pos));
  }
  if (last != 0 && !(partial && out->size() >= max_bytes))
    return Fail(why,
                fmt::format("the zstd data end after {} bytes, cut short",
                            data.size()));
  return true;
}

}  // namespace

Compression CompressionOf(std::string_view head) {
  if (head.size() >= 3 && head[0] == '\x1f' && head[1] == '\x8b' &&
      head[2] == '\x08')
    return Compression::kGzip;
  if (head.size() >= 4 &&
      head.substr(0, 4) == std::string_view("\x28\xb5\x2f\xfd", 4))
    return Compression::kZstd;
  return Compression::kNone;
}

const char* CompressionName(Compression c) {
  switch (c) {
    case Compression::kGzip:
      return "gzip";
    case Compression::kZstd:
      return "zstd";
    case Compression::kNone:
      break;
  }
  return "";
}

std::string WithoutCompressionSuffix(const std::string& path) {
  for (const char* suffix : {".gz", ".gzip", ".zst", ".zstd"}) {
    const std::string s(suffix);
    if (path.size() > s.size() &&
        Lower(path.substr(path.size() - s.size())) == s)
      return path.substr(0, path.size() - s.size());
  }
  return path;
}

bool Decompress(std::string_view data,
                Compression c,
                std::uint64_t max_bytes,
                bool partial,
                std::string* out,
                std::string* why) {
  out->clear();
  switch (c) {
    case Compression::kGzip:
      return Gunzip(data, max_bytes, partial, out, why);
    case Compression::kZstd:
      return Unzstd(data, max_bytes, partial, out, why);
    case Compression::kNone:
      break;
  }
  if (data.size() > max_bytes && !partial)
    return Fail(why, "larger than the bound");
  out->assign(data.substr(0,
                          static_cast<std::size_t>(std::min<std::uint64_t>(
                              data.size(), max_bytes))));
  return true;
}

}  // namespace wearscar::support
