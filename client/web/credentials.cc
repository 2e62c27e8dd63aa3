#include "client/web/credentials.h"

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/rand.h>

#include <stdexcept>
#include <vector>

namespace flsd::web {
namespace {

constexpr char kScheme[] = "pbkdf2-sha256";
constexpr std::size_t kSaltBytes = 16, kHashBytes = 32;

std::string Hex(const unsigned char* data, std::size_t size) {
  static const char digits[] = "0123456789abcdef";
  std::string text;
  for (std::size_t i = 0; i < size; ++i) {
    text += digits[data[i] >> 4];
    text += digits[data[i] & 15];
  }
  return text;
}

bool FromHex(const std::string& text, std::vector<unsigned char>& bytes) {
  if (text.size() % 2 != 0) return false;
  bytes.clear();
  for (std::size_t i = 0; i < text.size(); i += 2) {
    const auto nibble = [](char c) {
      return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
    };
    const int high = nibble(text[i]), low = nibble(text[i + 1]);
    if (high < 0 || low < 0) return false;
    bytes.push_back(static_cast<unsigned char>(high * 16 + low));
  }
  return true;
}

std::string Pbkdf2(const std::string& password, const std::vector<unsigned char>& salt, int iterations) {
  unsigned char hash[kHashBytes];
  if (PKCS5_PBKDF2_HMAC(password.data(), static_cast<int>(password.size()), salt.data(), static_cast<int>(salt.size()),
                        iterations, EVP_sha256(), sizeof hash, hash) != 1) {
    throw std::runtime_error("PKCS5_PBKDF2_HMAC failed");
  }
  return Hex(hash, sizeof hash);
}

struct Parsed {
  int iterations = 0;
  std::vector<unsigned char> salt;
  std::string hash;
};

// "" and `out` filled, or why `stored` is malformed.
std::string Parse(const std::string& stored, Parsed& out) {
  const std::string expected = std::string("expected ") + kScheme + "$ITERATIONS$SALT$HASH (hex)";
  const auto a = stored.find('$'), b = stored.find('$', a + 1), c = stored.find('$', b + 1);
  if (c == std::string::npos || stored.substr(0, a) != kScheme) return expected;
  const std::string iterations = stored.substr(a + 1, b - a - 1);
  if (iterations.empty() || iterations.size() > 9 || iterations.find_first_not_of("0123456789") != std::string::npos) {
    return expected;
  }
  out.iterations = std::stoi(iterations);
  if (out.iterations < 10000) return "at least 10000 iterations, got " + iterations;
  std::vector<unsigned char> hash;
  out.hash = stored.substr(c + 1);
  if (!FromHex(stored.substr(b + 1, c - b - 1), out.salt) || out.salt.size() < 8 || !FromHex(out.hash, hash) ||
      hash.size() != kHashBytes) {
    return expected + ", with a salt of 8 bytes or more and a 32-byte hash";
  }
  return "";
}

}  // namespace

std::string RandomHex(std::size_t bytes) {
  std::vector<unsigned char> data(bytes);
  if (RAND_bytes(data.data(), static_cast<int>(bytes)) != 1) throw std::runtime_error("RAND_bytes failed");
  return Hex(data.data(), bytes);
}

std::string HashPassword(const std::string& password, int iterations) {
  std::vector<unsigned char> salt(kSaltBytes);
  if (RAND_bytes(salt.data(), static_cast<int>(salt.size())) != 1) throw std::runtime_error("RAND_bytes failed");
  return std::string(kScheme) + "$" + std::to_string(iterations) + "$" + Hex(salt.data(), salt.size()) + "$" +
         Pbkdf2(password, salt, iterations);
}

std::string PasswordHashError(const std::string& stored) {
  Parsed parsed;
  return Parse(stored, parsed);
}

bool VerifyPassword(const std::string& password, const std::string& stored) {
  Parsed parsed;
  if (!Parse(stored, parsed).empty()) return false;
  return SameSecret(Pbkdf2(password, parsed.salt, parsed.iterations), parsed.hash);
}

bool SameSecret(const std::string& a, const std::string& b) {
  return a.size() == b.size() && CRYPTO_memcmp(a.data(), b.data(), a.size()) == 0;
}

}  // namespace flsd::web
