#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "wearscar/scan/height_map.h"
#include "wearscar/scan/read_scan.h"

namespace wearscar::scan {

// How sure a format is that some bytes are its own (Gwyddion's detect
// score): the highest score reads the file.
inline constexpr int kDetectMagic = 100;     // its magic bytes are there
inline constexpr int kDetectExtension = 50;  // no magic; the name says so
inline constexpr int kDetectText = 20;       // a text layout it recognises
inline constexpr int kDetectFallback = 1;    // anything else it may try

// One height-map format: what ReadScan, the audit's pairing of files, the
// help text and the fuzz targets read. The registry (ScanFormats) lists
// them; adding a format is one source file defining its ScanFormat and one
// line in scan/src/format_list.h.
struct ScanFormat {
  std::string name;                     // "plu": registry key, fuzz target
  std::string title;                    // "Sensofar .plu"
  std::string instruments;              // who writes it, for the docs and help
  std::vector<std::string> extensions;  // lower case, with the dot
  // Bytes at offset 0 that every file of the format starts with; empty
  // when the format has none. A file named like the format without them is
  // refused with a message that names them.
  std::vector<std::string> magics;
  // Score (kDetect...) for a file whose first bytes are `head` (at most
  // kDetectHeadBytes) and whose lower-case extension is `extension`; 0 when
  // the file is not of this format.
  int (*detect)(std::string_view head, std::string_view extension) = nullptr;
  // Reads the whole file; `name` appears in every error. Throws ScanError.
  HeightMap (*parse)(const std::string& bytes,
                     const std::string& name,
                     const ReadScanOptions& options) = nullptr;
};

inline constexpr std::size_t kDetectHeadBytes = 1 << 16;

// Every format, in the order that breaks ties between equal scores.
const std::vector<ScanFormat>& ScanFormats();

// The format named `name` ("zon", "plu", ...), or nullptr.
const ScanFormat* FindScanFormat(std::string_view name);

// The format that reads `bytes` of a file named `path`, chosen by score;
// throws ScanError when a file named like a format lacks its magic.
const ScanFormat& DetectScanFormat(const std::string& bytes,
                                   const std::string& path);

// The binary format of the file at `path` by its first bytes and name
// (score kDetectExtension or more), or nullptr for text, for a file that
// cannot be opened and for anything else: how the audit tells scans from
// force records (".dat" is a Zygo map or a force export by its content).
const ScanFormat* BinaryScanFormatOf(const std::string& path);

// The format whose detect score for the file at `path` is at least
// `min_score` (kDetectText: a text layout it recognises, such as a Keyence
// VR CSV), or nullptr: how the audit tells a text height map whose name
// says nothing from a force export.
const ScanFormat* ScanFormatOf(const std::string& path, int min_score);

// "zon, zag, vk4, vk6, vk7, x3p, gsf, plu, al3d, opd, sur, dat, csv, txt"
// for help strings.
std::string ScanExtensionList();

// The lower-case extension of `path`, with the dot ("" when none).
std::string LowerExtension(const std::string& path);

}  // namespace wearscar::scan
