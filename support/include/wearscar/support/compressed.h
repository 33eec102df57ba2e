#pragma once
// Files a lab compressed to save space (gzip, zstd): told by their first
// bytes, opened whole in memory within a bound on what they expand to.

#include <cstdint>
#include <string>
#include <string_view>

namespace wearscar::support {

enum class Compression { kNone, kGzip, kZstd };

// By the magic number at the start of `head` (any extension).
Compression CompressionOf(std::string_view head);

// "gzip", "zstd" or "" for kNone.
const char* CompressionName(Compression c);

// "a/oak_01.csv.gz" -> "a/oak_01.csv" (also .gzip, .zst, .zstd, any
// case); any other name unchanged.
std::string WithoutCompressionSuffix(const std::string& path);

// The bytes `data` (compressed with `c`) expand to. At most `max_bytes`
// come out: beyond that, `partial` keeps the first `max_bytes` (a file's
// head for detection), else it fails. Returns false with `why` set when
// the data are corrupt, cut short, or expand beyond the bound.
bool Decompress(std::string_view data,
                Compression c,
                std::uint64_t max_bytes,
                bool partial,
                std::string* out,
                std::string* why);

}  // namespace wearscar::support
