// Cloth meshes from OBJ files and scene files that name them: what is read, and every kind of
// bad file refused with its line.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "drape/error.h"
#include "drape/simulation.h"
#include "io/mesh_export.h"
#include "io/obj_import.h"
#include "io/scene_io.h"
#include "temp_dir.h"

namespace drape {
namespace {

using nlohmann::json;

class Obj : public testing_support::TempDirTest {
 protected:
  Obj() : TempDirTest("drape_obj_") {}
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  // The message a scene naming `obj` as its cloth (with `extra` keys in "cloth") gives.
  std::string scene_error(const std::string& obj_text, const std::string& extra = "") const {
    write("cloth.obj", obj_text);
    const std::string scene = write(
        "scene.json", R"({"cloth": {"mesh": "cloth.obj")" + extra + "}}");
    try {
      io::load_scene(scene);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
};

const char* kSquare =
    "# a unit square as one quad\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "f 1/1 2/2 3/3 4/4\n";

TEST_F(Obj, ReadsVerticesFansPolygonsAndKeepsTexcoordsAndLines) {
  const ClothMesh m = io::read_obj(write("square.obj", kSquare));
  ASSERT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.positions[2], Vec3(1, 1, 0));
  ASSERT_EQ(m.triangles.size(), 2u);  // the quad as a fan from its first corner
  EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (Triangle{0, 2, 3}));
  ASSERT_EQ(m.triangle_texcoords.size(), 2u);
  EXPECT_EQ(m.texcoords[m.triangle_texcoords[1][2]], Vec2(0, 1));
  EXPECT_EQ(m.triangle_line, (std::vector<int32_t>{10, 10}));  // the face's line, for messages
}

TEST_F(Obj, NegativeIndicesCountBackAndGroupsAndMaterialsAreIgnored) {
  const ClothMesh m = io::read_obj(write(
      "n.obj", "mtllib nowhere.mtl\no cloth\nv 0 0 0\nv 1 0 0\nv 0 1 0\ng part\nusemtl red\n"
               "s off\nvn 0 0 1\nf -3//1 -2//1 -1//1\n"));
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_TRUE(m.triangle_texcoords.empty());  // no vt: none
}

TEST_F(Obj, ASeamsTexcoordsSurviveTheModelAndTheExport) {
  // Vertex 0 has u = 0 in one face and u = 1 in the other (a seam): the model keeps both, and
  // the exported OBJ names them per corner, v flipped back as OBJ has it.
  const std::string file = write(
      "seam.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                  "vt 0 0\nvt 0.5 0\nvt 0.5 1\nvt 1 0\nvt 1 1\n"
                  "f 1/1 2/2 3/3\nf 1/4 3/5 4/3\n");
  SceneDef def;
  def.cloth.mesh = std::make_shared<const ClothMesh>(io::read_obj(file));
  def.cloth.pins.clear();
  Simulation sim(def);
  ASSERT_FALSE(sim.model().triangle_texcoords.empty());
  io::write_mesh(path("out.obj"), io::MeshFormat::obj, sim.model(), sim.state());
  const ClothMesh back = io::read_obj(path("out.obj"));
  ASSERT_EQ(back.triangles.size(), 2u);
  for (int t = 0; t < 2; ++t)
    for (int c = 0; c < 3; ++c) {
      const Vec2 in = def.cloth.mesh->texcoords[def.cloth.mesh->triangle_texcoords[t][c]];
      const Vec2 out = back.texcoords[back.triangle_texcoords[t][c]];
      EXPECT_LT((in - out).norm(), 1e-6) << t << " " << c;
    }
}

TEST_F(Obj, ASceneFindsItsMeshBesideItAndPlacesIt) {
  write("square.obj", kSquare);
  const SceneDef def = io::load_scene(write(
      "s.json", R"({"cloth": {"mesh": "square.obj",
        "transform": {"translate": [1, 2, 3], "rotate": [90, 0, 0], "scale": 2},
        "pins": [{"vertex": 3}, {"box": {"min": [0.9, 1.9, 2.9], "max": [1.1, 2.1, 3.1]}}]}})"));
  ASSERT_TRUE(def.cloth.mesh);
  EXPECT_EQ(def.cloth.mesh_file, path("square.obj"));
  EXPECT_EQ(def.cloth.transform.scale, Vec3(2, 2, 2));
  ASSERT_EQ(def.cloth.pins.size(), 2u);
  EXPECT_EQ(def.cloth.pins[0].kind, PinKind::vertex);
  EXPECT_EQ(def.cloth.pins[1].kind, PinKind::box);
  Simulation sim(def);
  // (0, 1, 0) scaled to (0, 2, 0), turned to (0, 0, 2), moved to (1, 2, 5).
  EXPECT_LT((sim.state().x[3] - Vec3(1, 2, 5)).norm(), 1e-12);
  EXPECT_TRUE(sim.state().pinned[3]);
  EXPECT_TRUE(sim.state().pinned[0]);   // the box is round where (0, 0, 0) is placed: (1, 2, 3)
  EXPECT_FALSE(sim.state().pinned[1]);  // and holds nothing else
}

TEST_F(Obj, AMeshWithoutPinsHasNoneAndItsSceneRoundTrips) {
  write("square.obj", kSquare);
  const SceneDef def = io::load_scene(write("s.json", R"({"cloth": {"mesh": "square.obj"}})"));
  EXPECT_TRUE(def.cloth.pins.empty());  // the grid's default corners are not a mesh's
  const SceneDef again = io::parse_scene(io::to_json(def), "again");
  EXPECT_EQ(again.cloth.mesh_file, def.cloth.mesh_file);
  EXPECT_EQ(again.cloth.mesh->positions, def.cloth.mesh->positions);
}

struct BadObj {
  const char* what;
  const char* text;
  const char* words;
};

void PrintTo(const BadObj& b, std::ostream* os) { *os << b.what; }

class BadObjFile : public Obj, public ::testing::WithParamInterface<BadObj> {};

TEST_P(BadObjFile, IsRefusedNamingTheFileTheLineAndTheProblem) {
  const std::string message = scene_error(GetParam().text);
  ASSERT_FALSE(message.empty()) << "accepted";
  EXPECT_NE(message.find("cloth.mesh (" + path("cloth.obj") + ")"), std::string::npos) << message;
  EXPECT_NE(message.find(GetParam().words), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadObjFile,
    ::testing::Values(
        BadObj{"a word for a number", "v 0 0 0\nv 1 0 zero\n", "line 2: \"zero\" is not a number"},
        BadObj{"too few numbers", "v 0 0\n", "line 1: expected x y z"},
        BadObj{"non-finite", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n",
               "line 2: \"nan\" is not a finite number"},
        BadObj{"an unknown statement", "v 0 0 0\nbogus 1 2\n", "line 2: unknown statement"},
        BadObj{"a face of two", "v 0 0 0\nv 1 0 0\nf 1 2\n", "line 3: a face needs at least 3"},
        BadObj{"a broken reference", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2/x 3\n",
               "line 4: \"2/x\" is not a vertex reference"},
        BadObj{"index zero", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "line 4"},
        BadObj{"index out of range", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n",
               "line 4: the face names vertex 9, but the file has 3 vertices"},
        BadObj{"no triangles", "v 0 0 0\nv 1 0 0\n", "has no triangles"},
        BadObj{"zero area", "v 0 0 0\nv 1 0 0\nv 2 0 0\n\nf 1 2 3\n",
               "the face on line 5 (vertices 0, 1, 2) has zero area"},
        BadObj{"non-manifold",
               "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\nf 1 2 5\n",
               "the edge between vertices 0 and 1 is shared by 3 triangles (the face on line 6, "
               "the face on line 7, the face on line 8)"},
        BadObj{"empty", "", "has no triangles"}));

TEST_F(Obj, AMissingOrSpecialFileIsRefused) {
  write("scene.json", R"({"cloth": {"mesh": "absent.obj"}})");
  try {
    io::load_scene(path("scene.json"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("absent.obj): no such file"), std::string::npos)
        << e.what();
  }
  std::filesystem::create_directory(path("folder.obj"));
  write("scene2.json", R"({"cloth": {"mesh": "folder.obj"}})");
  EXPECT_THROW(io::load_scene(path("scene2.json")), InputError);
}

TEST_F(Obj, GridKeysBesideAMeshAndATransformWithoutOneAreRefused) {
  EXPECT_NE(scene_error(kSquare, R"(, "resolution": [8, 8], "size": [1, 1])")
                .find("the grid's keys (cloth.size, cloth.resolution) have no meaning"),
            std::string::npos);
  write("t.json", R"({"cloth": {"transform": {"scale": 2}}})");
  EXPECT_THROW(io::load_scene(path("t.json")), InputError);
  EXPECT_NE(scene_error(kSquare, R"(, "transform": {"scale": 0})").find("cloth.transform.scale"),
            std::string::npos);
  EXPECT_NE(scene_error(kSquare, R"(, "pins": ["top-left"])").find("needs a grid cloth"),
            std::string::npos);
  EXPECT_NE(scene_error(kSquare, R"(, "pins": [{"vertex": 4}])").find("cloth.pins[0].vertex"),
            std::string::npos);
  EXPECT_NE(scene_error(kSquare, R"(, "pins": [{"box": {"min": [1, 1, 1], "max": [0, 2, 2]}}])")
                .find("min is above max along x"),
            std::string::npos);
}

}  // namespace
}  // namespace drape
