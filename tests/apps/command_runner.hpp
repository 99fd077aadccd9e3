// Runs the tumble command line as a user would, for the tests of one command each.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace tumble::test {

struct CommandOutput {
  int exit_code = -1;
  std::string text;  // stdout and stderr together
};

// `tumble <arguments>` through the shell.
inline CommandOutput run_tumble_command(const std::string& arguments) {
  std::string command = TUMBLE_CLI;
  command += ' ';
  command += arguments;
  command += " 2>&1";
  CommandOutput out;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr)
    return out;
  std::array<char, 4096> buffer;
  for (std::size_t n; (n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0;)
    out.text.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  out.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return out;
}

}  // namespace tumble::test
