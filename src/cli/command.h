#pragma once
// The `hribench` command is a set of subcommands, one per file in src/cli (render_command.cc,
// bench_command.cc, ...). Each file registers itself with HRIB_REGISTER_COMMAND; main.cc
// builds the CLI11 app from the registry, so adding a command never edits another file.
//
// A subcommand's `run` returns the process exit code. Bad user input is reported by throwing
// core::InputError (or a CLI11 parse error); main turns it into one line on stderr and exit 2.

#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

namespace hribench::cli {

struct Command {
  std::string name;
  std::string help;
  // Adds the subcommand's options to `app` and returns the function that runs it once parsed.
  std::function<std::function<int()>(CLI::App& app)> setup;
};

// A check for counts and seeds: digits only ("-1" would otherwise wrap to 2^64 - 1), with the
// message "expected a non-negative whole number, got '-1'".
inline const CLI::Validator kNonNegativeWhole(
    [](std::string& text) -> std::string {
      const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
      return digits ? std::string() : "expected a non-negative whole number, got '" + text + "'";
    },
    "UINT");

// All registered commands, sorted by name.
std::vector<Command>& registry();

struct Registration {
  explicit Registration(Command command);
};

}  // namespace hribench::cli

#define HRIB_CLI_CONCAT_INNER(a, b) a##b
#define HRIB_CLI_CONCAT(a, b) HRIB_CLI_CONCAT_INNER(a, b)
#define HRIB_REGISTER_COMMAND(...)                                                     \
  static const ::hribench::cli::Registration HRIB_CLI_CONCAT(hribench_command_, __LINE__)( \
      ::hribench::cli::Command{__VA_ARGS__})
