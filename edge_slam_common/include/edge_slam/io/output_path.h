// Output files (statistics, metrics, trajectories, KeyFrame poses) may name a folder that does
// not exist yet: it is created, so `out:=<new folder>` just works. Files other processes read
// while they are rewritten (metrics.json, the edge's KeyFrame poses) are replaced atomically.
#pragma once
#include <string>

namespace edge_slam {

// Creates the folder of `path` if needed; throws naming the folder when it cannot.
void ensure_parent_directory(const std::string& path);

// Writes `content` to `path` through a temporary file and a rename, so a reader sees the old or
// the new file, never half of one. Creates the folder; throws naming the file on any error.
void write_file_atomically(const std::string& path, const std::string& content);

}  // namespace edge_slam
