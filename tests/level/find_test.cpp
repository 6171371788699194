#include "proxygrasp/level/find.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace pg {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// two level folders in a fresh temporary folder: first/ with demo_sort and side_push, second/
// with side_push (shadowed by first's) and top_drag
class FindLevel : public ::testing::Test {
 protected:
  void SetUp() override {
    m_root = fs::temp_directory_path() /
             ("pg_find_level_" +
              std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(m_root);
    fs::create_directories(m_root / "first");
    fs::create_directories(m_root / "second");
    for (const char* f : {"first/demo_sort.toml", "first/side_push.toml", "second/side_push.toml",
                          "second/top_drag.toml", "second/notes.txt"})
      std::ofstream(m_root / f) << "name = \"x\"\n";
    m_dirs = {(m_root / "first").string(), (m_root / "second").string()};
  }
  void TearDown() override { fs::remove_all(m_root); }

  fs::path m_root;
  std::vector<std::string> m_dirs;
};

TEST_F(FindLevel, AnExistingFileIsItself) {
  const std::string path = (m_root / "second/top_drag.toml").string();
  const Result<std::string> r = FindLevelFile(path, m_dirs);
  ASSERT_TRUE(r.ok()) << r.error().Format();
  EXPECT_EQ(r.value(), path);
}

TEST_F(FindLevel, ANameIsLookedUpInTheFoldersInOrder) {
  Result<std::string> r = FindLevelFile("side_push", m_dirs);
  ASSERT_TRUE(r.ok()) << r.error().Format();
  EXPECT_EQ(r.value(), (m_root / "first/side_push.toml").string());  // the first folder wins
  r = FindLevelFile("top_drag", m_dirs);
  ASSERT_TRUE(r.ok()) << r.error().Format();
  EXPECT_EQ(r.value(), (m_root / "second/top_drag.toml").string());
  // the name with its extension finds the same file
  r = FindLevelFile("top_drag.toml", m_dirs);
  ASSERT_TRUE(r.ok()) << r.error().Format();
  EXPECT_EQ(r.value(), (m_root / "second/top_drag.toml").string());
}

TEST_F(FindLevel, AnUnknownNameListsTheFoldersAndSuggests) {
  const Result<std::string> r = FindLevelFile("demo_srot", m_dirs);
  ASSERT_FALSE(r.ok());
  EXPECT_THAT(r.error().Format(),
              HasSubstr("level demo_srot: not a file, and no demo_srot.toml in " + m_dirs[0] +
                        ", " + m_dirs[1]));
  EXPECT_THAT(r.error().Format(), HasSubstr("did you mean 'demo_sort'?"));
  // with no folders to search, it says so
  EXPECT_THAT(FindLevelFile("demo_sort", {}).error().Format(), HasSubstr("no level folders"));
}

TEST_F(FindLevel, APathIsNeverLookedUpByName) {
  // a missing path names the path; a folder is not a level
  Result<std::string> r = FindLevelFile("elsewhere/side_push.toml", m_dirs);
  ASSERT_FALSE(r.ok());
  EXPECT_THAT(r.error().Format(), HasSubstr("level elsewhere/side_push.toml: no such file"));
  r = FindLevelFile(m_dirs[0], m_dirs);
  ASSERT_FALSE(r.ok());
  EXPECT_THAT(r.error().Format(), HasSubstr("is a folder, not a level file"));
  EXPECT_FALSE(FindLevelFile("", m_dirs).ok());
}

TEST_F(FindLevel, ListsTheLevelNamesOnce) {
  std::vector<std::string> dirs = m_dirs;
  dirs.push_back((m_root / "missing").string());
  EXPECT_EQ(ListLevelNames(dirs), (std::vector<std::string>{"demo_sort", "side_push", "top_drag"}));
}

}  // namespace
}  // namespace pg
