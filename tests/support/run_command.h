#pragma once
// Runs a shell command line and captures its exit code and output, for tests of the
// `hribench` command and of files checked by other programs (ffprobe, node, python3) (HRIBENCH_BINARY is its path; tests run from the repository root).

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace hribench::testing {

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// Runs a shell command line (already quoted), stdout and stderr captured together.
inline CommandResult run_shell(const std::string& command_line) {
  const std::string command = command_line + " 2>&1";
  CommandResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer{};
  size_t n = 0;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

// Runs `prefix` (shell words before the command, e.g. "cd DIR && " or "VAR=1 ") and then the
// hribench binary with `args` (already shell-quoted).
inline CommandResult run_hribench_with(const std::string& prefix, const std::string& args) {
  return run_shell(prefix + std::string(HRIBENCH_BINARY) + " " + args);
}

// Runs `args` (already shell-quoted) as arguments of the hribench binary.
inline CommandResult run_hribench(const std::string& args) { return run_hribench_with("", args); }

// As run_hribench, from the folder `dir` (e.g. one outside the repository).
inline CommandResult run_hribench_in(const std::string& dir, const std::string& args) {
  return run_hribench_with("cd '" + dir + "' && ", args);
}

// Number of lines in `text` (a trailing newline does not start a new line).
inline int count_lines(const std::string& text) {
  int lines = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n' || i + 1 == text.size()) ++lines;
  }
  return lines;
}

}  // namespace hribench::testing
