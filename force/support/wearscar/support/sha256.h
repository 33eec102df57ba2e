// SHA-256 of a file's bytes by OpenSSL's EVP (a target using this links
// OpenSSL::Crypto).
#pragma once

#include <openssl/evp.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace wearscar::support {

struct FileChecksum {
  std::string sha256;  // 64 lowercase hex digits; empty on failure
  std::uintmax_t bytes = 0;
  std::string error;  // why there is none (cannot open, read error, stopped)
};

// Streams `path` in 1 MiB blocks (constant memory). `stop`, when given, is
// read between blocks: set, the hashing ends at once with an error (a
// reader that failed early does not wait for the rest of a huge file).
inline FileChecksum Sha256OfFile(const std::string& path,
                                 const std::atomic<bool>* stop = nullptr) {
  FileChecksum out;
  struct Closer {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  struct Freer {
    void operator()(EVP_MD_CTX* c) const { EVP_MD_CTX_free(c); }
  };
  std::unique_ptr<std::FILE, Closer> f(std::fopen(path.c_str(), "rb"));
  if (!f) {
    out.error = std::strerror(errno);
    return out;
  }
  std::unique_ptr<EVP_MD_CTX, Freer> ctx(EVP_MD_CTX_new());
  if (!ctx || EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr) != 1) {
    out.error = "SHA-256 is not available";
    return out;
  }
  std::vector<unsigned char> block(std::size_t{1} << 20);
  std::size_t got = 0;
  while ((got = std::fread(block.data(), 1, block.size(), f.get())) > 0) {
    if (stop != nullptr && stop->load(std::memory_order_relaxed)) {
      out.error = "stopped";
      return out;
    }
    EVP_DigestUpdate(ctx.get(), block.data(), got);
    out.bytes += got;
  }
  if (std::ferror(f.get())) {
    out.error = "read error";
    return out;
  }
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  EVP_DigestFinal_ex(ctx.get(), digest, &length);
  static const char kHex[] = "0123456789abcdef";
  for (unsigned int i = 0; i < length; ++i) {
    out.sha256 += kHex[digest[i] >> 4];
    out.sha256 += kHex[digest[i] & 15];
  }
  return out;
}

}  // namespace wearscar::support
