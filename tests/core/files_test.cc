#include "core/files.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/errors.h"
#include "support/test_files.h"

namespace hribench::core {
namespace {

namespace fs = std::filesystem;

TEST(WriteFileAtomically, ReplacesTheFileWholeAndLeavesNoTemporary) {
  const fs::path dir = ::hribench::testing::temp_dir("files", "atomic");
  fs::create_directories(dir);
  const fs::path path = dir / "results.json";
  write_file_atomically(path, "old");
  write_file_atomically(path, std::string("new\0bytes", 9));
  EXPECT_EQ(::hribench::testing::read_text(path), std::string("new\0bytes", 9));
  EXPECT_FALSE(fs::exists(dir / "results.json.tmp"));
  fs::remove_all(dir);
}

TEST(WriteFileAtomically, AFolderThatIsNotThereIsAnInputError) {
  try {
    write_file_atomically("/nonexistent/dir/x.json", "x");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/dir/x.json: cannot write the file: No such file or directory");
  }
}

TEST(WriteFileAtomically, AFolderInTheWayKeepsItAndRemovesTheTemporary) {
  const fs::path dir = ::hribench::testing::temp_dir("files", "in_the_way");
  fs::create_directories(dir / "summary.md" / "inside");
  try {
    write_file_atomically(dir / "summary.md", "x");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind((dir / "summary.md").string() + ": cannot write the file: ", 0), 0u)
        << e.what();
  }
  EXPECT_TRUE(fs::is_directory(dir / "summary.md" / "inside"));
  EXPECT_FALSE(fs::exists(dir / "summary.md.tmp"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hribench::core
