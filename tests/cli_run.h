// Running the tissuebench program from a test: its exit status and what it printed.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace tb::testing {

/// Runs `TB_CLI args` (TB_CLI: the tissuebench program, defined for every test
/// executable in tests/CMakeLists.txt) through the shell, after `env` (environment
/// assignments, e.g. "TISSUEBENCH_DATA=/x", or empty), with stderr joined to stdout;
/// returns its exit status (-1 if it did not exit) and its output in `output`.
inline int run_tissuebench(const std::string& args, std::string& output, const std::string& env = "") {
  FILE* p = popen((env + " " + std::string(TB_CLI) + " " + args + " 2>&1").c_str(), "r");
  if (!p) return -1;
  output.clear();
  char buffer[4096];
  while (size_t n = fread(buffer, 1, sizeof buffer, p)) output.append(buffer, n);
  const int status = pclose(p);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace tb::testing
