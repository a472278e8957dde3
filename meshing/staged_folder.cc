#include "staged_folder.h"

#include <signal.h>
#include <unistd.h>

namespace tb {
namespace fs = std::filesystem;

fs::path staging_folder(const fs::path& dir) { return dir.string() + ".tmp" + std::to_string(::getpid()); }

void remove_stale_staging(const fs::path& dir) {
  std::error_code ec;
  const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
  if (!fs::exists(parent, ec)) return;
  const std::string stem = dir.filename().string();
  for (const auto& entry : fs::directory_iterator(parent, ec)) {
    const std::string name = entry.path().filename().string();
    for (const std::string tag : {".tmp", ".old"}) {
      if (name.rfind(stem + tag, 0) != 0) continue;
      const std::string pid = name.substr(stem.size() + tag.size());
      if (pid.empty() || pid.size() > 9 || pid.find_first_not_of("0123456789") != std::string::npos) continue;
      const long p = std::stol(pid);
      // Our own pid: a folder of this process's earlier attempt, replaced anyway.
      if (p == ::getpid() || ::kill(static_cast<pid_t>(p), 0) != 0) fs::remove_all(entry.path(), ec);
    }
  }
}

void replace_folder(const fs::path& staging, const fs::path& dir) {
  const fs::path old = dir.string() + ".old" + std::to_string(::getpid());
  std::error_code ec;
  fs::remove_all(old, ec);
  if (fs::exists(dir)) fs::rename(dir, old);
  fs::rename(staging, dir);
  fs::remove_all(old, ec);
}

}  // namespace tb
