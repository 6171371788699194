#include "proxygrasp/app/level_search.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace pg {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// runs the test in a fresh working directory and returns to the old one after it
class LevelSearch : public ::testing::Test {
 protected:
  void SetUp() override {
    m_old = fs::current_path();
    m_root = fs::temp_directory_path() / "pg_level_search";
    fs::remove_all(m_root);
    fs::create_directories(m_root);
    fs::current_path(m_root);
  }
  void TearDown() override {
    fs::current_path(m_old);
    fs::remove_all(m_root);
  }

  fs::path m_old;
  fs::path m_root;
};

TEST_F(LevelSearch, TheTestExecutableIsNeitherInstalledNorInABuildFolderTop) {
  // test executables sit in build/<preset>/tests/: no CMakeCache.txt beside them, no share/
  EXPECT_EQ(InstalledDataDir(), "");
  EXPECT_EQ(BuildSourceDir(), "");
  EXPECT_TRUE(LevelSearchDirs().empty());
}

TEST_F(LevelSearch, TheWorkingDirectorysLevelsComeFirst) {
  fs::create_directories("levels");
  std::ofstream("levels/mine.toml") << "name = \"mine\"\n";
  EXPECT_EQ(LevelSearchDirs(), std::vector<std::string>{"levels"});
  const Result<std::string> r = ResolveLevel("mine");
  ASSERT_TRUE(r.ok()) << r.error().Format();
  EXPECT_EQ(r.value(), "levels/mine.toml");
  // a file path is taken as it is
  std::ofstream("here.toml") << "name = \"here\"\n";
  EXPECT_EQ(ResolveLevel("here.toml").value(), "here.toml");
  // an unknown name names the folders searched
  EXPECT_THAT(
      ResolveLevel("mien").error().Format(),
      HasSubstr("level mien: not a file, and no mien.toml in levels (did you mean 'mine'?)"));
}

}  // namespace
}  // namespace pg
