#include "wearscar/fusion/provenance.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>

#include "wearscar/fusion/error.h"
#include "wearscar/support/sha256.h"

namespace wearscar::fusion {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

// Seconds since the epoch: SOURCE_DATE_EPOCH when it holds a number, else
// the clock.
std::time_t Now() {
  if (const char* s = std::getenv("SOURCE_DATE_EPOCH")) {
    char* end = nullptr;
    const long long v = std::strtoll(s, &end, 10);
    if (end != s && *end == '\0' && v >= 0) return static_cast<std::time_t>(v);
  }
  return std::time(nullptr);
}

}  // namespace

std::string Sha256OfFile(const std::string& path) {
  std::string error;
  std::string hex = support::Sha256OfFile(path, &error);
  if (hex.empty()) {
    throw FusionError(
        fmt::format("{}: cannot read for its checksum: {}", path, error));
  }
  return hex;
}

InputFile DescribeInputFile(const std::string& role, const std::string& path) {
  InputFile in;
  in.role = role;
  in.path = path;
  std::unique_ptr<std::FILE, FileCloser> f(std::fopen(path.c_str(), "rb"));
  if (!f || std::fseek(f.get(), 0, SEEK_END) != 0) {
    throw FusionError(
        fmt::format("{}: cannot read: {}", path, std::strerror(errno)));
  }
  in.bytes = static_cast<std::uintmax_t>(std::ftell(f.get()));
  in.sha256 = Sha256OfFile(path);
  return in;
}

nlohmann::json Provenance::ToJson() const {
  nlohmann::json files = nlohmann::json::array();
  for (const InputFile& in : inputs) {
    files.push_back({{"role", in.role},
                     {"path", in.path},
                     {"bytes", in.bytes},
                     {"sha256", in.sha256}});
  }
  return {{"wearscar_version", version},
          {"git_commit", commit},
          {"date_utc", date_utc},
          {"inputs", files}};
}

Provenance CurrentProvenance(std::vector<InputFile> inputs) {
  Provenance p;
  p.version = Version();
  p.commit = GitCommit();
  const std::time_t now = Now();
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  p.date_utc = text;
  p.inputs = std::move(inputs);
  return p;
}

}  // namespace wearscar::fusion
