#include "core/paths.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/common/test_support.h"

namespace flsd {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using testutil::InputErrorMessage;
namespace fs = std::filesystem;

// Sets FLSD_ROOT for the scope of one test and restores what was there.
class ScopedRoot {
 public:
  explicit ScopedRoot(const std::string& value) {
    if (const char* old = std::getenv("FLSD_ROOT")) old_ = old, had_ = true;
    setenv("FLSD_ROOT", value.c_str(), 1);
  }
  ~ScopedRoot() { had_ ? setenv("FLSD_ROOT", old_.c_str(), 1) : unsetenv("FLSD_ROOT"); }

 private:
  std::string old_;
  bool had_ = false;
};

// Runs the test from an empty directory, so that nothing resolves relative to the working one.
class ResolveDataPathTest : public ::testing::Test {
 protected:
  void SetUp() override {
    old_cwd_ = fs::current_path();
    empty_ = testutil::UniqueTempPath("cwd");
    fs::create_directories(empty_);
    fs::current_path(empty_);
  }
  void TearDown() override {
    fs::current_path(old_cwd_);
    fs::remove_all(empty_);
  }

 private:
  fs::path old_cwd_, empty_;
};

TEST_F(ResolveDataPathTest, FindsProjectFilesFromTheSourceTree) {
  const std::string path = ResolveDataPath("robot/a1/scene.xml");
  EXPECT_TRUE(fs::exists(path)) << path;
  EXPECT_THAT(path, HasSubstr("robot/a1/scene.xml"));
}

TEST_F(ResolveDataPathTest, FlsdRootComesBeforeTheSourceTree) {
  const fs::path root = testutil::UniqueTempPath("root");
  fs::create_directories(root / "robot/a1");
  std::ofstream(root / "robot/a1/scene.xml") << "<mujoco/>\n";
  {
    const ScopedRoot scoped(root.string());
    EXPECT_EQ(ResolveDataPath("robot/a1/scene.xml"), (root / "robot/a1/scene.xml").string());
  }
  fs::remove_all(root);
}

TEST_F(ResolveDataPathTest, AbsolutePathsAreReturnedAsGiven) {
  EXPECT_EQ(ResolveDataPath("/no/such/file.xml"), "/no/such/file.xml");
}

TEST_F(ResolveDataPathTest, WorkingDirectoryComesFirst) {
  fs::create_directories("robot/a1");
  std::ofstream("robot/a1/scene.xml") << "<mujoco/>\n";
  EXPECT_EQ(ResolveDataPath("robot/a1/scene.xml"), "robot/a1/scene.xml");
}

TEST_F(ResolveDataPathTest, MissingFileNamesEveryPlaceTried) {
  const ScopedRoot scoped("/flsd/empty/root");
  EXPECT_THAT(InputErrorMessage([] { ResolveDataPath("robot/none.xml"); }),
              AllOf(HasSubstr("'robot/none.xml'"),
                    HasSubstr(fs::current_path().string() + "/robot/none.xml"),
                    HasSubstr("/flsd/empty/root/robot/none.xml"),
                    HasSubstr(std::string(FLSD_SOURCE_DIR) + "/robot/none.xml")));
}

}  // namespace
}  // namespace flsd
