// The README and docs/ stay true: every relative link resolves inside the repository, every
// command line in a fenced code block runs (with small sizes), and every `hribench` command
// written inline or as a template names a command and options that exist.
//
// A fenced line that runs hribench (as `hribench`, `build/hribench` or a path ending in
// `/hribench`, possibly after `cd DIR &&`) is run from a fresh folder per document (later
// commands of a document may read what earlier ones wrote) with HRIBENCH_ROOT naming the
// repository (so tasks/, pool/ and tests/ are found as from anywhere), with absolute /tmp paths
// moved into that folder and the sizes shrunk (one task, one episode, a 1 s horizon, a few candidates,
// tiny images, a collect of one episode; servers and commands that need one are only checked against help): what is
// tested is that the command line is accepted and runs to the end.
// Lines with placeholders (`[...]`, `A|B`, words like FILE or DIR, $VARIABLES) are templates: like inline
// commands they are checked against `hribench help COMMAND`.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "support/run_command.h"
#include "support/test_files.h"

namespace hribench::cli {
namespace {

namespace fs = std::filesystem;
using ::hribench::testing::read_text;
using ::hribench::testing::run_hribench;

const fs::path kRoot = HRIBENCH_SOURCE_DIR;

// README.md and every docs/*.md, relative to the repository.
std::vector<fs::path> documents() {
  std::vector<fs::path> files = {"README.md"};
  for (const auto& entry : fs::directory_iterator(kRoot / "docs")) {
    if (entry.path().extension() == ".md") files.push_back(fs::relative(entry.path(), kRoot));
  }
  std::sort(files.begin(), files.end());
  return files;
}

struct Shown {
  fs::path file;
  int line = 0;
  std::string text;  // the command, from the hribench word on (continuations joined)
  bool fenced = false;
  std::string where() const { return file.string() + ":" + std::to_string(line); }
};

const std::regex kCommandStart(R"((^|\s|&&\s*)((?:\S*/)?hribench)\s)");

// The hribench command lines of a document: fenced lines and inline code spans.
std::vector<Shown> commands_in(const fs::path& file) {
  std::vector<Shown> shown;
  std::istringstream in(read_text(kRoot / file));
  std::string line;
  bool fenced = false;
  int number = 0;
  std::string pending;  // a fenced command continued with a backslash
  int pending_line = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.rfind("```", 0) == 0) {
      fenced = !fenced;
      continue;
    }
    if (fenced) {
      if (!pending.empty()) {
        pending += " " + line;
      } else {
        pending = line;
        pending_line = number;
      }
      if (!pending.empty() && pending.back() == '\\') {
        pending.pop_back();
        continue;
      }
      std::smatch m;
      const std::string text = pending.substr(0, pending.find(" #"));  // a trailing comment
      if (std::regex_search(text, m, kCommandStart) && text.find("hribench:") == std::string::npos) {
        shown.push_back({file, pending_line, text.substr(static_cast<size_t>(m.position(2))), true});
      }
      pending.clear();
      continue;
    }
    static const std::regex span(R"(`((?:\S*/)?hribench(?: [^`]*)?)`)");
    for (auto it = std::sregex_iterator(line.begin(), line.end(), span); it != std::sregex_iterator(); ++it) {
      shown.push_back({file, number, (*it)[1].str(), false});
    }
  }
  return shown;
}

std::vector<std::string> words(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string w;
  while (in >> w) out.push_back(w);
  return out;
}

// A template: optional parts, alternatives, placeholder words (FILE, DIR, SECONDS, ...) or
// variables of a job script ($POLICY_HOST, ${SLURM_ARRAY_TASK_ID}).
bool is_template(const std::string& text) {
  static const std::regex placeholder(R"((^|[\s=/$])\{?[A-Z][A-Z_]{2,}\b)");
  return text.find('[') != std::string::npos || text.find('|') != std::string::npos ||
         text.find("...") != std::string::npos || text.find('<') != std::string::npos ||
         std::regex_search(text, placeholder);
}

// A server (`serve`, run until stopped, often with `&`) or a command that talks to one
// (openpi:// or gr00t://): checked against help only; tests/remote and tests/cli/serve_command_test
// run client and server together.
bool needs_a_server(const std::string& text) {
  return text.find(" serve ") != std::string::npos || text.find("openpi://") != std::string::npos ||
         text.find("gr00t://") != std::string::npos || (!text.empty() && text.back() == '&');
}

// The options `hribench help COMMAND` lists (cached per command); empty for an unknown command.
const std::set<std::string>& options_of(const std::string& command) {
  static std::map<std::string, std::set<std::string>> cache;
  const auto found = cache.find(command);
  if (found != cache.end()) return found->second;
  std::set<std::string>& options = cache[command];
  const auto help = run_hribench("help " + command);
  if (help.exit_code != 0) return options;
  static const std::regex option(R"(--[a-z][a-z0-9-]*)");
  for (auto it = std::sregex_iterator(help.output.begin(), help.output.end(), option);
       it != std::sregex_iterator(); ++it) {
    options.insert(it->str());
  }
  options.insert("--help");
  return options;
}

// Checks that a shown command names a command and options that exist; returns a problem or "".
std::string check_syntax(const Shown& shown) {
  std::vector<std::string> w = words(shown.text);
  size_t i = 1;
  while (i < w.size() && (w[i] == "--root" || w[i] == "--log-level")) i += 2;  // global options
  if (i >= w.size()) return "";  // `hribench` alone lists the commands
  const std::string command = w[i];
  if (command == "help" || command == "--help" || is_template(command)) return "";
  const std::set<std::string>& options = options_of(command);
  if (options.empty()) return "unknown command '" + command + "'";
  for (size_t k = i + 1; k < w.size(); ++k) {
    std::string word = w[k];
    const size_t start = word.find("--");
    if (start == std::string::npos) continue;
    word = word.substr(start);
    word = word.substr(0, word.find_first_of("=\\|]`)"));
    if (word.size() > 2 && !options.count(word)) return "'" + command + "' has no option " + word;
  }
  return "";
}

// The value after `flag` in `w`, replaced by `value` (or appended with the flag when absent).
void set_option(std::vector<std::string>& w, const std::string& flag, const std::string& value) {
  for (size_t i = 0; i + 1 < w.size(); ++i) {
    if (w[i] == flag) {
      w[i + 1] = value;
      return;
    }
  }
  w.push_back(flag);
  w.push_back(value);
}

bool has_option(const std::vector<std::string>& w, const std::string& flag) {
  return std::find(w.begin(), w.end(), flag) != w.end();
}

// The shown command with small sizes and paths inside `dir`, as arguments of the binary.
std::string small_version(const Shown& shown, const fs::path& dir) {
  std::string text = std::regex_replace(shown.text, std::regex(R"(\$\(nproc\))"), "2");
  text = std::regex_replace(text, std::regex(R"((^|\s)/tmp/)"), "$1" + dir.string() + "/");
  std::vector<std::string> w = words(text);
  w.erase(w.begin());  // the binary
  const std::string command = w.empty() ? "" : w.front();
  if (command == "eval") {
    set_option(w, "--tasks", "I1");
    set_option(w, "--horizon", "1");
    if (!has_option(w, "--pool")) set_option(w, "--episodes", "1");
  } else if (command == "generate") {
    set_option(w, "--tasks", "I1");
    set_option(w, "--candidates", "2");
    set_option(w, "--adapt", "1");
    set_option(w, "--eval", "1");
    set_option(w, "--test", "0");
    set_option(w, "--executable-by", "none");
  } else if (command == "collect") {
    set_option(w, "--tasks", "I1");
    set_option(w, "--episodes", "1");
    set_option(w, "--size", "16");
  } else if (command == "render") {
    set_option(w, "--width", "32");
    set_option(w, "--height", "24");
  } else if (command == "bench" && has_option(w, "--episodes")) {
    set_option(w, "--tasks", "I1");
    set_option(w, "--seeds", "1");
    set_option(w, "--horizon", "1");
  } else if (command == "bench") {
    set_option(w, "--seconds", "0.1");
  }
  // Relative output files get their folders inside `dir`.
  for (size_t i = 0; i + 1 < w.size(); ++i) {
    if ((w[i] == "--out" || w[i] == "--render") && fs::path(w[i + 1]).is_relative()) {
      fs::create_directories((dir / w[i + 1]).parent_path());
    }
  }
  std::string args;
  for (const std::string& word : w) args += (args.empty() ? "" : " ") + word;
  return args;
}

TEST(Docs, EveryRelativeLinkResolvesInsideTheRepository) {
  static const std::regex link(R"(\]\(([^)\s]+)\))");
  int checked = 0;
  for (const fs::path& file : documents()) {
    const std::string text = read_text(kRoot / file);
    for (auto it = std::sregex_iterator(text.begin(), text.end(), link); it != std::sregex_iterator(); ++it) {
      std::string target = (*it)[1].str();
      if (target.rfind("http://", 0) == 0 || target.rfind("https://", 0) == 0 || target.rfind("mailto:", 0) == 0 ||
          target.front() == '#') {
        continue;
      }
      target = target.substr(0, target.find('#'));
      const fs::path resolved = fs::weakly_canonical(kRoot / file.parent_path() / target);
      const std::string relative = fs::relative(resolved, fs::weakly_canonical(kRoot)).string();
      EXPECT_FALSE(relative.rfind("..", 0) == 0) << file << ": " << target << " leaves the repository";
      EXPECT_TRUE(fs::exists(resolved)) << file << ": " << target << " does not exist";
      ++checked;
    }
  }
  EXPECT_GT(checked, 20);  // the documents do link to each other
}

TEST(Docs, EveryCommandNamesACommandAndOptionsThatExist) {
  int checked = 0;
  for (const fs::path& file : documents()) {
    for (const Shown& shown : commands_in(file)) {
      const std::string problem = check_syntax(shown);
      EXPECT_EQ(problem, "") << shown.where() << ": `" << shown.text << "`";
      ++checked;
    }
  }
  EXPECT_GT(checked, 30);
}

TEST(Docs, EveryFencedCommandRuns) {
  int ran = 0;
  for (const fs::path& file : documents()) {
    const fs::path dir = ::hribench::testing::temp_dir("docs", file.stem().string());
    fs::create_directories(dir);
    for (const Shown& shown : commands_in(file)) {
      if (!shown.fenced || is_template(shown.text) || needs_a_server(shown.text)) continue;
      const std::string args = small_version(shown, dir);
      const auto r = ::hribench::testing::run_hribench_with(
          "cd '" + dir.string() + "' && HRIBENCH_ROOT='" + kRoot.string() + "' ", args);
      EXPECT_EQ(r.exit_code, 0) << shown.where() << ": `" << shown.text << "` ran as `hribench " << args
                                << "`:\n" << r.output;
      ++ran;
    }
    fs::remove_all(dir);
  }
  EXPECT_GE(ran, 5);
}

}  // namespace
}  // namespace hribench::cli
