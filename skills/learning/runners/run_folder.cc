#include "skills/learning/runners/run_folder.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <vector>

#include "core/atomic_file.h"
#include "core/check.h"
#include "flsd_commit.h"

namespace flsd {

RunFolder OpenRunFolder(const std::string& run_dir, bool resume) {
  namespace fs = std::filesystem;
  RunFolder folder{run_dir, (fs::path(run_dir) / "config.yaml").string(), (fs::path(run_dir) / "checkpoint.pt").string(),
                   (fs::path(run_dir) / "progress.csv").string()};
  if (resume && !fs::exists(folder.checkpoint)) {
    throw InputError(run_dir + ": nothing to resume (no checkpoint.pt)");
  }
  if (!resume && fs::exists(folder.checkpoint)) {
    throw InputError(run_dir + " already holds a run (checkpoint.pt): pass --resume to continue it, "
                     "or choose another --out");
  }
  return folder;
}

std::optional<int> ParseIteration(const std::string& text) {
  if (text.empty() || text.size() > 9 || text.find_first_not_of("0123456789") != std::string::npos) return {};
  return std::stoi(text);
}

std::string KeptCheckpointPath(const std::string& run_dir, int iteration) {
  return (std::filesystem::path(run_dir) / "checkpoints" / (std::to_string(iteration) + ".pt")).string();
}

std::vector<int> KeptIterations(const std::string& run_dir) {
  namespace fs = std::filesystem;
  std::vector<int> kept;
  const fs::path dir = fs::path(run_dir) / "checkpoints";
  if (fs::is_directory(dir)) {
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::optional<int> kept_iteration = ParseIteration(entry.path().stem().string());
      if (entry.path().extension() == ".pt" && kept_iteration) kept.push_back(*kept_iteration);
    }
  }
  std::sort(kept.begin(), kept.end());
  return kept;
}

std::string RunCheckpoint(const std::string& run_dir, int iteration) {
  namespace fs = std::filesystem;
  if (iteration == 0) return (fs::path(run_dir) / "checkpoint.pt").string();
  const std::string path = KeptCheckpointPath(run_dir, iteration);
  if (fs::exists(path)) return path;
  const std::vector<int> kept = KeptIterations(run_dir);
  std::string list;
  for (int k : kept) list += (list.empty() ? "" : ", ") + std::to_string(k);
  throw InputError(run_dir + " kept no checkpoint of iteration " + std::to_string(iteration) + " (" +
                   (kept.empty() ? std::string("it kept none") : "kept: " + list) + ")");
}

void KeepCheckpoint(const RunFolder& folder, int iteration) {
  namespace fs = std::filesystem;
  const std::string path = KeptCheckpointPath(folder.dir, iteration);
  fs::create_directories(fs::path(path).parent_path());
  WriteFileAtomically(path, [&](const std::string& temp_path) {
    fs::copy_file(folder.checkpoint, temp_path, fs::copy_options::overwrite_existing);
  });
}

void RecordRunStart(const RunFolder& folder, const std::string& config_yaml, bool resume,
                    const std::string& from_checkpoint) {
  namespace fs = std::filesystem;
  fs::create_directories(folder.dir);
  WriteFileAtomically(folder.config_file, config_yaml + "\n");
  std::ofstream commits((fs::path(folder.dir) / "commits").string(), std::ios::app);
  commits << FLSD_GIT_COMMIT << (resume ? " (resumed)" : "")
          << (from_checkpoint.empty() ? "" : " (from " + from_checkpoint + ")") << "\n";
}

}  // namespace flsd
