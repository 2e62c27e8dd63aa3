#pragma once
// Secrets for skillweb's logins, all from OpenSSL: random tokens, and passwords stored as
// PBKDF2-HMAC-SHA256 with a salt of their own, "pbkdf2-sha256$ITERATIONS$SALT$HASH" (hex), so
// that a stolen users file costs an attacker a slow hash per guess and per user.

#include <string>

namespace flsd::web {

constexpr int kPasswordIterations = 200000;  // about 0.1 s per login on one core

// `bytes` random bytes from OpenSSL's generator, in hex.
std::string RandomHex(std::size_t bytes);

// A stored hash of `password` with a new random salt.
std::string HashPassword(const std::string& password, int iterations = kPasswordIterations);

// Why `stored` is not a hash HashPassword makes; "" if it is.
std::string PasswordHashError(const std::string& stored);

// Whether `password` is the one `stored` was made from; compared in constant time.
bool VerifyPassword(const std::string& password, const std::string& stored);

// Equal strings, compared in time that depends on their length only.
bool SameSecret(const std::string& a, const std::string& b);

}  // namespace flsd::web
