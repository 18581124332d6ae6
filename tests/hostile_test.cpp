// `drape` as a hostile or careless user drives it: special files and links as outputs, outputs
// that cannot be written, inputs from pipes, huge and tiny values, options that would do
// nothing, names that try to leave their folder, runs interrupted twice or by a closed
// terminal. Each case is one a trial of the command line once broke (issue 24). The binary is
// DRAPE_EXE, or the one named by the environment variable DRAPE_EXE (to try an older build).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "temp_dir.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string exe() {
  const char* other = std::getenv("DRAPE_EXE");
  return other && *other ? other : DRAPE_EXE;
}

std::string scene(const std::string& name) {
  return std::string(DRAPE_SOURCE_DIR) + "/scenes/" + name + ".json";
}

struct Result {
  int code = -1;
  std::string out;  // standard output
  std::string err;  // standard error
};

constexpr int kNoGraphics = 4;  // drape render without an EGL context

// For drape render in a sanitizer build: Mesa and its drivers leak a few bytes at exit from
// modules already unloaded, which name nothing to suppress (as in viewer_smoke_test.cpp). Only
// the render commands run without leak checking.
const std::string kNoLeakCheck = "LSAN_OPTIONS=detect_leaks=0 ";

class Hostile : public drape::testing_support::TempDirTest {
 protected:
  Hostile() : TempDirTest("drape_hostile_") {}

  // Runs a bash command line in the test's folder, `drape` standing for the binary.
  Result sh(const std::string& command) const {
    const std::string err = path(".stderr");
    const std::string line =
        "cd " + dir_.string() + " && drape() { \"" + exe() + "\" \"$@\"; }; " + command;
    FILE* pipe = popen(("bash -c '" + quoted(line) + "' 2>" + err).c_str(), "r");
    Result r;
    if (!pipe) return r;
    std::array<char, 4096> buf;
    for (size_t n; (n = fread(buf.data(), 1, buf.size(), pipe)) > 0;) r.out.append(buf.data(), n);
    const int status = pclose(pipe);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.err = read(err);
    fs::remove(err);
    return r;
  }
  Result drape(const std::string& args) const { return sh("drape " + args); }

  std::string read(const std::string& file) const {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  json read_json(const std::string& file) const { return json::parse(read(file)); }

  // The names in a folder.
  std::set<std::string> names(const std::string& folder) const {
    std::set<std::string> out;
    for (const auto& e : fs::directory_iterator(folder)) out.insert(e.path().filename().string());
    return out;
  }

  // Starts drape with `args` (stdout and stderr to /dev/null), `ignore_hangup` as nohup does.
  pid_t spawn(const std::vector<std::string>& args, bool ignore_hangup = false) const {
    std::vector<std::string> all{exe()};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    posix_spawn_file_actions_addopen(&files, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&files, 2, "/dev/null", O_WRONLY, 0);
    // An ignored signal stays ignored across exec: that is how nohup works.
    struct sigaction ignore {
    }, old{};
    ignore.sa_handler = SIG_IGN;
    if (ignore_hangup) sigaction(SIGHUP, &ignore, &old);
    pid_t pid = -1;
    posix_spawn(&pid, argv[0], &files, nullptr, argv.data(), environ);
    if (ignore_hangup) sigaction(SIGHUP, &old, nullptr);
    posix_spawn_file_actions_destroy(&files);
    return pid;
  }
  static int wait_for(pid_t pid) {
    int status = 0;
    waitpid(pid, &status, 0);
    return status;
  }
  static void pause(double seconds) {
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  }
  // Whether `file` appeared within a minute (a sanitizer build starts slowly).
  static bool wait_for_file(const std::string& file) {
    for (int k = 0; k < 600 && !fs::exists(file); ++k) pause(0.1);
    return fs::exists(file);
  }

  // A device every write to fails (ENOSPC): a node of the test's own where it may make one
  // (root), so that a build which replaces what it writes to cannot replace the system's
  // /dev/full; else /dev/full, which only root could replace. Empty when there is neither.
  std::string full_device() const {
    const std::string own = path("full");
    if (mknod(own.c_str(), S_IFCHR | 0666, makedev(1, 7)) == 0) return own;
    return fs::exists("/dev/full") ? "/dev/full" : "";
  }

 private:
  // For inside single quotes.
  static std::string quoted(const std::string& text) {
    std::string out;
    for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out;
  }
};

// Every figure the stats hold is a number, or a string that says which non-number it is; and
// `finite` is true only when all of them are numbers.
void expect_honest_figures(const json& s) {
  bool all_numbers = true;
  for (const char* key : {"kinetic_energy", "max_strain", "mean_strain", "max_penetration",
                          "pinned_drift", "ms_per_frame", "wall_seconds", "sim_seconds"}) {
    const json& v = s.at(key);
    EXPECT_FALSE(v.is_null()) << key << " is null in " << s.dump();
    if (v.is_string()) {
      EXPECT_TRUE(v == "inf" || v == "-inf" || v == "nan") << key << ": " << v;
      all_numbers = false;
    } else {
      EXPECT_TRUE(v.is_number()) << key << ": " << v;
    }
  }
  if (!all_numbers) {
    EXPECT_EQ(s.at("finite"), false) << s.dump();
  }
}

// Item 1.
TEST_F(Hostile, AnOverflowingRunIsADivergenceWithHonestStatsForEveryMethod) {
  for (const char* g : {"1e308", "1e300"}) {
    for (const char* method : {"symplectic", "implicit", "xpbd", "fast"}) {
      const std::string stats = path(std::string(method) + g + ".json");
      const Result r = drape("run " + scene("hang") + " --set \"forces.gravity=[0,-" + g +
                             ",0]\" --set solver.method=" + method +
                             " --set \"cloth.resolution=[8,8]\" --seconds 0.1 --stats " + stats);
      EXPECT_EQ(r.code, 3) << method << " g " << g << ": " << r.out << r.err;
      const json s = read_json(stats);
      EXPECT_EQ(s["status"], "diverged") << method << " g " << g;
      EXPECT_EQ(s["finite"], false) << method << " g " << g;
      expect_honest_figures(s);
    }
  }
}

// Item 2.
TEST_F(Hostile, StatsThroughALinkWriteTheTargetAndKeepTheLink) {
  std::ofstream(path("real.json")) << "old";
  fs::create_symlink("real.json", dir_ / "link.json");
  const Result r = drape("run " + scene("hang") + " --seconds 0.05 --quiet --stats link.json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.json"));
  EXPECT_EQ(read_json(path("real.json"))["status"], "ok");
}

TEST_F(Hostile, StatsIntoANamedPipeReachItsReaderAndThePipeStays) {
  ASSERT_EQ(mkfifo(path("fifo").c_str(), 0600), 0);
  const Result r = sh("timeout 20 cat fifo > got.json & drape run " + scene("hang") +
                      " --seconds 0.05 --quiet --stats fifo; code=$?; wait; exit $code");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::is_fifo(path("fifo")));
  EXPECT_EQ(read_json(path("got.json"))["status"], "ok");
}

TEST_F(Hostile, StatsToStandardOutputAreJsonWithTheSummaryOnStandardError) {
  const Result r = drape("run " + scene("hang") + " --seconds 0.05 --stats -");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(json::parse(r.out)["status"], "ok") << r.out;
  EXPECT_NE(r.err.find("particles"), std::string::npos) << r.err;
}

TEST_F(Hostile, AFileOfTheUsersBesideTheOutputIsNeverTouchedAndPermissionsStay) {
  std::ofstream(path("s.json.tmp")) << "mine";
  std::ofstream(path("s.json")) << "{}";
  ASSERT_EQ(chmod(path("s.json").c_str(), 0640), 0);
  ASSERT_EQ(drape("run " + scene("hang") + " --seconds 0.05 --quiet --stats s.json").code, 0);
  EXPECT_EQ(read(path("s.json.tmp")), "mine");
  struct stat st;
  ASSERT_EQ(stat(path("s.json").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0640u);
}

// Items 2 and 3: refused before the run, with nothing done.
TEST_F(Hostile, OutputsThatCannotBeWrittenAreRefusedBeforeTheRun) {
  std::ofstream(path("file")) << "";
  struct Case {
    std::string args, words;
  };
  for (const Case& c :
       std::vector<Case>{{"--export frames --stats nodir/s.json",
                          "--stats nodir/s.json: the folder nodir does not exist"},
                         {"--export frames --stats .", "is a folder"},
                         {"--export frames --stats file/s.json", "--stats file/s.json"},
                         {"--export frames --stats " + scene("hang"), "is the scene file"},
                         {"--export frames --stats ''", "--stats"},
           {"--export frames/ --stats ./frames", "is the --export folder"},
                         {"--stats s.json --export file", "exists and is not a folder"},
                         {"--stats s.json --export file/below", "is not a folder"},
                         {"--stats s.json --export -", "needs a folder"}}) {
    const Result r = drape("run " + scene("hang") + " --seconds 3 " + c.args);
    EXPECT_EQ(r.code, 2) << c.args << ": " << r.err;
    EXPECT_NE(r.err.find(c.words), std::string::npos) << c.args << ": " << r.err;
    EXPECT_EQ(r.out, "") << c.args << ": no summary, for nothing was run";
    EXPECT_FALSE(fs::exists(path("frames"))) << c.args;
    EXPECT_FALSE(fs::exists(path("s.json"))) << c.args;
  }
}

TEST_F(Hostile, AFolderThatCannotBeWrittenInIsRefusedBeforeTheRun) {
  fs::create_directories(dir_ / "ro");
  fs::permissions(dir_ / "ro",
                  fs::perms::owner_write | fs::perms::group_write | fs::perms::others_write,
                  fs::perm_options::remove);
  // Root writes in any folder: the check is tried as nobody then.
  std::string as;
  if (geteuid() == 0) {
    if (sh("command -v setpriv").code != 0) GTEST_SKIP() << "root, and no setpriv to be nobody";
    as = "setpriv --reuid=65534 --regid=65534 --clear-groups ";
  }
  for (const std::string output : {"--stats ro/s.json", "--export ro/frames", "--export ro"}) {
    const Result r = sh(as + "\"" + exe() + "\" run " + scene("hang") + " --seconds 3 " + output);
    EXPECT_EQ(r.code, 2) << output << ": " << r.out << r.err;
    EXPECT_NE(r.err.find("cannot write in the folder ro"), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "") << output;
  }
  EXPECT_TRUE(fs::is_empty(dir_ / "ro"));
}

// Item 3: what still fails at the end is reported after the summary, with its own code.
TEST_F(Hostile, AnOutputThatFailsAtTheEndPrintsTheSummaryAndExits5) {
  const std::string full = full_device();
  if (full.empty()) GTEST_SKIP() << "no device that refuses writes";
  const Result r = drape("run " + scene("hang") + " --seconds 0.05 --stats " + full);
  EXPECT_EQ(r.code, 5) << r.out << r.err;
  EXPECT_NE(r.out.find("hang: 3 frames"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find(full + ": cannot write: No space left on device"), std::string::npos)
      << r.err;
  EXPECT_TRUE(fs::is_character_file(full));
}

TEST_F(Hostile, AnExportThatFailsMidRunStopsItWithStatsSummaryAndExit5) {
  // A folder where frame 5 must go: drape did not write it, so --force leaves it there.
  fs::create_directories(dir_ / "frames" / "frame_00005.obj");
  const Result r =
      drape("run " + scene("hang") + " --seconds 1 --export frames --force --stats s.json");
  EXPECT_EQ(r.code, 5) << r.out << r.err;
  EXPECT_NE(r.out.find("hang: 5 frames"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("frame_00005.obj: cannot write"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("stopped at frame 5"), std::string::npos) << r.err;
  const json s = read_json(path("s.json"));
  EXPECT_EQ(s["status"], "output_failed");
  EXPECT_NE(s["message"].get<std::string>().find("frame_00005.obj"), std::string::npos);
  EXPECT_EQ(names(path("frames")),
            (std::set<std::string>{"frame_00000.obj", "frame_00001.obj", "frame_00002.obj",
                                   "frame_00003.obj", "frame_00004.obj", "frame_00005.obj"}));
}

// Item 4.
TEST_F(Hostile, RenderKeepsTheScenesNameOneFolderInsideOut) {
  for (const std::string name : {"../escaped", "/tmp/drape_absolute_name", "", "a/b/c"}) {
    const Result r = sh(kNoLeakCheck + "drape render " + scene("hang") +
                        " --frames 0 --size 16x16 --quiet --set 'name=\"" + name + "\"'");
    if (r.code == kNoGraphics) GTEST_SKIP() << "no EGL context: " << r.err;
    ASSERT_EQ(r.code, 0) << name << ": " << r.err;
  }
  EXPECT_EQ(names(dir_.string()), std::set<std::string>{"out"});
  EXPECT_EQ(names(path("out")),
            (std::set<std::string>{"___escaped", "_tmp_drape_absolute_name", "untitled", "a_b_c"}));
  EXPECT_FALSE(fs::exists("/tmp/drape_absolute_name"));
}

// Item 5.
TEST_F(Hostile, ForceReplacesTheEarlierRunsFramesAndNothingElse) {
  // A small cloth: what is checked is which files are left.
  const std::string run = "run " + scene("hang") + " --set cloth.resolution=[8,8] --quiet";
  ASSERT_EQ(drape(run + " --seconds 1 --export ow --every 10").code, 0);
  std::ofstream(path("ow/notes.txt")) << "mine";
  std::ofstream(path("ow/frame_notes.txt")) << "mine too";
  const Result again = drape(run + " --seconds 0.5 --export ow --every 15");
  EXPECT_EQ(again.code, 2) << again.err;
  EXPECT_NE(again.err.find("--force"), std::string::npos) << again.err;
  ASSERT_EQ(drape(run + " --seconds 0.5 --export ow --every 15 --force --format ply").code, 0);
  EXPECT_EQ(names(path("ow")),
            (std::set<std::string>{"frame_00000.ply", "frame_00015.ply", "frame_00030.ply",
                                   "notes.txt", "frame_notes.txt"}));
}

TEST_F(Hostile, RenderForceReplacesTheEarlierRendersFramesAndNothingElse) {
  const std::string base =
      kNoLeakCheck + "drape render " + scene("hang") + " --size 16x16 --quiet --out pics";
  const Result first = sh(base + " --frames 20 --every 10");
  if (first.code == kNoGraphics) GTEST_SKIP() << "no EGL context: " << first.err;
  ASSERT_EQ(first.code, 0) << first.err;
  std::ofstream(path("pics/cover.png")) << "mine";
  ASSERT_EQ(sh(base + " --frames 15 --every 15 --force").code, 0);
  EXPECT_EQ(names(path("pics")),
            (std::set<std::string>{"frame_00000.png", "frame_00015.png", "cover.png"}));
}

// Item 6.
TEST_F(Hostile, AClothStartingInsideAColliderIsBadInputNamingIt) {
  struct Case {
    std::string args, words;
  };
  for (const Case& c : std::vector<Case>{{scene("sphere") + " --set colliders.0.radius=2",
                                          "colliders[0]: the cloth starts inside this sphere"},
                                         {scene("ground") + " --set 'colliders.1.normal=[1,0,0]'",
                                          "colliders[1]: the cloth starts behind this plane"},
                                         {scene("ground") + " --set 'colliders.1.normal=[0,-1,0]'",
                                          "colliders[1]: the cloth starts behind this plane"}}) {
    const Result r = drape("run " + c.args);
    EXPECT_EQ(r.code, 2) << c.args << ": " << r.err;
    EXPECT_NE(r.err.find(c.words), std::string::npos) << c.args << ": " << r.err;
    EXPECT_EQ(r.err.find("diverged"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("solver.dt"), std::string::npos) << r.err;
  }
}

// A cloth placed so far from the origin that double precision rounds its positions in steps
// too coarse for its springs: at 1e20 m the grid's particles fell onto each other and it ran
// on with springs of rest length 0, printing a strain of "inf%" and exiting 0. It is bad input
// naming the key that placed it, saying how far the cloth may lie; a cloth 1e6 m out runs.
TEST_F(Hostile, AClothTooFarFromTheOriginForItsEdgesIsBadInput) {
  struct Case {
    std::string args, words;
  };
  // (At 1e20 the file's own triangle would already have no area, an error of its own.)
  std::ofstream(path("far.obj")) << "v 1e13 1 0\nv 10000000000000.1 1 0\nv 1e13 1 0.1\n"
                                    "f 1 2 3\n";
  std::ofstream(path("far.json")) << R"({"cloth": {"mesh": "far.obj", "pins": []},
    "duration": 0.1})";
  for (const Case& c : std::vector<Case>{
           {scene("hang") + " --set 'cloth.origin=[1e20,0,0]'",
            "cloth.origin: places the cloth up to 1e+20 m from the origin"},
           {scene("skirt") + " --set 'cloth.transform.translate=[0,1e15,0]'",
            "cloth.transform: places the cloth up to 1e+15 m from the origin"},
           {"far.json", "cloth.mesh (far.obj): has vertices up to 1e+13 m from the origin"},
           // A pin keyed to carry the cloth's corner that far, or turning it about a pivot
           // that far out, ran on with strains of 1e23% and exited 0.
           {scene("hang") +
                R"( --set 'cloth.pins=[{"pin": "top-left", "motion": {"keys": [{"t": 0, )"
                R"("translate": [0, 0, 0]}, {"t": 0.05, "translate": [1e20, 0, 0]}]}}]')",
            "cloth.pins[0].motion: carries its particles up to 1e+20 m from the origin"},
           {scene("hang") +
                R"( --set 'cloth.pins=["top-left", {"pin": "top-right", "motion": {"pivot": )"
                R"([0, 0, 5e14], "keys": [{"t": 0, "rotate": [0, 0, 0]}, {"t": 1, )"
                R"("rotate": [0, 180, 0]}]}}]')",
            "cloth.pins[1].motion: carries its particles up to 1e+15 m from the origin"}}) {
    const Result r = drape("run " + c.args);
    EXPECT_EQ(r.code, 2) << c.args << ": " << r.err;
    EXPECT_NE(r.err.find(c.words), std::string::npos) << c.args << ": " << r.err;
    EXPECT_EQ(r.err.find("diverged"), std::string::npos) << r.err;
  }
  const Result grid = drape("run " + scene("hang") + " --set 'cloth.origin=[1e20,0,0]'");
  EXPECT_NE(grid.err.find("keep the cloth within 2.84e+11 m of the origin"), std::string::npos)
      << grid.err;
  const Result near = drape("run " + scene("hang") +
                            " --set 'cloth.origin=[1e6,2,0]' --seconds 0.1 --stats stats.json");
  ASSERT_EQ(near.code, 0) << near.err;
  EXPECT_TRUE(read_json(path("stats.json")).at("finite").get<bool>());
  // A pin carried a kilometre is a long way, but one doubles resolve: it runs.
  const Result carried =
      drape("run " + scene("hang") +
            R"( --seconds 0.1 --set 'cloth.pins=[{"pin": "top-left", "motion": {"keys": [{"t": 0, )"
            R"("translate": [0, 0, 0]}, {"t": 1, "translate": [1000, 0, 0]}]}}]')");
  EXPECT_EQ(carried.code, 0) << carried.err;
}

// Pieces of a cloth, or of a body, far apart: the coarse grids over them (self-collision's
// smooth parts, a body's sharp features) once counted their cells in an int, which overflowed
// (a cloth of two sheets 1e10 m apart threw std::length_error; such a body crashed the run).
TEST_F(Hostile, PiecesFarApartRunAsAnyOthers) {
  auto obj = [&](const std::string& name, const std::string& text) {
    std::ofstream(path(name)) << text;
  };
  // Two sheets of two triangles each, 1e10 m apart, as one cloth with self-collision on.
  obj("sheets.obj",
      "v 0 1 0\nv 0.1 1 0\nv 0.1 1 0.1\nv 0 1 0.1\n"
      "v 1e10 1 0\nv 1e10 1 0.1\nv 10000000000.1 1 0.1\nv 10000000000.1 1 0\n"
      "f 1 2 3\nf 1 3 4\nf 5 6 7\nf 5 7 8\n");
  std::ofstream(path("sheets.json")) << R"({"cloth": {"mesh": "sheets.obj", "mass": 0.1,
    "pins": [], "self_collision": true}, "duration": 0.1})";
  // A body of two tetrahedra, one under the cloth, one 1e10 m away (every edge sharp).
  obj("body.obj",
      "v -0.5 -1.2 -0.5\nv 0.5 -1.2 -0.5\nv -0.5 -1.2 0.5\nv -0.5 -0.2 -0.5\n"
      "v 1e10 0 0\nv 10000000001 0 0\nv 1e10 0 1\nv 1e10 1 0\n"
      "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 5 7 6\nf 5 6 8\nf 5 8 7\nf 6 7 8\n");
  std::ofstream(path("body.json")) << R"({"cloth": {"size": [1, 1], "resolution": [8, 8],
    "origin": [-0.5, 0.2, -0.5], "orientation": "horizontal", "pins": []},
    "colliders": [{"type": "mesh", "file": "body.obj"}], "duration": 0.5})";
  for (const std::string name : {"sheets.json", "body.json"}) {
    const Result r = drape("run " + name + " --stats stats.json");
    EXPECT_EQ(r.code, 0) << name << ": " << r.err;
    if (r.code == 0) {
      EXPECT_TRUE(read_json(path("stats.json")).at("finite").get<bool>()) << name;
    }
  }
}

// Item 8.
TEST_F(Hostile, CompareChecksEachMethodAfterTheOverrides) {
  const Result r = drape("compare " + scene("hang") +
                         " --methods xpbd --set solver.precision=single --seconds 0.05"
                         " --set 'cloth.resolution=[8,8]'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("xpbd"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" ok"), std::string::npos) << r.out;
  // A scene no method takes is still bad input.
  const Result none = drape("compare " + scene("hang") + " --set cloth.mass=-1");
  EXPECT_EQ(none.code, 2) << none.err;
  EXPECT_NE(none.err.find("cloth.mass"), std::string::npos) << none.err;
}

// Item 9, and values CLI11's own checks let through (NaN passes every range).
TEST_F(Hostile, OptionsThatWouldDoNothingOrBreakTheViewAreRefused) {
  const std::string run = "run " + scene("hang") + " --seconds 0.05 --quiet";
  const std::string render = "render " + scene("hang") + " --frames 1 --size 16x16 --quiet";
  const std::string bench = "bench --scenes hang --sizes 8 --threads 1 --frames 2";
  for (const std::string& args :
       {run + " --format ply", run + " --every 5", "run " + scene("hang") + " --seconds nan",
        "run " + scene("hang") + " --seconds inf", render + " --yaw nan", render + " --yaw 1e308",
        render + " --pitch nan", render + " --zoom nan", render + " --out ''",
        "compare " + scene("hang") + " --seconds nan", bench + " --max-updates nan",
        bench + " --methods symplectic --stiff-sweeps 2", bench + " --methods fast --no-search",
        "view " + scene("hang") + " --frames 1 --screenshot ''"}) {
    const Result r = drape(args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.out << r.err;
    EXPECT_FALSE(fs::exists(path("out"))) << args;
    EXPECT_FALSE(fs::exists(path("bench-results"))) << args;
  }
}

TEST_F(Hostile, TinySecondsAreKeptExactly) {
  // 4.9 µs at dt = 2 µs is 2.45, so 2 frames (--seconds once went through six decimals: 5 µs,
  // 2.5, 3 frames).
  const Result r = drape("run " + scene("hang") +
                         " --set solver.dt=2e-6 --set 'cloth.resolution=[4,4]' --seconds 0.0000049"
                         " --quiet --stats s.json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(read_json(path("s.json"))["frames"], 2);
}

// Item 10.
TEST_F(Hostile, ASceneIsReadFromStandardInputAndFromPipes) {
  const std::string hang = scene("hang");
  Result r = sh("drape run - --seconds 0.05 --quiet --stats a.json < " + hang);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(read_json(path("a.json"))["scene"], "hang");
  r = sh("drape run <(cat " + hang + ") --seconds 0.05 --quiet --stats b.json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(read_json(path("b.json"))["scene"], "hang");
  r = sh("cat " + hang + " | drape compare - --methods xpbd --seconds 0.05");
  EXPECT_EQ(r.code, 0) << r.err;
  r = sh("echo '{\"cloth\": {\"mass\": -1}}' | drape run -");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("standard input: cloth.mass: is -1"), std::string::npos) << r.err;
  r = sh("drape run . ");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("is a folder"), std::string::npos) << r.err;
}

// Item 11.
TEST_F(Hostile, AHugeSceneIsRefusedWithoutReadingItWhole) {
  // A sparse file: 300 MB long, no disk used.
  { std::ofstream(path("huge.json")); }
  fs::resize_file(path("huge.json"), 300'000'000);
  Result r = drape("run huge.json");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("huge.json: is larger than the 16 MiB a scene file may be"),
            std::string::npos)
      << r.err;
  r = sh("head -c 20000000 /dev/zero | drape run -");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("standard input: is larger than the 16 MiB"), std::string::npos) << r.err;
}

TEST_F(Hostile, ALongOrHostileNameIsShortenedAndMadeHarmlessInWhatIsShown) {
  const std::string longest(100000, 'n');
  Result r = drape("run " + scene("hang") + " --seconds 0.05 --set name=" + longest);
  ASSERT_EQ(r.code, 0) << r.err.substr(0, 300);
  EXPECT_LT(r.out.size(), 600u) << r.out.substr(0, 300);
  r = drape("run " + scene("hang") + " --set cloth." + longest + "=1");
  EXPECT_EQ(r.code, 2);
  EXPECT_LT(r.err.size(), 600u) << r.err.substr(0, 300);
  r = drape("run " + scene("hang") + " --set solver.method=" + longest);
  EXPECT_EQ(r.code, 2);
  EXPECT_LT(r.err.size(), 600u) << r.err.substr(0, 300);
  // A terminal escape in the name is not sent to the terminal.
  r = drape("run " + scene("hang") + " --seconds 0.05 --set name=$'\\e[2Jx'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.find('\x1b'), std::string::npos) << r.out;
}

TEST_F(Hostile, ANameWithInvalidUtf8StillGivesValidStats) {
  const Result r = drape("run " + scene("hang") +
                         " --seconds 0.05 --quiet --set name=$'\\xff\\xfe' --stats s.json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(read_json(path("s.json"))["status"], "ok");
}

TEST_F(Hostile, APictureBeyondTheMemoryBudgetIsRefusedUnlessForced) {
  const Result r = drape("render " + scene("hang") + " --frames 0 --size 8192x8192 --out big");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--size 8192x8192: drawing at this size takes about 3.0 GiB"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(path("big")));
}

TEST_F(Hostile, CompareKeepsTheBudgetsOfTheOtherCommands) {
  const Result r = drape("compare " + scene("hang") + " --set 'cloth.resolution=[3000,3000]'");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("GiB budget"), std::string::npos) << r.err;
}

// Item 12.
TEST_F(Hostile, BenchRefusesToReplaceAnEarlierRunsResultsUnlessForced) {
  const std::string bench =
      "bench --scenes hang --sizes 8 --methods symplectic --threads 1 --frames 2 --out b";
  ASSERT_EQ(drape(bench).code, 0);
  const std::string first = read(path("b/bench.json"));
  const Result again = drape(bench);
  EXPECT_EQ(again.code, 2) << again.err;
  EXPECT_NE(again.err.find("already holds bench.json"), std::string::npos) << again.err;
  EXPECT_EQ(read(path("b/bench.json")), first);
  EXPECT_EQ(drape(bench + " --force").code, 0);
  std::ofstream(path("file")) << "";
  EXPECT_EQ(drape("bench --scenes hang --sizes 8 --methods symplectic --threads 1 --frames 2"
                  " --out file")
                .code,
            2);
}

TEST_F(Hostile, BenchCsvQuotesTheFieldsThatHoldCommas) {
  // Every run skipped: the reason, which holds commas, goes into the status column.
  ASSERT_EQ(drape("bench --scenes hang --sizes 8 --methods symplectic --threads 1 --frames 2"
                  " --max-updates 1 --out b")
                .code,
            0);
  std::ifstream in(path("b/bench.csv"));
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  const auto fields = [](const std::string& line) {
    size_t count = 1;
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      if (c == ',' && !quoted) ++count;
    }
    return count;
  };
  EXPECT_NE(row.find("skipped"), std::string::npos) << row;
  EXPECT_EQ(fields(row), fields(header)) << row;
}

// Item 13.
TEST_F(Hostile, HelpShowsDefaultsAndExitCodes) {
  const Result run = drape("run --help");
  EXPECT_NE(run.out.find("Exit codes:"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("5    an output could not be written"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("Default: from --export's name, else obj"), std::string::npos) << run.out;
  const Result bench = drape("bench --help");
  EXPECT_NE(bench.out.find("32,64,128,256"), std::string::npos) << bench.out;
  EXPECT_NE(bench.out.find("=300"), std::string::npos) << bench.out;
  EXPECT_NE(bench.out.find("Exit codes:"), std::string::npos) << bench.out;
  for (const char* command : {"compare", "render", "view"})
    EXPECT_NE(drape(std::string(command) + " --help").out.find("Exit codes:"), std::string::npos)
        << command;
}

// Interrupted runs.
TEST_F(Hostile, AClosedTerminalStopsTheRunLikeCtrlCUnlessNohupIgnoresIt) {
  // Signals are sent once frame 0 is exported: the handlers are in place by then.
  const auto run = [&](const std::string& name) {
    return std::vector<std::string>{"run",     scene("hang"), "--seconds",          "1000",
                                    "--quiet", "--stats",     path(name + ".json"), "--export",
                                    path(name)};
  };
  pid_t pid = spawn(run("hup"));
  ASSERT_TRUE(wait_for_file(path("hup/frame_00000.obj")));
  kill(pid, SIGHUP);
  int status = wait_for(pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 129);
  EXPECT_EQ(read_json(path("hup.json"))["status"], "interrupted");
  // Under nohup the hangup is not seen; SIGTERM still stops the run.
  pid = spawn(run("nohup"), true);
  ASSERT_TRUE(wait_for_file(path("nohup/frame_00000.obj")));
  kill(pid, SIGHUP);
  pause(0.5);
  kill(pid, SIGTERM);
  status = wait_for(pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 143);
}

TEST_F(Hostile, CtrlCStopsALongFrameAtItsNextSubstepAndKeepsTheStats) {
  // Frames of 200000 substeps take seconds (25 s for a symplectic 256 × 256 frame): the run
  // stops at the substep under way, writes its stats and exits 130 within a second.
  const pid_t pid =
      spawn({"run", scene("hang"), "--set", "solver.method=symplectic", "--set",
             "solver.substeps=200000", "--seconds", "0.5", "--quiet", "--stats", path("s.json"),
             "--export", path("frames")});
  ASSERT_TRUE(wait_for_file(path("frames/frame_00000.obj")));
  pause(0.2);  // into frame 1
  const auto sent = std::chrono::steady_clock::now();
  kill(pid, SIGINT);
  const int status = wait_for(pid);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_LT(seconds, 1.0);
  const json stats = read_json(path("s.json"));
  EXPECT_EQ(stats["status"], "interrupted");
  EXPECT_EQ(stats["frames"], 0);  // frame 1, cut short, is not counted
}

TEST_F(Hostile, ASecondCtrlCEndsAFrameThatTakesTooLong) {
  // One substep of 10000 local/global iterations on a 128 × 128 cloth takes seconds and has no
  // substep to stop at: the first Ctrl-C waits for it, the second does not.
  const pid_t pid = spawn({"run", scene("hang"), "--set", "solver.method=fast", "--set",
                           "solver.substeps=1", "--set", "solver.iterations=10000", "--set",
                           "cloth.resolution=[128,128]", "--seconds", "0.5", "--quiet",
                           "--export", path("frames")});
  ASSERT_TRUE(wait_for_file(path("frames/frame_00000.obj")));
  kill(pid, SIGINT);
  pause(0.3);
  kill(pid, SIGINT);
  const int status = wait_for(pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << "exited with " << WEXITSTATUS(status);
  EXPECT_EQ(WTERMSIG(status), SIGINT);
}

TEST_F(Hostile, CtrlCDuringAVideoLetsFfmpegFinishIt) {
  // A stand-in ffmpeg counts the bytes it is sent. Ctrl-C reaches the whole foreground process
  // group (set -m gives the job one of its own), sent once frames flow; ffmpeg must outlive it
  // and count every frame drape drew before it stopped.
  fs::create_directories(dir_ / "bin");
  std::ofstream(path("bin/ffmpeg")) << "#!/bin/sh\nfor last in \"$@\"; do :; done\n"
                                       "touch \"$last.started\"\nwc -c > \"$last\"\n";
  fs::permissions(path("bin/ffmpeg"), fs::perms::owner_all);
  const Result r =
      sh("set -m; PATH=$PWD/bin:$PATH " + kNoLeakCheck + "drape render " + scene("hang") +
         " --frames 100000 --size 32x32 --quiet --video clip.mp4 & pid=$!;"
         " for i in $(seq 600); do [ -e clip.mp4.started ] && break; sleep 0.1; done;"
         " sleep 0.5; kill -INT -$pid; wait $pid");
  if (r.code == kNoGraphics) GTEST_SKIP() << "no EGL context: " << r.err;
  EXPECT_EQ(r.code, 130) << r.err;
  long long bytes = 0;
  std::ifstream(path("clip.mp4")) >> bytes;
  EXPECT_GT(bytes, 0);
  EXPECT_EQ(bytes % (32 * 32 * 4), 0);
  const Result no_extension =
      sh("PATH=$PWD/bin:$PATH drape render " + scene("hang") + " --frames 1 --video clip");
  EXPECT_EQ(no_extension.code, 2) << no_extension.err;
  EXPECT_NE(no_extension.err.find("needs a file name with an extension"), std::string::npos);
}

}  // namespace
