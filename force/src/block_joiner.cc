#include "wearscar/force/block_joiner.h"

#include <fmt/format.h>
#include <fnmatch.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

#include "wearscar/force/force_record.h"

namespace wearscar::force {
namespace {

namespace fs = std::filesystem;

// At most this much of a block is taken in one update (the rest at the
// next): memory stays bounded however far behind the watch is.
constexpr std::uintmax_t kMostBytes = std::uintmax_t{16} << 20;

std::string Name(const std::string& path) {
  return fs::path(path).filename().string();
}

}  // namespace

bool NaturalLess(const std::string& a, const std::string& b) {
  const auto digit = [](char c) {
    return std::isdigit(static_cast<unsigned char>(c)) != 0;
  };
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (digit(a[i]) && digit(b[j])) {
      size_t ie = i, je = j;
      while (ie < a.size() && digit(a[ie])) ++ie;
      while (je < b.size() && digit(b[je])) ++je;
      // Compared as numbers: without leading zeros, the longer is larger.
      size_t ia = i, jb = j;
      while (ia + 1 < ie && a[ia] == '0') ++ia;
      while (jb + 1 < je && b[jb] == '0') ++jb;
      if (ie - ia != je - jb) return ie - ia < je - jb;
      const int c = a.compare(ia, ie - ia, b, jb, je - jb);
      if (c != 0) return c < 0;
      i = ie;
      j = je;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j || (i == a.size() && j != b.size());
}

BlockJoiner::BlockJoiner(std::string folder,
                         std::string pattern,
                         std::string joined)
    : folder_(std::move(folder)),
      pattern_(std::move(pattern)),
      joined_(std::move(joined)) {
  std::error_code ec;
  if (!fs::is_directory(folder_, ec))
    throw ForceError(folder_ +
                     " is not a folder (the blocks' folder is expected)");
  if (pattern_.empty())
    throw ForceError(folder_ + ": an empty pattern for its blocks");
  std::ofstream(joined_, std::ios::binary | std::ios::trunc);
}

std::vector<std::string> BlockJoiner::Blocks() const {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(folder_, ec)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file(ec) &&
        fnmatch(pattern_.c_str(), name.c_str(), 0) == 0)
      names.push_back(name);
  }
  std::sort(names.begin(), names.end(), NaturalLess);
  for (std::string& n : names) n = (fs::path(folder_) / n).string();
  return names;
}

bool BlockJoiner::Append(bool finished) {
  // Only what the block holds beyond offset_ (at most kMostBytes): a look
  // at a block that has not grown reads and allocates nothing.
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(taken_.back(), ec);
  const std::uintmax_t left = ec || size < offset_ ? 0 : size - offset_;
  std::string text(static_cast<size_t>(std::min(left, kMostBytes)), '\0');
  if (!text.empty()) {
    std::ifstream in(taken_.back(), std::ios::binary);
    in.seekg(static_cast<std::streamoff>(offset_));
    in.read(text.data(), static_cast<std::streamsize>(text.size()));
    text.resize(static_cast<size_t>(in.gcount()));
  }
  const bool to_end = left <= kMostBytes;
  size_t take = text.size();
  if (!(finished && to_end)) {
    const size_t eol = text.rfind('\n');
    take = eol == std::string::npos ? 0 : eol + 1;
  }
  if (take == 0) return finished && to_end;
  std::ofstream out(joined_, std::ios::binary | std::ios::app);
  out.write(text.data(), static_cast<std::streamsize>(take));
  if (take == text.size() && text.back() != '\n') out << '\n';
  if (!out) throw ForceError(joined_ + ": cannot write the blocks' joining");
  offset_ += take;
  return finished && to_end && take == text.size();
}

std::string BlockJoiner::Update() {
  const std::vector<std::string> blocks = Blocks();
  std::string note;
  if (taken_.empty()) {
    if (blocks.empty()) return note;
    taken_.push_back(blocks.front());
    note = fmt::format("block {} started", Name(taken_.back()));
  }
  for (;;) {
    const auto next =
        std::find_if(blocks.begin(), blocks.end(), [&](const std::string& b) {
          return NaturalLess(taken_.back(), b);
        });
    if (next == blocks.end()) {
      Append(false);
      return note;
    }
    // A later block exists: this one is finished.
    if (!Append(true)) return note;  // more than one update's bytes
    taken_.push_back(*next);
    offset_ = 0;
    note += fmt::format("{}block {} finished; block {} started",
                        note.empty() ? "" : "; ",
                        Name(taken_[taken_.size() - 2]),
                        Name(taken_.back()));
  }
}

}  // namespace wearscar::force
