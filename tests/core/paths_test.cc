// Tests of the data root (core/paths.h): the override wins, a bad override is an InputError,
// and a relative path is taken from the current folder first, then from the root.

#include "core/paths.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "support/test_files.h"

namespace hribench::core {
namespace {

namespace fs = std::filesystem;

class DataRootTest : public ::testing::Test {
 protected:
  void TearDown() override { set_data_root({}); }
};

TEST_F(DataRootTest, OverrideWinsAndResolvesRelativePaths) {
  const fs::path root = ::hribench::testing::temp_dir("paths", "root");
  fs::create_directories(root / "tasks");
  std::ofstream(root / "tasks" / "Z1_only_here.yaml") << "x";
  set_data_root(root);
  EXPECT_EQ(data_root(), fs::absolute(root));
  EXPECT_EQ(resolve_data_path("tasks/Z1_only_here.yaml"), fs::absolute(root) / "tasks/Z1_only_here.yaml");
  // Absent in both places: unchanged, so an error names what was written.
  EXPECT_EQ(resolve_data_path("tasks/none.yaml"), fs::path("tasks/none.yaml"));
  // Absolute: unchanged.
  EXPECT_EQ(resolve_data_path("/etc/hostname"), fs::path("/etc/hostname"));
  fs::remove_all(root);
}

TEST_F(DataRootTest, TheRepositoryIsFoundWithoutAnOverride) {
  // Tests run from the repository root, which has tasks/.
  EXPECT_TRUE(fs::is_directory(data_root() / "tasks"));
}

TEST_F(DataRootTest, BadOverrideIsAnInputError) {
  EXPECT_EQ(::hribench::testing::error_of([] { set_data_root("/nonexistent/hribench"); }),
            "--root: expected a folder holding tasks/ and pool/, got '/nonexistent/hribench'");
}

// The repository stands alone: nothing it builds, tests or documents reads or cites the
// planning folder beside the checkout (the patterns are split so this file does not match).
TEST(Repository, NamesNothingOutsideItself) {
  const fs::path root = HRIBENCH_SOURCE_DIR;
  const std::vector<std::string> patterns = {std::string("../") + "shared", std::string("DESIGN") + ".md",
                                             std::string("reference/") + "robots.md",
                                             std::string("reference/") + "human.md"};
  std::vector<std::string> found;
  const auto scan = [&](const fs::path& file) {
    std::ifstream in(file);
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
      for (const std::string& p : patterns) {
        if (line.find(p) != std::string::npos) {
          found.push_back(fs::relative(file, root).string() + ":" + std::to_string(n) + ": " + line);
        }
      }
    }
  };
  for (const char* dir : {"src", "tests", "bench", "scripts", "docs", "fuzz", "cmake"}) {
    if (!fs::is_directory(root / dir)) continue;
    for (const auto& entry : fs::recursive_directory_iterator(root / dir)) {
      const std::string ext = entry.path().extension().string();
      if (ext == ".cc" || ext == ".h" || ext == ".md" || ext == ".sh" || ext == ".txt" || ext == ".cmake" ||
          ext == ".py") {
        scan(entry.path());
      }
    }
  }
  scan(root / "README.md");
  scan(root / "CMakeLists.txt");
  EXPECT_TRUE(found.empty()) << [&] {
    std::string text;
    for (const std::string& f : found) text += f + "\n";
    return text;
  }();
}

}  // namespace
}  // namespace hribench::core
