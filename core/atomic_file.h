#pragma once
#include <functional>
#include <string>

namespace flsd {

// Writes `path` all at once: `write` fills a temporary file beside it, which is flushed to disk
// and renamed over `path`. A crash leaves either the old file or the new one, never a torn one.
// Throws InputError naming the path if the write or the rename fails.
void WriteFileAtomically(const std::string& path, const std::function<void(const std::string& temp_path)>& write);

// Convenience for text and byte contents.
void WriteFileAtomically(const std::string& path, const std::string& contents);

}  // namespace flsd
