#include "server/snapshot_seal.h"

#include <sys/random.h>

#include <fstream>
#include <iterator>
#include <stdexcept>

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/hmac.h>

#include "server/wire/field_error.h"

namespace culinarycut::server {
namespace {

constexpr char kMagic[] = "CCSEAL01";  // 8 bytes, then the 32-byte tag, then the snapshot
constexpr std::size_t kMagicSize = 8;
constexpr std::size_t kTagSize = 32;
constexpr std::size_t kKeySize = 32;

std::string Tag(const std::string& key, const std::string& bytes) {
  unsigned char tag[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (!HMAC(EVP_sha256(), key.data(), static_cast<int>(key.size()), reinterpret_cast<const unsigned char*>(bytes.data()),
            bytes.size(), tag, &length) ||
      length != kTagSize) {
    throw std::runtime_error("HMAC-SHA256 failed");
  }
  return std::string(reinterpret_cast<const char*>(tag), kTagSize);
}

}  // namespace

SnapshotSeal::SnapshotSeal(const std::string& key_file) {
  if (!key_file.empty()) {
    std::ifstream in(key_file, std::ios::binary);
    if (!in) throw std::runtime_error("--snapshot-key-file " + key_file + ": cannot read it");
    key_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (key_.size() < kKeySize) {
      throw std::runtime_error("--snapshot-key-file " + key_file + ": holds " + std::to_string(key_.size()) +
                               " bytes; give at least 32 random bytes (e.g. head -c 32 /dev/urandom > FILE)");
    }
    return;
  }
  key_.resize(kKeySize);
  std::size_t filled = 0;
  while (filled < kKeySize) {
    const ssize_t got = getrandom(key_.data() + filled, kKeySize - filled, 0);
    if (got < 0) throw std::runtime_error("getrandom failed: no randomness for the snapshot key");
    filled += static_cast<std::size_t>(got);
  }
}

std::string SnapshotSeal::Seal(const std::string& snapshot) const {
  return std::string(kMagic, kMagicSize) + Tag(key_, snapshot) + snapshot;
}

std::string SnapshotSeal::Open(const std::string& sealed) const {
  if (sealed.size() < kMagicSize + kTagSize || sealed.compare(0, kMagicSize, kMagic) != 0) {
    throw FieldError("snapshot", "is not a CulinaryCut snapshot (bad header); pass the bytes SaveSnapshot returned");
  }
  const std::string snapshot = sealed.substr(kMagicSize + kTagSize);
  const std::string expected = Tag(key_, snapshot);
  if (CRYPTO_memcmp(expected.data(), sealed.data() + kMagicSize, kTagSize) != 0) {
    throw FieldError("snapshot", "was not written by this server, or was changed: its authentication tag does not "
                                 "match (servers that share snapshots must share --snapshot-key-file)");
  }
  return snapshot;
}

}  // namespace culinarycut::server
