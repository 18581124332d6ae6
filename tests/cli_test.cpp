// `drape run` as a user runs it: exit codes, messages, stats and exports.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "drape_process.h"
#include "shipped_scenes.h"
#include "temp_dir.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

using Result = drape::testing_support::CommandResult;

Result drape(const std::string& args) {
  return drape::testing_support::run_drape(args);
}

std::string scene(const std::string& name) {
  return std::string(DRAPE_SOURCE_DIR) + "/scenes/" + name + ".json";
}

class Cli : public drape::testing_support::TempDirTest {
 protected:
  Cli() : TempDirTest("drape_cli_") {}
  // Runs `drape bench` with these options into out and returns its rows (bench.json).
  json bench_rows(const std::string& options, const std::string& out) const {
    const Result r = drape("bench " + options + " --out " + out);
    EXPECT_EQ(r.code, 0) << r.output;
    return read_json(out + "/bench.json");
  }
  json read_json(const std::string& file) const {
    std::ifstream in(file);
    return json::parse(in);
  }
};

// The memory a run reported, from its parts.
double memory_total(const json& j) {
  return static_cast<double>(j["state_bytes"].get<int64_t>() + j["model_bytes"].get<int64_t>() +
                             j["workspace_bytes"].get<int64_t>());
}

TEST_F(Cli, EveryShippedSceneRunsAndWritesItsStats) {
  for (const std::string& name : drape::testing_support::shipped_scene_names()) {
    const std::string stats = path(std::string(name) + ".json");
    const Result r = drape("run " + scene(name) + " --seconds 0.5 --stats " + stats);
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("frames"), std::string::npos);
    const json s = read_json(stats);
    for (const char* key : {"status",
                            "diverged_frame",
                            "method",
                            "particles",
                            "springs",
                            "frames",
                            "substeps_per_frame",
                            "sim_seconds",
                            "wall_seconds",
                            "setup_ms",
                            "ms_per_frame",
                            "kinetic_energy",
                            "max_strain",
                            "mean_strain",
                            "max_penetration",
                            "pinned_drift",
                            "finite",
                            "state_bytes",
                            "model_bytes",
                            "workspace_bytes",
                            "bytes_per_particle",
                            "self_intersections"})
      EXPECT_TRUE(s.contains(key)) << name << " lacks " << key;
    EXPECT_DOUBLE_EQ(s["bytes_per_particle"].get<double>(),
                     memory_total(s) / s["particles"].get<double>());
    EXPECT_EQ(s["status"], "ok");
    EXPECT_TRUE(s["diverged_frame"].is_null());
    EXPECT_EQ(s["frames"], 30);
    EXPECT_GE(s["particles"], 900) << name;  // 32 × 32 for the grid scenes
    EXPECT_EQ(s["finite"], true);
    EXPECT_EQ(s["pinned_drift"], 0.0);
    EXPECT_TRUE(s["self_intersections"].is_number_integer()) << name;
  }
}

TEST_F(Cli, ExportsEveryNthFrameAndTheLastAsObj) {
  const std::string out = path("frames");
  const Result r =
      drape("run " + scene("hang") + " --seconds 0.2 --export " + out + " --every 5 --quiet");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(r.output.empty()) << r.output;  // --quiet
  // 12 frames: 0, 5, 10 and the last, 12.
  for (const char* f : {"frame_00000.obj", "frame_00005.obj", "frame_00010.obj", "frame_00012.obj"})
    EXPECT_TRUE(fs::exists(fs::path(out) / f)) << f;
  EXPECT_FALSE(fs::exists(fs::path(out) / "frame_00001.obj"));
  std::ifstream in(fs::path(out) / "frame_00012.obj");
  int v = 0, vn = 0, vt = 0, f = 0;
  for (std::string line; std::getline(in, line);) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    v += tag == "v", vn += tag == "vn", vt += tag == "vt";
    if (tag == "f") {
      ++f;
      std::string corner;
      while (ls >> corner) {  // v/vt/vn, 1-based and in range
        const int index = std::stoi(corner.substr(0, corner.find('/')));
        EXPECT_GE(index, 1);
        EXPECT_LE(index, 1024);
      }
    }
  }
  EXPECT_EQ(v, 1024);
  EXPECT_EQ(vn, 1024);
  EXPECT_EQ(vt, 1024);
  EXPECT_EQ(f, 2 * 31 * 31);
}

TEST_F(Cli, AMeshExportsItsOwnTrianglesAndTextureCoordinatesAsItHadThem) {
  // The skirt's tube has a seam: its texture coordinates are per corner, and the export names
  // them so; the triangles are the file's.
  const std::string out = path("skirt");
  const Result r = drape("run " + scene("skirt") + " --seconds 0.05 --export " + out + " --quiet");
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream in(fs::path(out) / "frame_00003.obj"),
      mesh(std::string(DRAPE_SOURCE_DIR) + "/meshes/skirt.obj");
  auto count = [](std::ifstream& f, std::vector<std::string>& faces) {
    std::map<std::string, int> n;
    for (std::string line; std::getline(f, line);) {
      std::istringstream ls(line);
      std::string tag;
      ls >> tag;
      ++n[tag];
      if (tag != "f") continue;
      std::string face, corner;
      while (ls >> corner) face += corner.substr(0, corner.find('/')) + " ";
      faces.push_back(face);
    }
    return n;
  };
  std::vector<std::string> exported, original;
  std::map<std::string, int> a = count(in, exported), b = count(mesh, original);
  EXPECT_EQ(a["v"], b["v"]);
  EXPECT_EQ(a["vt"], b["vt"]);  // more than the vertices: the seam's
  EXPECT_GT(a["vt"], a["v"]);
  EXPECT_EQ(exported, original);  // the same triangles, corner for corner
}

TEST_F(Cli, ABadMeshExitsTwoNamingTheFileAndTheLine) {
  std::ofstream(path("bad.obj")) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 7\n";
  std::ofstream(path("bad.json")) << R"({"cloth": {"mesh": "bad.obj"}})";
  const Result r = drape("run " + path("bad.json") + " --stats " + path("s.json"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("bad.obj): line 4: the face names vertex 7"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(path("s.json")));
}

TEST_F(Cli, ExportsPlyWithAHeaderMeshLabReads) {
  const std::string out = path("ply");
  const Result r =
      drape("run " + scene("sphere") + " --seconds 0.05 --export " + out + " --format ply --quiet");
  ASSERT_EQ(r.code, 0) << r.output;
  const fs::path file = fs::path(out) / "frame_00003.ply";
  ASSERT_TRUE(fs::exists(file));
  std::ifstream in(file, std::ios::binary);
  std::string header, line;
  while (std::getline(in, line) && line != "end_header") header += line + "\n";
  EXPECT_NE(header.find("format binary_little_endian 1.0"), std::string::npos);
  EXPECT_NE(header.find("element vertex 1024"), std::string::npos);
  EXPECT_NE(header.find("element face 1922"), std::string::npos);
  const size_t body = fs::file_size(file) - static_cast<size_t>(in.tellg());
  EXPECT_EQ(body, 1024 * 8 * 4 + 1922 * (1 + 3 * 4));
}

TEST_F(Cli, ExportRefusesAFolderFromAnEarlierRunUnlessForced) {
  const std::string out = path("again");
  ASSERT_EQ(drape("run " + scene("hang") + " --seconds 0.05 --export " + out + " --quiet").code, 0);
  const Result again = drape("run " + scene("hang") + " --seconds 0.05 --export " + out);
  EXPECT_EQ(again.code, 2);
  EXPECT_NE(again.output.find("--force"), std::string::npos) << again.output;
  EXPECT_EQ(
      drape("run " + scene("hang") + " --seconds 0.05 --export " + out + " --force --quiet").code,
      0);
}

TEST_F(Cli, SetOverridesAnyKey) {
  const std::string stats = path("s.json");
  const Result r = drape("run " + scene("hang") +
                         " --seconds 0.05 --set cloth.resolution=[8,6] --set solver.substeps=7"
                         " --set name=small --stats " +
                         stats);
  ASSERT_EQ(r.code, 0) << r.output;
  const json s = read_json(stats);
  EXPECT_EQ(s["particles"], 48);
  EXPECT_EQ(s["substeps_per_frame"], 7);
  EXPECT_EQ(s["scene"], "small");
}

struct BadRun {
  const char* args;
  const char* words;
};

void PrintTo(const BadRun& r, std::ostream* os) {
  *os << r.args;
}

class CliBadInput : public Cli, public ::testing::WithParamInterface<BadRun> {};

TEST_P(CliBadInput, ExitsTwoWithOneClearMessageAndWritesNothing) {
  const std::string stats = path("stats.json"), out = path("out");
  std::string args = GetParam().args;  // HANG and DIR stand for the scene and a scratch folder
  if (size_t at = args.find("HANG"); at != std::string::npos) args.replace(at, 4, scene("hang"));
  if (size_t at = args.find("DIR"); at != std::string::npos) args.replace(at, 3, dir_.string());
  const Result r = drape("run " + args + " --stats " + stats + " --export " + out);
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find(GetParam().words), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(stats));
  EXPECT_FALSE(fs::exists(out));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, CliBadInput,
    ::testing::Values(
        BadRun{"DIR/missing.json", "missing.json: no such file"},
        BadRun{"HANG --set cloth.mass=-1", "cloth.mass: is -1"},
        BadRun{"HANG --set cloth.masss=2", "did you mean \"mass\""},
        BadRun{"HANG --set solver.method=rk4", "solver.method"},
        BadRun{"HANG --set cloth.springs.structural.stiffness=1e9", "substeps per frame"},
        BadRun{"HANG --seconds -1", "--seconds"}, BadRun{"HANG --every 0", "--every"},
        BadRun{"HANG --format stl", "--format"}, BadRun{"HANG --no-such-flag", "no-such-flag"},
        // Budgets that protect the machine, lifted only by --force.
        BadRun{"HANG --set cloth.resolution=[3000,3000]", "GiB budget"},
        BadRun{"HANG --set cloth.resolution=[200000,200000]", "40000000000 particles"},
        BadRun{"HANG --set solver.dt=1e-6 --seconds 86400", "hours of work"},
        // Legal-looking but wild values.
        BadRun{"HANG --set cloth.springs.structural.stiffness=1e308", "inf substeps"},
        BadRun{"HANG --set solver.dt=1e-320", "solver.dt"},
        BadRun{"HANG --set cloth.mass=1e11", "cloth.mass"},
        // Colliders (issue 21): an unknown type, a mesh's missing file, a cloth inside a box.
        BadRun{"HANG --set 'colliders=[{\"type\": \"bx\"}]'", "did you mean \"box\""},
        BadRun{"HANG --set 'colliders=[{\"type\": \"mesh\", \"file\": \"no.obj\"}]'",
               "colliders[0].file"},
        BadRun{"HANG --set 'colliders=[{\"type\": \"box\", \"center\": [0, 1, 0]}]'",
               "inside this box"}));

TEST_F(Cli, DivergenceExitsThreeWithFrameAndHintAndStillWritesStats) {
  const std::string stats = path("d.json");
  const Result r = drape("run " + scene("hang") +
                         " --set cloth.springs.structural.stiffness=1e9 --set solver.substeps=1"
                         " --stats " +
                         stats);
  EXPECT_EQ(r.code, 3) << r.output;
  EXPECT_NE(r.output.find("diverged at frame 1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("smaller solver.dt"), std::string::npos) << r.output;
  const json s = read_json(stats);
  EXPECT_EQ(s["status"], "diverged");
  EXPECT_EQ(s["diverged_frame"], 1);
}

TEST_F(Cli, AStiffSceneExplodesWithSymplecticAndRunsWithImplicit) {
  const std::string stiff = "run " + scene("hang") +
                            " --seconds 1 --set cloth.springs.structural.stiffness=1e9"
                            " --set solver.substeps=1 --stats ";
  const Result explicit_run = drape(stiff + path("symplectic.json"));
  EXPECT_EQ(explicit_run.code, 3) << explicit_run.output;
  EXPECT_NE(explicit_run.output.find("diverged at frame 1"), std::string::npos);
  EXPECT_NE(explicit_run.output.find("symplectic method"), std::string::npos);
  EXPECT_NE(explicit_run.output.find("implicit method"), std::string::npos);  // the hint
  EXPECT_EQ(read_json(path("symplectic.json"))["status"], "diverged");
  const Result implicit_run =
      drape(stiff + path("implicit.json") + " --set solver.method=implicit");
  EXPECT_EQ(implicit_run.code, 0) << implicit_run.output;
  const json s = read_json(path("implicit.json"));
  EXPECT_EQ(s["status"], "ok");
  EXPECT_EQ(s["finite"], true);
}

TEST_F(Cli, WildButLegalValuesEndWithinSecondsAsOkOrDiverged) {
  // Stiffness 1e308 at a fixed substep: forces overflow; the run must stop, not hang or lie.
  const Result r = drape("run " + scene("hang") +
                         " --set cloth.springs.structural.stiffness=1e308 --set solver.substeps=1");
  EXPECT_EQ(r.code, 3) << r.output;
  EXPECT_NE(r.output.find("diverged at frame"), std::string::npos) << r.output;
  const Result heavy =
      drape("run " + scene("sphere") + " --set cloth.mass=1e6 --seconds 1 --quiet");
  EXPECT_EQ(heavy.code, 0) << heavy.output;
}

TEST_F(Cli, InterruptFinishesTheFrameWritesStatsAndExits130) {
  const std::string stats = path("i.json");
  const std::string command = std::string(DRAPE_EXE) + " run " + scene("hang") +
                              " --seconds 1000 --quiet --stats " + stats +
                              " & pid=$!; sleep 1; kill -INT $pid; wait $pid";
  const int status = std::system(("bash -c '" + command + "'").c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  const json s = read_json(stats);
  EXPECT_EQ(s["status"], "interrupted");
  EXPECT_GT(s["frames"].get<int>(), 0);
}

TEST_F(Cli, BenchInterruptedWritesTheRowsSoFarAndExits130) {
  const std::string out = path("bench");
  const std::string command = std::string(DRAPE_EXE) +
                              " bench --scenes hang --sizes 16 --methods symplectic --threads 1"
                              " --frames 1000000 --max-updates 1e15 --out " +
                              out + " >/dev/null 2>&1 & pid=$!; sleep 1; kill -INT $pid; wait $pid";
  const int status = std::system(("bash -c '" + command + "'").c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  const json rows = read_json(out + "/bench.json");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0]["status"], "interrupted");
  EXPECT_TRUE(fs::exists(out + "/bench.csv"));
}

TEST_F(Cli, BenchReportsSpeedBesideQuality) {
  const std::string out = path("bench");
  const json rows = bench_rows(
      "--scenes hang,drape --sizes 12 --methods symplectic --threads 1 --frames 30", out);
  ASSERT_EQ(rows.size(), 2u);
  for (const json& row : rows) {
    EXPECT_EQ(row["status"], "ok");
    EXPECT_EQ(row["particles"], 144);
    EXPECT_GT(row["ms_per_frame_median"].get<double>(), 0.0);
    EXPECT_TRUE(row.contains("p99_strain"));
    EXPECT_GT(row["workspace_bytes"].get<int64_t>(), 0);
    EXPECT_DOUBLE_EQ(row["bytes_per_particle"].get<double>(), memory_total(row) / 144.0);
    // The bar is exactly this: strain within 1% and, on the sphere, no deep contact.
    const bool bar = row["max_strain_last_second"].get<double>() <= 0.01 &&
                     row["max_strain"].get<double>() <= 0.01 &&
                     row["penetration_fraction_of_radius"].get<double>() <= 0.01 &&
                     row["on_sphere"].get<bool>();
    EXPECT_EQ(row["quality"].get<bool>(), bar);
  }
  EXPECT_EQ(drape("bench --methods rk4 --out " + out).code, 2);
}

TEST_F(Cli, BenchRunsXpbdInBothPrecisionsAndOthersInDouble) {
  const std::string out = path("bench");
  const json rows = bench_rows(
      "--scenes hang-lr --sizes 12 --methods symplectic,xpbd --threads 1"
      " --no-search --frames 10",
      out);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0]["method"], "symplectic");
  EXPECT_EQ(rows[0]["precision"], "double");
  EXPECT_EQ(rows[1]["method"], "xpbd");
  EXPECT_EQ(rows[1]["precision"], "double");
  EXPECT_EQ(rows[2]["method"], "xpbd");
  EXPECT_EQ(rows[2]["precision"], "single");
  for (const json& row : rows) EXPECT_EQ(row["status"], "ok");
  // Nothing to run, or a precision that does not exist: an error, not an empty table.
  const Result none = drape("bench --methods symplectic --precision single --out " + out);
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.output.find("only xpbd"), std::string::npos) << none.output;
  EXPECT_EQ(drape("bench --precision quad --out " + out).code, 2);
}

TEST_F(Cli, BenchSearchesXpbdSubstepsAndStiffSweepsForTheBar) {
  const std::string out = path("bench");
  const json rows = bench_rows(
      "--scenes drape --sizes 12 --methods xpbd --precision single --threads 1 --frames 60"
      " --stiff-sweeps 5,0",
      out);
  ASSERT_EQ(rows.size(), 1u);
  const json& row = rows[0];
  EXPECT_EQ(row["status"], "ok");
  EXPECT_TRUE(row["quality"].get<bool>()) << row.dump();
  // The counts asked for, or with line passes none to two after them.
  const int sweeps = row["stiff_sweeps"].get<int>();
  if (row["line_passes"].get<int>() > 0)
    EXPECT_TRUE(sweeps >= 0 && sweeps <= 2) << sweeps;
  else
    EXPECT_TRUE(sweeps == 0 || sweeps == 5) << sweeps;
  EXPECT_GE(row["substep_tries"].get<int>(), 1);
  // The most self-intersections over the frames counted (a cloth draped on a sphere has none).
  EXPECT_TRUE(row["self_intersections_max"].is_number_integer()) << row.dump();
  // Without the search, xpbd runs once at its automatic substeps and no stiff sweeps.
  const json plain = bench_rows(
      "--scenes drape --sizes 12 --methods xpbd --precision single --threads 1 --frames 5"
      " --no-search",
      path("plain"));
  EXPECT_EQ(plain[0]["stiff_sweeps"], 0);
  EXPECT_EQ(plain[0]["substep_tries"], 1);
  EXPECT_EQ(drape("bench --stiff-sweeps -1 --out " + out).code, 2);
}

TEST_F(Cli, TerminateKeepsTheExportsSoFarAndExits143) {
  const std::string out = path("term");
  const std::string command = std::string(DRAPE_EXE) + " run " + scene("hang") +
                              " --seconds 1000 --quiet --every 7 --export " + out +
                              " & pid=$!; sleep 1; kill -TERM $pid; wait $pid";
  const int status = std::system(("bash -c '" + command + "'").c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 143);
  // Whole files only (no .tmp left), frame 0 among them, and the frame it stopped at.
  int frames = 0;
  for (const auto& entry : fs::directory_iterator(out)) {
    EXPECT_EQ(entry.path().extension(), ".obj") << entry.path();
    ++frames;
  }
  EXPECT_GE(frames, 2);
  EXPECT_TRUE(fs::exists(fs::path(out) / "frame_00000.obj"));
}

TEST_F(Cli, CompareRunsEachMethodAndPrintsOneRowEach) {
  const Result r = drape("compare " + scene("hang") +
                         " --seconds 0.2 --threads 1 --set cloth.resolution=[12,12]");
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* column : {"method", "ms/frame", "substeps", "max strain", "mean strain",
                             "kinetic J", "penetration m", "finite"})
    EXPECT_NE(r.output.find(column), std::string::npos) << column;
  int rows = 0;
  std::istringstream lines(r.output);
  for (std::string line; std::getline(lines, line);) {
    for (const char* m : {"symplectic", "implicit", "xpbd", "fast"}) {
      if (line.rfind(m, 0) != 0) continue;
      ++rows;
      EXPECT_NE(line.find(" yes "), std::string::npos) << line;  // finite
      EXPECT_NE(line.find(" ok"), std::string::npos) << line;
    }
  }
  EXPECT_EQ(rows, 4) << r.output;
  // implicit and fast take one step per frame.
  EXPECT_NE(r.output.find("12 frames"), std::string::npos) << r.output;
}

TEST_F(Cli, CompareTakesAMethodListAndRejectsUnknownMethods) {
  const Result two = drape("compare " + scene("sphere") +
                           " --seconds 0.1 --methods xpbd,fast --set cloth.resolution=[8,8]");
  ASSERT_EQ(two.code, 0) << two.output;
  EXPECT_NE(two.output.find("xpbd"), std::string::npos);
  EXPECT_EQ(two.output.find("symplectic"), std::string::npos);
  const Result bad = drape("compare " + scene("hang") + " --methods xpbd,magic");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("unknown method \"magic\""), std::string::npos) << bad.output;
}

TEST_F(Cli, LabRefusesAnUnknownMaterialAndABadMaterialFileNamingTheField) {
  Result r = drape("lab cantilever --material velvet");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("--material: unknown material \"velvet\"; the presets are"),
            std::string::npos)
      << r.output;
  std::ofstream(path("m.json")) << R"({"preset": "denim", "density": -1})";
  r = drape("lab cusick --no-picture --material " + path("m.json"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("m.json: density:"), std::string::npos) << r.output;
  r = drape("lab cusick --no-picture --material " + path("none.json"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("none.json: no such file"), std::string::npos) << r.output;
  r = drape("lab cantilever --material denim --set cloth.pins=[]");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("cloth.pins"), std::string::npos) << r.output;
}

TEST_F(Cli, ALabRunThatBlowsUpExitsThreeNamingTheFrame) {
  // Denim on 1 cm cells with one explicit substep a frame is far past symplectic's bound.
  const Result r = drape(
      "lab cantilever --material denim --resolution 20 --quiet --set solver.method=symplectic "
      "--set solver.substeps=1");
  EXPECT_EQ(r.code, 3) << r.output;
  EXPECT_NE(r.output.find("lab cantilever: the simulation diverged at frame "), std::string::npos)
      << r.output;
}

TEST_F(Cli, LabCusickPrintsJsonAndWritesItsTopViewOnlyWhereAsked) {
  std::ofstream(path("m.json")) << R"({"preset": "knit", "bending": 30e-6})";
  const std::string picture = path("top.png");
  Result r = drape("lab cusick --material " + path("m.json") +
                   " --resolution 8 --seconds 1 --json --picture " + picture);
  ASSERT_EQ(r.code, 0) << r.output;
  const json j = json::parse(r.output.substr(r.output.find('{')));
  EXPECT_EQ(j["test"], "cusick");
  EXPECT_EQ(j["material"], "knit");
  EXPECT_GT(j["drape_coefficient_percent"].get<double>(), 0.0);
  EXPECT_LT(j["drape_coefficient_percent"].get<double>(), 100.0);
  EXPECT_EQ(j["hem_radius_m"].size(), 360u);
#ifdef DRAPE_TEST_HAVE_RENDER
  EXPECT_TRUE(fs::exists(picture));
  // An existing picture is not replaced without --force.
  r = drape("lab cusick --material knit --resolution 8 --seconds 0.5 --picture " + picture);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("already exists; pass --force"), std::string::npos) << r.output;
#endif
}

}  // namespace
