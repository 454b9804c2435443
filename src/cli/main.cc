// hribench: the command-line entry point. Subcommands live in src/cli/*_command.cc.

#include <algorithm>
#include <cstdio>
#include <exception>
#include <functional>
#include <map>

#include "cli/command.h"
#include "core/errors.h"
#include "core/log.h"
#include "core/paths.h"
#include "core/version.h"
#include "remote/remote.h"

namespace hribench::cli {

std::vector<Command>& registry() {
  static std::vector<Command> commands;
  return commands;
}

Registration::Registration(Command command) {
  auto& commands = registry();
  const auto at = std::lower_bound(commands.begin(), commands.end(), command.name,
                                   [](const Command& c, const std::string& name) { return c.name < name; });
  commands.insert(at, std::move(command));
}

namespace {

int run(int argc, char** argv) {
  remote::register_remote_policies();  // openpi:// and gr00t:// policy references
  CLI::App app{"HRIBench: interaction-centric human-robot collaboration benchmark"};
  app.require_subcommand(0, 1);
  app.set_version_flag("--version", std::string(core::version()) + " (" +
                                        std::string(core::git_hash()) + ")");
  std::string log_level = "info";
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error or off");
  std::string root;
  app.add_option("--root", root,
                 "Folder holding tasks/ and pool/ (default: HRIBENCH_ROOT, the current folder if it has "
                 "tasks/, else the source tree; docs/getting-started.md)");
  app.footer("Run 'hribench help COMMAND' (or 'hribench COMMAND --help') for a command's options.");

  std::map<CLI::App*, std::function<int()>> runners;
  std::string names;
  for (const Command& command : registry()) {
    CLI::App* sub = app.add_subcommand(command.name, command.help);
    sub->option_defaults()->always_capture_default();  // --help shows every default
    runners[sub] = command.setup(*sub);
    names += (names.empty() ? "" : ", ") + command.name;
  }
  names += ", help";
  // The first word that is not an option names the command; say so when it names none.
  // `hribench help [COMMAND]` prints the help of hribench or of that command.
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.starts_with("-")) {
      if (word == "--log-level" || word == "--root") ++i;  // skip its value
      continue;
    }
    const auto& commands = registry();
    if (word == "help") {
      if (i + 1 >= argc) {
        std::fputs(app.help().c_str(), stdout);
        return 0;
      }
      const std::string name = argv[i + 1];
      if (std::none_of(commands.begin(), commands.end(), [&](const Command& c) { return c.name == name; })) {
        throw core::InputError("hribench help", "a command (" + names + ")", "'" + name + "'");
      }
      std::fputs(app.get_subcommand(name)->help().c_str(), stdout);
      return 0;
    }
    if (std::none_of(commands.begin(), commands.end(),
                     [&](const Command& c) { return c.name == word; })) {
      throw core::InputError("hribench", "a command (" + names + ")", "'" + word + "'");
    }
    break;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Help and version print to stdout and exit 0; real parse errors are one line, exit 2.
    if (e.get_exit_code() == 0) return app.exit(e);
    std::fprintf(stderr, "hribench: %s\n", e.what());
    return 2;
  }
  core::set_log_level(log_level);
  if (!root.empty()) core::set_data_root(root);
  for (CLI::App* sub : app.get_subcommands()) return runners.at(sub)();
  // No command: the overview of commands, as `hribench help` prints it.
  std::fputs(app.help().c_str(), stdout);
  return 0;
}

}  // namespace
}  // namespace hribench::cli

int main(int argc, char** argv) {
  try {
    return hribench::cli::run(argc, argv);
  } catch (const hribench::core::InputError& e) {
    std::fprintf(stderr, "hribench: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hribench: error: %s\n", e.what());
    return 1;
  }
}
