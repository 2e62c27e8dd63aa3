#include "client/web/users_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>

#include "client/web/credentials.h"
#include "core/atomic_file.h"
#include "core/check.h"

namespace flsd::web {
namespace {

// make_pki.sh's rule for identity names, which user names follow too.
const std::regex kName("[A-Za-z0-9_.-]{1,40}");

std::string Format(const User& u) {
  return u.name + " " + RoleName(u.role) + " " + u.identity + " " + u.password_hash + "\n";
}

}  // namespace

const char* RoleName(Role role) { return role == Role::kOperator ? "operator" : "observer"; }

std::string UserFieldError(const std::string& name, const std::string& role, const std::string& identity) {
  if (!std::regex_match(name, kName)) return "user name '" + name + "' must be 1-40 of [A-Za-z0-9_.-]";
  if (role != "operator" && role != "observer") return "role must be operator or observer, got '" + role + "'";
  if (identity != "-" && !std::regex_match(identity, kName)) {
    return "identity '" + identity + "' must be a make_pki.sh identity name (1-40 of [A-Za-z0-9_.-]) or '-'";
  }
  return "";
}

Users LoadUsers(const std::string& path) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) throw InputError("--users " + path + ": " + std::strerror(errno));
  if ((st.st_mode & (S_IRWXG | S_IRWXO)) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    throw InputError("--users " + path + " has mode " + mode +
                     "; it holds password hashes and must be readable by its owner only (chmod 600)");
  }
  std::ifstream in(path);
  if (!in) throw InputError("--users " + path + ": cannot read");
  Users users;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    line = line.substr(0, line.find('#'));
    std::istringstream fields(line);
    std::string name, role, identity, hash, extra;
    if (!(fields >> name)) continue;
    const std::string where = path + ":" + std::to_string(number) + ": ";
    if (!(fields >> role >> identity >> hash) || (fields >> extra)) {
      throw InputError(where + "expected NAME ROLE IDENTITY PASSWORD_HASH");
    }
    std::string error = UserFieldError(name, role, identity);
    if (error.empty()) error = PasswordHashError(hash);
    if (error.empty() && users.count(name)) error = "user '" + name + "' appears twice";
    if (!error.empty()) throw InputError(where + error);
    users[name] = User{name, role == "operator" ? Role::kOperator : Role::kObserver, identity, hash};
  }
  return users;
}

void SaveUser(const std::string& path, const User& user) {
  Users users;
  if (access(path.c_str(), F_OK) == 0) users = LoadUsers(path);
  users[user.name] = user;
  std::string text = "# skillweb users: NAME ROLE IDENTITY PASSWORD_HASH (docs/skillweb.md)\n";
  for (const auto& [name, u] : users) text += Format(u);
  WriteFileAtomically(path, [&text](const std::string& temp) {
    // Created 0600 from the start: the hashes are never readable by others, even briefly.
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0) throw InputError(temp + ": " + std::strerror(errno));
    const bool written = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
    ::close(fd);
    if (!written) throw InputError(temp + ": write failed");
  });
}

}  // namespace flsd::web
