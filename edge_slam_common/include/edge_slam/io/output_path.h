// Output files (statistics, metrics, trajectories) may name a folder that does not exist yet:
// it is created, so `out:=<new folder>` just works. Throws naming the folder when it cannot be.
#pragma once
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

namespace edge_slam {

inline void ensure_parent_directory(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (parent.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(parent, ec);
  if (ec) throw std::runtime_error("cannot create the folder '" + parent.string() + "': " + ec.message());
}

}  // namespace edge_slam
