#pragma once
// skillweb's users file (--users): who may log in, in which role, as which DDS identity. One user
// a line, fields separated by spaces, '#' starts a comment:
//
//   NAME ROLE IDENTITY PASSWORD_HASH
//   alice operator alice pbkdf2-sha256$200000$5f0c...$9a4e...
//
// ROLE is operator (watches and commands) or observer (watches only); IDENTITY is the folder
// scripts/make_pki.sh made for that user (under skillweb's --pki), or '-' without DDS Security.
// The file holds password hashes: it must be readable by its owner only, as `--add-user` writes it.

#include <map>
#include <string>

namespace flsd::web {

enum class Role { kOperator, kObserver };
const char* RoleName(Role role);

struct User {
  std::string name;
  Role role = Role::kObserver;
  std::string identity;  // "-": none
  std::string password_hash;
};

using Users = std::map<std::string, User>;

// The users of `path`; InputError naming the file and line for anything malformed, and for a
// file others may read.
Users LoadUsers(const std::string& path);

// Adds `user` to `path` (creating it), replacing a user of the same name; the file is rewritten
// atomically with mode 0600.
void SaveUser(const std::string& path, const User& user);

// Why `name`, `role` or `identity` cannot be a user's; "" if they can.
std::string UserFieldError(const std::string& name, const std::string& role, const std::string& identity);

}  // namespace flsd::web
