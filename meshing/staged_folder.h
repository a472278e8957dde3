// Folders written whole or not at all (docs/robustness.md, "Interrupted runs"):
// their files go to a staging folder beside them, <dir>.tmp<pid>, which is renamed
// into place once every file is written. A run interrupted by a signal (SIGINT,
// SIGTERM, SIGKILL) leaves the folder as it was, or whole, and at most a staging
// folder, which the next run writing the same folder removes (the process whose
// pid it names no longer exists) and which readers of results skip by its name.
#pragma once

#include <filesystem>
#include <string>

namespace tb {

/// `<dir>.tmp<this process's pid>`: where the files of `dir` are staged.
std::filesystem::path staging_folder(const std::filesystem::path& dir);

/// Removes `<dir>.tmp<pid>` and `<dir>.old<pid>` folders left by processes that no
/// longer exist (a killed run). Best effort: errors are ignored.
void remove_stale_staging(const std::filesystem::path& dir);

/// Replaces `dir` by `staging` (two renames: the old folder to `<dir>.old<pid>`,
/// the staging folder into place; then the old one is removed). A reader sees the
/// old folder, nothing, or the new one, never a mix. Throws on failure.
void replace_folder(const std::filesystem::path& staging, const std::filesystem::path& dir);

}  // namespace tb
