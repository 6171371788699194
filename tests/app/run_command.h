// Runs the proxygrasp executable in tests and captures what it prints and its exit code.
#pragma once

#include "test_paths.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>
#include <sys/wait.h>

namespace pg::test {

struct CommandResult {
  int exitCode = -1;
  std::string output;  ///< stdout and stderr together
};

/// Runs `proxygrasp <args>` through the shell; args are pasted as they are.
inline CommandResult RunProxygrasp(const std::string& args) {
  CommandResult result;
  const std::string command = std::string(pg::test::ProxygraspBin()) + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer;
  size_t n = 0;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

/// A fresh, empty folder "<prefix>_<name>" under the test's temporary folder.
inline std::string FreshDir(const std::string& prefix, const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/" + prefix + "_" + name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace pg::test
