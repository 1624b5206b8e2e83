// Runs some of this test binary's own tests again in a child process served by jemalloc
// (libjemalloc.so.2 preloaded, as the launch files' allocator:=jemalloc does), so the heap
// readings and the page release are tested on both allocators the nodes can run on.
#pragma once
#include <glob.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace edge_slam {
namespace test_support {

// Set in the child: the tests there check that jemalloc, not glibc, answered.
constexpr const char* kExpectAllocatorVariable = "EDGE_SLAM_TEST_EXPECT_ALLOCATOR";

inline bool jemalloc_installed() {
  glob_t g{};
  const bool found = glob("/usr/lib/*/libjemalloc.so.2", 0, nullptr, &g) == 0 ||
                     glob("/usr/lib/libjemalloc.so.2", 0, nullptr, &g) == 0 ||
                     glob("/usr/local/lib/libjemalloc.so.2", 0, nullptr, &g) == 0;
  globfree(&g);
  return found;
}

// The expected allocator when this process is the child; nullptr otherwise.
inline const char* expected_allocator() { return std::getenv(kExpectAllocatorVariable); }

struct ChildRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

// /proc/self/exe --gtest_filter=<filter> with libjemalloc.so.2 preloaded.
inline ChildRun run_under_jemalloc(const std::string& filter) {
  const std::string command = std::string("env LD_PRELOAD=libjemalloc.so.2 ") + kExpectAllocatorVariable +
                              "=jemalloc /proc/" + std::to_string(getpid()) + "/exe --gtest_filter='" + filter +
                              "' 2>&1";
  ChildRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  std::array<char, 4096> buffer{};
  size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

}  // namespace test_support
}  // namespace edge_slam
