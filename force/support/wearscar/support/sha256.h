// SHA-256 by OpenSSL's EVP (a target using this links OpenSSL::Crypto).
#pragma once

#include <openssl/evp.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

namespace wearscar::support {

// A digest fed block by block: Update, then Hex once (64 lowercase hex
// digits; empty when SHA-256 is not available).
class Sha256 {
 public:
  Sha256() : ctx_(EVP_MD_CTX_new()) {
    if (ctx_ && EVP_DigestInit_ex(ctx_.get(), EVP_sha256(), nullptr) != 1)
      ctx_.reset();
  }
  void Update(const void* data, std::size_t bytes) {
    if (ctx_) EVP_DigestUpdate(ctx_.get(), data, bytes);
    bytes_ += bytes;
  }
  std::uintmax_t bytes() const { return bytes_; }
  std::string Hex() {
    if (!ctx_) return "";
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    EVP_DigestFinal_ex(ctx_.get(), digest, &length);
    ctx_.reset();
    static const char kHex[] = "0123456789abcdef";
    std::string hex;
    for (unsigned int i = 0; i < length; ++i) {
      hex += kHex[digest[i] >> 4];
      hex += kHex[digest[i] & 15];
    }
    return hex;
  }

 private:
  struct Free {
    void operator()(EVP_MD_CTX* c) const { EVP_MD_CTX_free(c); }
  };
  std::unique_ptr<EVP_MD_CTX, Free> ctx_;
  std::uintmax_t bytes_ = 0;
};

// The SHA-256 (hex) of a file's bytes, streamed in 64 KiB blocks; empty
// with `error` set when it cannot be read.
inline std::string Sha256OfFile(const std::string& path, std::string* error) {
  struct Closer {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  std::unique_ptr<std::FILE, Closer> f(std::fopen(path.c_str(), "rb"));
  if (!f) {
    *error = std::strerror(errno);
    return "";
  }
  Sha256 hash;
  unsigned char block[std::size_t{1} << 16];
  std::size_t got = 0;
  while ((got = std::fread(block, 1, sizeof block, f.get())) > 0)
    hash.Update(block, got);
  if (std::ferror(f.get())) {
    *error = "read error";
    return "";
  }
  std::string hex = hash.Hex();
  if (hex.empty()) *error = "SHA-256 is not available";
  return hex;
}

}  // namespace wearscar::support
