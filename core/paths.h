#pragma once
#include <string>

namespace flsd {

// Resolves a project data file (robot model, config) given relative to the project root.
// Absolute paths and paths that exist relative to the working directory are returned as given;
// otherwise the file is looked up under $FLSD_ROOT, then under the source tree this binary was
// built from. Throws InputError naming every place tried when none has the file.
std::string ResolveDataPath(const std::string& path);

// The program a process runs, by its /proc link (this one's by default): the path to start it, or
// its siblings, again. Once the file is replaced on disk (a rebuild while it runs) Linux names it
// "PATH (deleted)"; the suffix is dropped, so that the path names the program now at PATH.
std::string ProgramPath(const std::string& exe_link = "/proc/self/exe");

}  // namespace flsd
