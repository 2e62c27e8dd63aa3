#include "core/paths.h"

#include <cstdlib>
#include <filesystem>

#include "core/check.h"

namespace flsd {

std::string ResolveDataPath(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  if (p.is_absolute() || fs::exists(p)) return path;
  std::string tried = fs::absolute(p).string();
  const char* roots[] = {std::getenv("FLSD_ROOT"), FLSD_SOURCE_DIR};
  for (const char* root : roots) {
    if (root == nullptr || *root == '\0') continue;
    const fs::path candidate = fs::path(root) / p;
    if (fs::exists(candidate)) return candidate.string();
    tried += ", " + candidate.string();
  }
  throw InputError("file not found: '" + path + "' (tried " + tried + ")");
}

std::string ProgramPath(const std::string& exe_link) {
  static const std::string kDeleted = " (deleted)";
  std::string path = std::filesystem::read_symlink(exe_link).string();
  const bool deleted = path.size() > kDeleted.size() &&
                       path.compare(path.size() - kDeleted.size(), kDeleted.size(), kDeleted) == 0;
  if (deleted && !std::filesystem::exists(path)) path.resize(path.size() - kDeleted.size());
  return path;
}

}  // namespace flsd
