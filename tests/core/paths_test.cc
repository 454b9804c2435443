// Tests of the data root (core/paths.h): the override wins, a bad override is an InputError,
// and a relative path is taken from the current folder first, then from the root.

#include "core/paths.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

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

}  // namespace
}  // namespace hribench::core
