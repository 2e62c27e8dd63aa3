#pragma once
#include <string>

namespace flsd {

// Resolves a project data file (robot model, config) given relative to the project root.
// Absolute paths and paths that exist relative to the working directory are returned as given;
// otherwise the file is looked up under $FLSD_ROOT, then under the source tree this binary was
// built from. Throws InputError naming every place tried when none has the file.
std::string ResolveDataPath(const std::string& path);

}  // namespace flsd
