#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace wearscar::fusion {

// This build of wearscar: the project version ("0.1.0") and the git commit
// it was built from (40 hex digits, "-dirty" when the tree had changes;
// "unknown" outside a git checkout).
const char* Version();
const char* GitCommit();

// One input file as it was read: what it was for ("force", "scan"), its
// path, size in bytes and SHA-256 (64 hex digits).
struct InputFile {
  std::string role;
  std::string path;
  std::uintmax_t bytes = 0;
  std::string sha256;
};

// SHA-256 of bytes given piece by piece.
class Sha256 {
 public:
  Sha256();  // throws FusionError when SHA-256 is not available
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;
  void Update(const char* bytes, std::size_t size);
  // 64 hex digits; ends the digest.
  std::string Hex();

 private:
  struct Context;
  std::unique_ptr<Context> context_;
};

// The SHA-256 of a file's bytes, streamed (constant memory). Throws
// FusionError naming the file when it cannot be read.
std::string Sha256OfFile(const std::string& path);

// Size and SHA-256 of `path`; throws FusionError naming it when unreadable.
InputFile DescribeInputFile(const std::string& role, const std::string& path);

// Where a result came from: this build, when it was made (UTC, ISO 8601;
// the environment's SOURCE_DATE_EPOCH when set, for reproducible outputs)
// and the files read.
struct Provenance {
  std::string version;
  std::string commit;
  std::string date_utc;
  std::vector<InputFile> inputs;

  nlohmann::json ToJson() const;
};

// This build, now, and the inputs given.
Provenance CurrentProvenance(std::vector<InputFile> inputs = {});

}  // namespace wearscar::fusion
