// tests/gui/test_ui_drop.cpp: files dropped on the window (drop.h): the dispatch by extension, the current scene
// with a dropped environment map, and the loads they start (scene_loads.h). No display.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/base/error.h"
#include "core/image/image_io.h"
#include "core/load/scene_file.h"
#include "drop.h"
#include "scene_loads.h"
#include "tests/support/temp_dir.h"

namespace pv::ui {
namespace {}  // namespace

TEST(ViewerDrop, KindByExtensionInAnyCase) {
    for (const char* p : {"a.obj", "dir/b.JSON", "c.gltf", "/x/y/d.GLB"}) EXPECT_EQ(drop_kind(p), DropKind::Scene) << p;
    for (const char* p : {"sky.exr", "sky.HDR", "/m/n.png", "photo.JPG", "a.jpeg"})
        EXPECT_EQ(drop_kind(p), DropKind::EnvironmentMap) << p;
    for (const char* p : {"notes.txt", "mesh.ply", "noext", "archive.obj.gz", ".exr", "dir.obj/"})
        EXPECT_EQ(drop_kind(p), DropKind::Unknown) << p;
}

TEST(ViewerDrop, FirstKnownFileIsLoadedAndUnknownOnesAreNamed) {
    EXPECT_EQ(dispatch_drop({}).kind, DropKind::Unknown);
    EXPECT_TRUE(dispatch_drop({}).message.empty());
    DropRequest r = dispatch_drop({"/s/room.obj"});
    EXPECT_EQ(r.kind, DropKind::Scene);
    EXPECT_EQ(r.path, "/s/room.obj");
    EXPECT_EQ(r.message, "loading scene /s/room.obj ...");
    r = dispatch_drop({"/a/readme.txt", "/m/sky.hdr", "/s/room.obj"});
    EXPECT_EQ(r.kind, DropKind::EnvironmentMap);
    EXPECT_EQ(r.path, "/m/sky.hdr");
    EXPECT_EQ(r.message, "loading environment map /m/sky.hdr ... (2 other files ignored)");
    r = dispatch_drop({"/a/readme.txt", "/b/c.ply"});
    EXPECT_EQ(r.kind, DropKind::Unknown);
    EXPECT_TRUE(r.path.empty());
    EXPECT_EQ(r.message.rfind("/a/readme.txt: unknown file type; ", 0), 0u) << r.message;
    EXPECT_EQ(r.message.find('\n'), std::string::npos);
}

// A dropped map lights the current scene as `--environment MAP` would, from the current camera and with the edited
// materials and light; a bad file throws naming it and the scene is untouched.
TEST(ViewerDrop, EnvironmentMapJoinsTheSceneAsEdited) {
    const test::TestDir dir("pathview-drop");
    const Scene scene = load_scene(builtin_scene_path());
    Image map(8, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) map.set(x, y, vec3(0.5f + 0.1f * float(x), 0.25f, 1.f));
    const std::string map_path = dir.file("sky.exr");
    write_exr(map_path, map);
    const CameraDesc camera{vec3(1.f, 2.f, 3.f), vec3(0.f), vec3(0.f, 1.f, 0.f), 35.f};
    std::vector<Material> materials = scene.materials;
    ASSERT_FALSE(materials.empty());
    materials[0].emission = vec3(7.f);
    EnvironmentSettings env = scene.environment;
    env.rotation_deg = 30.f;
    env.strength = 2.f;

    const Scene lit = with_environment_map(scene, map_path, camera, materials, env);
    ASSERT_NE(lit.environment_map, kNoIndex);
    ASSERT_LT(lit.environment_map, lit.textures.size());
    EXPECT_EQ(lit.textures[lit.environment_map].width(), 8);
    EXPECT_EQ(lit.textures[lit.environment_map].height(), 4);
    EXPECT_EQ(lit.camera.eye, camera.eye);
    EXPECT_EQ(lit.camera.vfov_deg, 35.f);
    EXPECT_EQ(lit.materials[0].emission, vec3(7.f));
    EXPECT_TRUE(lit.environment == env);
    EXPECT_EQ(lit.triangle_count(), scene.triangle_count());
    EXPECT_EQ(scene.environment_map, load_scene(builtin_scene_path()).environment_map);  // the original is untouched

    for (const std::string& bad : {dir.write("junk.hdr", "not an image"), dir.file("missing.exr")}) {
        try {
            with_environment_map(scene, bad, camera, materials, env);
            ADD_FAILURE() << bad << " loaded";
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind(bad, 0), 0u) << e.what();
        }
    }
}

// A dropped scene loads in the background; a failure names the file in the drop's status and the Scene section and
// leaves nothing to adopt; a drop while another load runs (until it is taken) is refused and says why; a dropped scene
// that loads is adopted with a "loaded scene PATH" status.
TEST(ViewerDrop, SceneLoadsReportFailuresRefuseADropDuringALoadAndNameWhatLoaded) {
    const test::TestDir dir("pathview-scene-loads");
    ViewLog log("");
    ActiveScene scene(log);
    SceneLoader loader([] {});
    SceneLoads loads(loader, scene, log, 1);
    ViewState state;
    const CameraDesc camera{vec3(0.f, 0.f, 5.f), vec3(0.f), vec3(0.f, 1.f, 0.f), 40.f};

    const std::string bad = dir.write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    std::vector<std::string> dropped{bad};
    loads.drop(dropped, state, camera);
    EXPECT_TRUE(dropped.empty());
    EXPECT_TRUE(state.drop_ok) << state.drop_status;
    EXPECT_TRUE(state.scene_loading);
    loader.wait();
    EXPECT_FALSE(loads.take_finished(state).has_value());
    EXPECT_FALSE(state.drop_ok);
    EXPECT_EQ(state.drop_status.rfind(bad, 0), 0u) << state.drop_status;
    EXPECT_EQ(state.scene_status, state.drop_status);
    EXPECT_FALSE(state.scene_loading);

    state.scene_path = builtin_scene_path();
    loads.load(state);
    loader.wait();
    const std::string good = dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    dropped = {good};
    loads.drop(dropped, state, camera);  // the first load has ended but is not taken: still one at a time
    EXPECT_FALSE(state.drop_ok);
    EXPECT_EQ(state.drop_status, good + ": not loaded, another load is running; drop it again when that ends");
    std::optional<LoadedScene> first = loads.take_finished(state);
    ASSERT_TRUE(first.has_value());
    scene.adopt(first->scene, state);  // as the viewer's use_scene() does
    loads.adopted(state);
    EXPECT_EQ(state.scene_status, "loaded " + builtin_scene_path());
    EXPECT_FALSE(state.drop_ok);  // that load was no drop: the refusal stays on screen

    dropped = {good};
    loads.drop(dropped, state, camera);
    loader.wait();
    std::optional<LoadedScene> second = loads.take_finished(state);
    ASSERT_TRUE(second.has_value());
    EXPECT_EQ(second->scene->triangle_count(), 1u);
    scene.adopt(second->scene, state);
    loads.adopted(state);
    EXPECT_TRUE(state.drop_ok);
    EXPECT_EQ(state.drop_status, "loaded scene " + good);
}

}  // namespace pv::ui
