// Writing the files drape is asked to write (io::OutputFile): what is at the path decides how,
// and nothing but the file's contents is ever replaced. Names made from scenes, and text shown.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <future>
#include <iterator>
#include <string>

#include "drape/error.h"
#include "io/output_file.h"
#include "io/shown_text.h"
#include "temp_dir.h"

namespace drape {
namespace {

namespace fs = std::filesystem;

class OutputFiles : public testing_support::TempDirTest {
 protected:
  OutputFiles() : TempDirTest("drape_output_") {}
  std::string read(const std::string& file) const {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  void write(const std::string& file, const std::string& text) const {
    std::ofstream(file, std::ios::binary) << text;
  }
  // The check's message, or "" when it passes.
  static std::string refusal(const std::string& file) {
    try {
      io::check_output("--stats", file);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(OutputFiles, ARegularFileIsReplacedWholeKeepingItsPermissions) {
  const std::string file = path("stats.json");
  write(file, "old");
  ASSERT_EQ(chmod(file.c_str(), 0640), 0);
  write(path("stats.json.tmp"), "the user's own file");
  io::write_output(file, "new");
  EXPECT_EQ(read(file), "new");
  struct stat st;
  ASSERT_EQ(stat(file.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0640u);
  // The temporary had a name of its own, and is gone.
  EXPECT_EQ(read(path("stats.json.tmp")), "the user's own file");
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) ++entries;
  EXPECT_EQ(entries, 2);
}

TEST_F(OutputFiles, NothingAppearsUntilCommitAndAnAbandonedFileLeavesNothing) {
  const std::string file = path("mesh.obj");
  {
    io::OutputFile out(file);
    std::fputs("half a mesh", out.get());
    std::fflush(out.get());
    EXPECT_FALSE(fs::exists(file));
  }
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(OutputFiles, ALinkIsFollowedToItsTargetAndStays) {
  fs::create_directories(dir_ / "real");
  write(path("real/stats.json"), "old");
  fs::create_symlink("real/stats.json", dir_ / "link.json");
  fs::create_symlink("link.json", dir_ / "link2.json");  // a chain
  io::write_output(path("link2.json"), "new");
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.json"));
  EXPECT_TRUE(fs::is_symlink(dir_ / "link2.json"));
  EXPECT_EQ(read(path("real/stats.json")), "new");
  // A dangling link: its target is created, as a plain write through it would.
  fs::create_symlink("real/new.json", dir_ / "dangling.json");
  io::write_output(path("dangling.json"), "made");
  EXPECT_TRUE(fs::is_symlink(dir_ / "dangling.json"));
  EXPECT_EQ(read(path("real/new.json")), "made");
  // A loop of links is refused, before and at writing.
  fs::create_symlink("loop_b", dir_ / "loop_a");
  fs::create_symlink("loop_a", dir_ / "loop_b");
  EXPECT_NE(refusal(path("loop_a")).find("too many levels of symbolic links"), std::string::npos);
  EXPECT_THROW(io::write_output(path("loop_a"), "x"), io::OutputError);
}

TEST_F(OutputFiles, ANamedPipeIsWrittenToItsReaderAndStaysAPipe) {
  const std::string fifo = path("fifo");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  auto reader = std::async(std::launch::async, [&] { return read(fifo); });
  io::write_output(fifo, "through the pipe");
  EXPECT_EQ(reader.get(), "through the pipe");
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_EQ(refusal(fifo), "");
}

TEST_F(OutputFiles, ADeviceIsWrittenDirectlyAndItsErrorsReported) {
  io::write_output("/dev/null", "gone");
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  // A device every write to fails: a node of the test's own where it may make one (root), so
  // that code which replaces what it writes to cannot replace the system's /dev/full.
  std::string full = path("full");
  if (mknod(full.c_str(), S_IFCHR | 0666, makedev(1, 7)) != 0) full = "/dev/full";
  if (!fs::exists(full)) GTEST_SKIP() << "no device that refuses writes";
  EXPECT_EQ(refusal(full), "");  // writable: its failure shows only when written
  try {
    io::write_output(full, std::string(1 << 16, 'x'));
    FAIL() << "a write to " << full << " succeeded";
  } catch (const io::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find(full + ": cannot write: No space left on device"),
              std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(fs::is_character_file(full));
}

TEST_F(OutputFiles, FoldersAndMissingFoldersAreRefusedBeforeAnythingIsWritten) {
  EXPECT_NE(refusal(dir_.string()).find("is a folder"), std::string::npos);
  EXPECT_THROW(io::write_output(dir_.string(), "x"), io::OutputError);
  EXPECT_NE(refusal(path("nodir/s.json")).find("does not exist"), std::string::npos);
  write(path("file"), "");
  EXPECT_NE(refusal(path("file/s.json")), "");
  EXPECT_EQ(refusal(path("s.json")), "");
  EXPECT_EQ(refusal("-"), "");
  EXPECT_FALSE(fs::exists(path("s.json")));  // checked, not written
  try {
    io::check_output_folder("--export", "-");
    FAIL() << "- accepted as a folder";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("needs a folder"), std::string::npos);
  }
  EXPECT_THROW(io::check_output_folder("--export", path("file")), InputError);
  EXPECT_THROW(io::check_output_folder("--export", path("file/below")), InputError);
  io::check_output_folder("--export", path("new/deeper"));  // creatable
  EXPECT_FALSE(fs::exists(path("new")));
}

TEST(FileNames, ASceneNameMakesOneHarmlessComponent) {
  EXPECT_EQ(io::file_name_from("hang"), "hang");
  EXPECT_EQ(io::file_name_from("../escaped"), "___escaped");
  EXPECT_EQ(io::file_name_from("/etc/passwd"), "_etc_passwd");
  EXPECT_EQ(io::file_name_from("a/b/c"), "a_b_c");
  EXPECT_EQ(io::file_name_from(""), "untitled");
  EXPECT_EQ(io::file_name_from("."), "_");
  EXPECT_EQ(io::file_name_from(".."), "__");
  EXPECT_EQ(io::file_name_from("wind 2.0+gusts"), "wind_2.0+gusts");
  EXPECT_EQ(io::file_name_from(std::string(100000, 'x')).size(), 64u);
}

TEST(ShownText, LongOrHostileTextIsOneReadableLine) {
  EXPECT_EQ(io::shown("hang"), "hang");
  EXPECT_EQ(io::shown(std::string(100000, 'x')), std::string(60, 'x') + "...");
  EXPECT_EQ(io::shown("two\nlines\x1b[2J"), "two?lines?[2J");
  EXPECT_EQ(io::shown("\xff\xfe ok"), "?? ok");
  EXPECT_EQ(io::shown("drapé", 5), "drapé");  // characters, not bytes
  EXPECT_EQ(io::shown("drapé!", 5), "drapé...");
}

}  // namespace
}  // namespace drape
