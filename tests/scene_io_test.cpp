// Scene files: every shipped scene loads; every kind of bad input is refused with a message
// that names the file, the JSON path and the problem.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "drape/cloth.h"
#include "drape/error.h"
#include "io/scene_io.h"
#include "shipped_scenes.h"

namespace drape {
namespace {

using nlohmann::json;

std::string scene_path(const std::string& name) {
  return std::string(DRAPE_SOURCE_DIR) + "/scenes/" + name + ".json";
}

// The message parse_scene gives for `j`, or "" if it parses.
std::string error_of(const json& j) {
  try {
    io::parse_scene(j, "test.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

json with(const std::string& assignment) {
  json j = json::object();
  io::apply_override(j, assignment);
  return j;
}

TEST(SceneFiles, EveryShippedSceneLoads) {
  for (const auto& entry : std::filesystem::directory_iterator(DRAPE_SOURCE_DIR "/scenes")) {
    EXPECT_NO_THROW(io::load_scene(entry.path().string())) << entry.path();
  }
}

TEST(SceneFiles, TheDefaultSceneIsTheHangScene) {
  const SceneDef def = io::load_scene(scene_path("hang"));
  EXPECT_EQ(def.cloth.cols, 32);
  EXPECT_EQ(def.cloth.pins.size(), 2u);
  EXPECT_EQ(def.cloth.structural.stiffness, 2000.0);
}

TEST(SceneFiles, RoundTripThroughJsonIsExact) {
  for (const std::string& name : testing_support::shipped_scene_names()) {
    const SceneDef a = io::load_scene(scene_path(name));
    const json ja = io::to_json(a);
    EXPECT_EQ(io::to_json(io::parse_scene(ja, name)), ja) << name;
  }
}

TEST(SceneFiles, EmptyObjectGivesTheDocumentedDefaults) {
  const SceneDef def = io::parse_scene(json::object(), "empty.json");
  EXPECT_EQ(io::to_json(def), io::to_json(SceneDef{}));
}

TEST(SceneFiles, CornerNamesAndIndicesPin) {
  const SceneDef def = io::parse_scene(json::parse(R"({"cloth": {"resolution": [10, 5],
                     "pins": ["top-left", "top-right", "bottom-left", "bottom-right", [3, 2]]}})"),
                                       "pins.json");
  ASSERT_EQ(def.cloth.pins.size(), 5u);
  EXPECT_EQ(def.cloth.pins[1].col, -1);  // the last column, at any resolution
  EXPECT_EQ(def.cloth.pins[3].row, -1);
  EXPECT_EQ(def.cloth.pins[4].col, 3);
}

TEST(SceneFiles, ABallPinHoldsEveryVertexWithinItsRadiusAndRoundTrips) {
  // A horizontal 1 m grid of 11 × 11 at y = 1: the ball of radius 0.25 about its centre holds
  // the particles within 2.5 spacings of it (none lies near its surface to round either way).
  const SceneDef def = io::parse_scene(
      json::parse(R"({"cloth": {"resolution": [11, 11], "size": [1, 1], "origin": [0, 1, 0],
                     "orientation": "horizontal",
                     "pins": [{"ball": {"center": [0.5, 1, 0.5], "radius": 0.25}}]}})"),
      "ball.json");
  ASSERT_EQ(def.cloth.pins.size(), 1u);
  EXPECT_EQ(def.cloth.pins[0].kind, PinKind::ball);
  const ClothModel m = build_model(def.cloth);
  const std::vector<int32_t> held = pinned_particles(def.cloth, m);
  int expected = 0;
  for (int c = 0; c < 11; ++c)
    for (int r = 0; r < 11; ++r) expected += (c - 5) * (c - 5) + (r - 5) * (r - 5) <= 6;
  EXPECT_EQ(static_cast<int>(held.size()), expected);
  for (int32_t i : held) EXPECT_LE((m.rest_position[i] - Vec3(0.5, 1, 0.5)).norm(), 0.25);
  const SceneDef back = io::parse_scene(io::to_json(def), "again");
  EXPECT_EQ(back.cloth.pins[0].ball_radius, 0.25);
  EXPECT_EQ(back.cloth.pins[0].ball_center, Vec3(0.5, 1, 0.5));
  // A ball that holds nothing is refused, naming it.
  SceneDef far = def;
  far.cloth.pins[0].ball_center = Vec3(5, 5, 5);
  try {
    pinned_particles(far.cloth, m);
    ADD_FAILURE() << "a ball holding no vertex was taken";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "cloth.pins[0].ball");
    EXPECT_NE(e.problem().find("holds no vertex"), std::string::npos) << e.what();
  }
}

struct BadCase {
  const char* assignment;  // applied to an empty scene
  const char* path;        // the JSON path the message must name
  const char* words;       // and words it must contain
};

void PrintTo(const BadCase& c, std::ostream* os) {
  *os << c.assignment;
}

class BadInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadInput, IsRefusedNamingFilePathAndProblem) {
  const BadCase& c = GetParam();
  const std::string message = error_of(with(c.assignment));
  ASSERT_FALSE(message.empty()) << c.assignment << " was accepted";
  EXPECT_EQ(message.rfind("test.json: ", 0), 0u) << message;
  EXPECT_NE(message.find(c.path), std::string::npos) << message;
  EXPECT_NE(message.find(c.words), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadInput,
    ::testing::Values(
        BadCase{"cloth.resolutoin=[4,4]", "cloth.resolutoin", "did you mean \"resolution\""},
        BadCase{"forces.gravty=[0,0,0]", "forces.gravty", "did you mean \"gravity\""},
        BadCase{"nonsense=1", "nonsense", "unknown key"},
        BadCase{"cloth.mass=heavy", "cloth.mass", "expected a number, got a string"},
        BadCase{"cloth.mass=[1]", "cloth.mass", "expected a number"},
        BadCase{"cloth.mass=0", "cloth.mass", "must be in (0"},
        BadCase{"cloth.mass=-1", "cloth.mass", "must be in (0"},
        BadCase{"cloth.size=[0,1]", "cloth.size[0]", "must be in (0"},
        BadCase{"cloth.size=[1]", "cloth.size", "expected an array of 2"},
        BadCase{"cloth.resolution=[1,8]", "cloth.resolution", "at least 2x2"},
        BadCase{"cloth.resolution=[2.5,8]", "cloth.resolution[0]", "expected an integer"},
        BadCase{"cloth.resolution=[200000,200000]", "cloth.resolution", "more than the limit"},
        BadCase{"cloth.origin=[0,0]", "cloth.origin", "array of 3 numbers"},
        BadCase{"cloth.orientation=sideways", "cloth.orientation", "expected one of"},
        BadCase{"cloth.pins=[[32,0]]", "cloth.pins[0]", "outside the 32x32 grid"},
        BadCase{"cloth.pins=[\"middle\"]", "cloth.pins[0]", "unknown corner"},
        BadCase{"cloth.pins=[{\"ball\": {\"center\": [0, 0, 0], \"radius\": 0}}]",
                "cloth.pins[0].ball.radius", "must be in (0"},
        BadCase{"cloth.pins=[{\"ball\": {\"radius\": 1}}]", "cloth.pins[0].ball.center", "missing"},
        BadCase{"cloth.pins=[{\"ball\": {\"center\": [0, 0, 0], \"radius\": 1}, \"box\": 1}]",
                "cloth.pins[0]", "expected one of"},
        BadCase{"cloth.springs.shear.stiffness=-5", "cloth.springs.shear.stiffness",
                "must not be negative"},
        BadCase{"cloth.springs.bending.damping=-1", "cloth.springs.bending.damping",
                "must not be negative"},
        BadCase{"cloth.springs.twist={}", "cloth.springs.twist", "unknown key"},
        BadCase{"forces.air_drag=-0.1", "forces.air_drag", "must not be negative"},
        BadCase{"forces.wind.model=storm", "forces.wind.model", "\"seed\", \"aero\""},
        BadCase{"forces.wind={\"strength\":1,\"direction\":[0,0,0]}", "forces.wind.direction",
                "must not be zero"},
        BadCase{"colliders=[{\"type\":\"cube\"}]", "colliders[0].type", "unknown value"},
        BadCase{"colliders=[{\"radius\":1}]", "colliders[0].type", "missing"},
        BadCase{"colliders=[{\"type\":\"sphere\",\"radius\":-1}]", "colliders[0].radius",
                "must be in (0"},
        BadCase{"colliders=[{\"type\":\"plane\",\"radius\":1}]", "colliders[0].radius",
                "unknown key"},
        BadCase{"colliders=[{\"type\":\"sphere\",\"friction\":-1}]", "colliders[0].friction",
                "must not be negative"},
        BadCase{"colliders={}", "colliders", "expected an array"},
        BadCase{"solver.method=magic", "solver.method", "unknown value"},
        BadCase{"solver.dt=0.5", "solver.dt", "must be in [1e-06, 0.1]"},
        BadCase{"solver.dt=1e-7", "solver.dt", "must be in [1e-06, 0.1]"},
        BadCase{"solver.substeps=-1", "solver.substeps", "must be in [0"},
        BadCase{"duration=-1", "duration", "must be in [0"},
        BadCase{"name=3", "name", "expected a string"}));

TEST(Overrides, SetNestedKeysArrayElementsAndBareWords) {
  json j = json::parse(R"({"colliders": [{"type": "sphere", "radius": 0.5}]})");
  io::apply_override(j, "cloth.resolution=[64,48]");
  io::apply_override(j, "colliders.0.radius=0.75");
  io::apply_override(j, "name=windy");
  const SceneDef def = io::parse_scene(j, "o.json");
  EXPECT_EQ(def.cloth.cols, 64);
  EXPECT_EQ(def.cloth.rows, 48);
  EXPECT_EQ(def.colliders[0].radius, 0.75);
  EXPECT_EQ(def.name, "windy");
}

// Found by fuzz/override_fuzz: a bare-word value with invalid UTF-8 made the error message's
// JSON dump throw a type_error instead of the loader's InputError.
TEST(Overrides, InvalidUtf8InAValueIsAnInputError) {
  json j = json::object();
  io::apply_override(j,
                     "cloth.pins=[\"top-left\",\x9b"
                     "3,-1]]");
  EXPECT_THROW(io::parse_scene(j, "fuzz.json"), InputError);
}

TEST(Overrides, MalformedOrImpossibleOnesAreRefused) {
  json j = json::parse(R"({"colliders": [], "cloth": {"mass": 1}})");
  EXPECT_THROW(io::apply_override(j, "novalue"), InputError);
  EXPECT_THROW(io::apply_override(j, "=3"), InputError);
  EXPECT_THROW(io::apply_override(j, "cloth..mass=3"), InputError);
  EXPECT_THROW(io::apply_override(j, "colliders.0.radius=1"), InputError);  // no collider 0
  EXPECT_THROW(io::apply_override(j, "cloth.mass.value=1"), InputError);    // mass is a number
}

class FileErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("drape_scene_io_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  std::string error_loading(const std::string& path) {
    try {
      io::load_scene(path);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  std::filesystem::path dir_;
};

TEST_F(FileErrors, MissingFile) {
  const std::string path = (dir_ / "nope.json").string();
  EXPECT_EQ(error_loading(path), path + ": no such file");
}

TEST_F(FileErrors, Folder) {
  EXPECT_NE(error_loading(dir_.string()).find("is a folder"), std::string::npos);
}

TEST_F(FileErrors, EmptyFile) {
  const std::string path = write("empty.json", "  \n");
  EXPECT_EQ(error_loading(path), path + ": the file is empty");
}

TEST_F(FileErrors, InvalidJsonNamesLineAndColumn) {
  const std::string path = write("bad.json", "{\n  \"cloth\": {\n    \"mass\": 1,\n  }\n}\n");
  const std::string message = error_loading(path);
  EXPECT_EQ(message.rfind(path + ": invalid JSON", 0), 0u) << message;
  EXPECT_NE(message.find("line 4"), std::string::npos) << message;
}

TEST_F(FileErrors, NumbersTooLargeForADoubleAreRefused) {
  const std::string path = write("huge.json", R"({"cloth": {"mass": 1e999}})");
  EXPECT_NE(error_loading(path).find("number overflow"), std::string::npos);
  json j = json::object();
  try {
    io::apply_override(j, "forces.gravity=[0,1e999,0]");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--set forces.gravity"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("number overflow"), std::string::npos) << e.what();
  }
}

TEST_F(FileErrors, RangeErrorsNameTheFile) {
  const std::string path = write("range.json", R"({"cloth": {"mass": -2}})");
  EXPECT_EQ(error_loading(path), path + ": cloth.mass: is -2, must be in (0, 1e+06]");
}

}  // namespace
}  // namespace drape
