#include "wearscar/fusion/provenance.h"

#include <fmt/format.h>
#include <openssl/evp.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>
#include <vector>

#include "wearscar/fusion/error.h"

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

struct Sha256::Context {
  struct Free {
    void operator()(EVP_MD_CTX* c) const { EVP_MD_CTX_free(c); }
  };
  std::unique_ptr<EVP_MD_CTX, Free> digest{EVP_MD_CTX_new()};
};

Sha256::Sha256() : context_(std::make_unique<Context>()) {
  if (!context_->digest ||
      EVP_DigestInit_ex(context_->digest.get(), EVP_sha256(), nullptr) != 1)
    throw FusionError("SHA-256 is not available");
}

Sha256::~Sha256() = default;

void Sha256::Update(const char* bytes, std::size_t size) {
  EVP_DigestUpdate(context_->digest.get(), bytes, size);
}

std::string Sha256::Hex() {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  EVP_DigestFinal_ex(context_->digest.get(), digest, &length);
  std::string hex;
  for (unsigned int i = 0; i < length; ++i)
    hex += fmt::format("{:02x}", digest[i]);
  return hex;
}

std::string Sha256OfFile(const std::string& path) {
  Sha256 hash;
  std::unique_ptr<std::FILE, FileCloser> f(std::fopen(path.c_str(), "rb"));
  if (!f) {
    throw FusionError(fmt::format(
        "{}: cannot read for its checksum: {}", path, std::strerror(errno)));
  }
  // Read through a buffer that stays in the cache: mapped instead, a large
  // force file's pages would count in the process's memory for as long as
  // the checksum takes, which runs only where a core is idle.
  std::vector<char> buffer(256 << 10);
  size_t got = 0;
  while ((got = std::fread(buffer.data(), 1, buffer.size(), f.get())) > 0)
    hash.Update(buffer.data(), got);
  if (std::ferror(f.get())) {
    throw FusionError(
        fmt::format("{}: read error while computing its checksum", path));
  }
  return hash.Hex();
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
