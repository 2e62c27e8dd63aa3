#include "core/paths.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <thread>
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

TEST(ProgramPathTest, IsThisTestsOwnProgram) {
  EXPECT_TRUE(fs::equivalent(ProgramPath(), "/proc/self/exe"));
}

TEST(ProgramPathTest, NamesTheProgramNowInPlaceOfOneReplacedWhileItRuns) {
  const fs::path dir = testutil::UniqueTempPath("bin");
  fs::create_directories(dir);
  const fs::path program = dir / "sleeper";
  fs::copy_file("/bin/sleep", program);
  const pid_t pid = fork();
  if (pid == 0) {
    execl(program.c_str(), program.c_str(), "30", static_cast<char*>(nullptr));
    _exit(127);
  }
  ASSERT_GT(pid, 0);
  const std::string link = "/proc/" + std::to_string(pid) + "/exe";
  for (int i = 0; i < 200 && fs::read_symlink(link) != program; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));  // until it has exec'd
  }
  // A rebuild: the running file is removed and a new one written in its place.
  fs::remove(program);
  fs::copy_file("/bin/sleep", program);
  EXPECT_EQ(fs::read_symlink(link).string(), program.string() + " (deleted)");
  EXPECT_EQ(ProgramPath(link), program.string());
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace flsd
