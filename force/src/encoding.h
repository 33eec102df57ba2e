#pragma once
// What a force file's first bytes say before any line is read: a workbook
// or document instead of text (refused), UTF-16 text (converted), lines
// ended by CR alone.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

namespace wearscar::force::internal {

// The most text a force file is read whole as (UTF-16 or CR line ends)
// and in one pass without counting its lines first.
inline constexpr std::uintmax_t kWholeTextMaxBytes = std::uintmax_t{256} << 20;
// What a compressed force file may expand to (read whole in memory).
inline constexpr std::uintmax_t kCompressedMaxBytes = std::uintmax_t{2} << 30;

// UTF-16 text (a byte order mark, or a NUL beside each of the first two
// ASCII bytes) from its first bytes, as iconv names its encoding; null for
// anything else.
const char* Utf16Encoding(std::string_view first);

// UTF-16 text as UTF-8 (what Excel's "Unicode Text" and some instruments'
// Windows software write), read block by block from `read` (bytes into a
// buffer, 0 at the end), each block handed to `on_bytes` (if any) as it
// is. At most kWholeTextMaxBytes; an ill-formed or cut sequence is refused
// at its byte offset.
std::string Utf16ToUtf8(
    const std::function<std::size_t(char*, std::size_t)>& read,
    const char* encoding,
    const std::string& name,
    std::uintmax_t size_hint,
    const std::function<void(const char*, std::size_t)>& on_bytes);

// Throws ForceError when the first bytes are a workbook or a document (a
// spreadsheet saved as such rather than as CSV is a common first attempt),
// saying what it is and what to do.
void RefuseWorkbook(std::string_view first, const std::string& name);

// Lines ended by CR alone (Excel's "CSV (Macintosh)", classic Mac OS): a
// CR and no LF in the first 64 KiB.
bool EndsLinesWithCrAlone(std::string_view first);

}  // namespace wearscar::force::internal
