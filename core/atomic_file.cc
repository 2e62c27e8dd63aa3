#include "core/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/check.h"

namespace flsd {
namespace {

void SyncFile(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) throw InputError(path + ": cannot reopen to sync: " + std::strerror(errno));
  const int rc = ::fsync(fd);
  ::close(fd);
  if (rc != 0) throw InputError(path + ": fsync failed: " + std::strerror(errno));
}

}  // namespace

void WriteFileAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
  static std::atomic<unsigned> counter{0};
  const std::string temp = path + ".tmp" + std::to_string(::getpid()) + "." + std::to_string(counter++);
  try {
    write(temp);
    SyncFile(temp);
    std::error_code ec;
    std::filesystem::rename(temp, path, ec);
    if (ec) throw InputError(path + ": cannot replace with " + temp + ": " + ec.message());
    // The rename itself lives in the directory: sync it too, or a crash may undo it.
    const std::filesystem::path parent = std::filesystem::absolute(path).parent_path();
    const int dir = ::open(parent.c_str(), O_RDONLY | O_DIRECTORY);
    if (dir >= 0) {
      ::fsync(dir);
      ::close(dir);
    }
  } catch (...) {
    std::remove(temp.c_str());
    throw;
  }
}

void WriteFileAtomically(const std::string& path, const std::string& contents) {
  WriteFileAtomically(path, [&](const std::string& temp) {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.close();
    if (!out) throw InputError(temp + ": write failed");
  });
}

}  // namespace flsd
