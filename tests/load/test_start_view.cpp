// tests/load/test_start_view.cpp: the start view of a scene without a camera (core/load/start_view.h): a closed room
// starts inside, looking along its long axis; objects (a closed sphere, a box open at its front with blocks in it) keep
// the outside framing bit for bit; load_scene gives OBJ and JSON scenes without a camera that view.
// Test kinds: unit
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/load/scene_file.h"
#include "core/load/start_view.h"
#include "tests/support/cli.h"
#include "tests/support/scenes.h"
#include "tests/support/temp_dir.h"

namespace pv {
namespace {

namespace fs = std::filesystem;

// The box [lo, hi] as six quads facing out of it, or into it when `inward` (a room's walls); `skip_face` (0..5:
// -x, +x, -y, +y, -z, +z) is left out.
void add_box(Scene& s, vec3 lo, vec3 hi, bool inward, uint32_t material, int skip_face = -1) {
    for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
            if (a * 2 + side == skip_face) continue;
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            vec3 q[4];
            const vec2 corner[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int k = 0; k < 4; ++k) {
                q[k][a] = side ? hi[a] : lo[a];
                q[k][b] = corner[k].x ? hi[b] : lo[b];
                q[k][c] = corner[k].y ? hi[c] : lo[c];
            }
            vec3 want(0.f);
            want[a] = (side ? 1.f : -1.f) * (inward ? -1.f : 1.f);
            if (glm::dot(glm::cross(q[1] - q[0], q[2] - q[0]), want) < 0.f) std::swap(q[1], q[3]);
            test::add_quad(s, q[0], q[1], q[2], q[3], material);
        }
}

// A closed room 10 x 3 x 4 (its long axis x) with a floor-to-ceiling pillar that holds candidate eyes of the grid.
Scene room_with_pillar() {
    Scene s;
    const uint32_t m = test::add_material(s, Material{});
    add_box(s, vec3(0.f), vec3(10.f, 3.f, 4.f), true, m);
    add_box(s, vec3(5.5f, 0.f, 1.5f), vec3(6.2f, 3.f, 2.5f), false, m);
    return s;
}

void expect_same_camera(const CameraDesc& a, const CameraDesc& b) {
    for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(a.eye[k], b.eye[k]);
        EXPECT_EQ(a.target[k], b.target[k]);
        EXPECT_EQ(a.up[k], b.up[k]);
    }
    EXPECT_EQ(a.vfov_deg, b.vfov_deg);
    EXPECT_EQ(a.aperture, b.aperture);
    EXPECT_EQ(a.focus_distance, b.focus_distance);
}

void expect_inside_looking_along_x(const StartView& v) {
    ASSERT_TRUE(v.inside);
    const vec3 e = v.camera.eye;
    EXPECT_TRUE(e.x > 0.f && e.x < 10.f && e.y > 0.f && e.y < 3.f && e.z > 0.f && e.z < 4.f) << "in the room";
    EXPECT_FALSE(e.x >= 5.5f && e.x <= 6.2f && e.z >= 1.5f && e.z <= 2.5f) << "not in the pillar";
    const vec3 d = glm::normalize(v.camera.target - e);
    EXPECT_EQ(d.y, 0.f) << "horizontal";
    EXPECT_GT(std::fabs(d.x), std::cos(glm::radians(20.f))) << "along the long axis: " << d.x << ", " << d.z;
    EXPECT_EQ(v.camera.up, vec3(0.f, 1.f, 0.f));
    EXPECT_EQ(v.enclosed_share, 1.f) << "every candidate outside the pillar is enclosed";
}

TEST(StartView, ClosedRoomStartsInsideLookingAlongItsLongAxis) {
    const Scene s = room_with_pillar();
    expect_inside_looking_along_x(choose_start_view(s));
    // Deterministic: the same view again.
    expect_same_camera(choose_start_view(s).camera, choose_start_view(s).camera);
}

TEST(StartView, ObjectsKeepTheOutsideFramingBitForBit) {
    // A closed sphere: inside it every probe sees the back of its surface.
    Scene sphere;
    test::add_icosphere(sphere, vec3(1.f, 2.f, 3.f), 1.5f, 3, test::add_material(sphere, Material{}));
    const StartView a = choose_start_view(sphere);
    EXPECT_FALSE(a.inside);
    EXPECT_EQ(a.enclosed_share, 0.f);
    expect_same_camera(a.camera, sphere.framing_camera());
    // A Cornell-like box: five walls facing in, open at +z, two blocks in it. Enclosed only near its back wall.
    Scene box;
    const uint32_t m = test::add_material(box, Material{});
    add_box(box, vec3(-1.f, 0.f, -1.f), vec3(1.f, 2.f, 1.f), true, m, 5);
    add_box(box, vec3(-0.7f, 0.f, -0.6f), vec3(-0.1f, 1.2f, 0.f), false, m);
    add_box(box, vec3(0.1f, 0.f, -0.2f), vec3(0.7f, 0.6f, 0.4f), false, m);
    const StartView b = choose_start_view(box);
    EXPECT_FALSE(b.inside);
    EXPECT_LT(b.enclosed_share, 0.25f);
    expect_same_camera(b.camera, box.framing_camera());
    // The same room with its front wall gone is such a box too.
    Scene open_room;
    add_box(open_room, vec3(0.f), vec3(10.f, 3.f, 4.f), true, test::add_material(open_room, Material{}), 5);
    EXPECT_FALSE(choose_start_view(open_room).inside);
    // No triangles, or a flat scene: the framing.
    Scene empty;
    expect_same_camera(choose_start_view(empty).camera, empty.framing_camera());
    Scene flat;
    test::add_quad(flat, vec3(0, 0, 0), vec3(1, 0, 0), vec3(1, 0, -1), vec3(0, 0, -1),
                   test::add_material(flat, Material{}));
    expect_same_camera(choose_start_view(flat).camera, flat.framing_camera());
}

// Scenes loaded without a camera (pathview render SCENE and pathview view both go through load_scene) start from
// choose_start_view's camera: inside the room, outside the sphere; a JSON scene's "camera" still wins.
TEST(StartView, LoadSceneStartsFromIt) {
    const test::TestDir tmp("pathview_start_view");
    const fs::path& dir = tmp.path;
    // With `lamp`, the last two triangles emit (an MTL with Ke).
    auto write_obj = [&](const Scene& s, const std::string& name, bool lamp = false) {
        std::ofstream f(dir / name);
        if (lamp) {
            std::ofstream(dir / (name + ".mtl")) << "newmtl wall\nKd 0.8 0.8 0.8\nnewmtl lamp\nKd 0 0 0\nKe 5 5 5\n";
            f << "mtllib " << name << ".mtl\nusemtl wall\n";
        }
        for (const vec3& p : s.positions) f << "v " << p.x << " " << p.y << " " << p.z << "\n";
        for (size_t i = 0; i < s.triangles.size(); ++i) {
            if (lamp && i + 2 == s.triangles.size()) f << "usemtl lamp\n";
            const uvec3 t = s.triangles[i];
            f << "f " << t.x + 1 << " " << t.y + 1 << " " << t.z + 1 << "\n";
        }
        return (dir / name).string();
    };
    // The room with a small lamp under its ceiling, facing down.
    Scene lit_room = room_with_pillar();
    test::add_quad(lit_room, vec3(2.f, 2.95f, 1.f), vec3(2.5f, 2.95f, 1.f), vec3(2.5f, 2.95f, 1.5f),
                   vec3(2.f, 2.95f, 1.5f), 0);
    const std::string room = write_obj(lit_room, "room.obj", true);
    Scene sphere_src;
    test::add_icosphere(sphere_src, vec3(0.f), 1.f, 2, test::add_material(sphere_src, Material{}));
    const std::string sphere = write_obj(sphere_src, "sphere.obj");
    std::ofstream(dir / "room.json") << R"({"obj": "room.obj"})";
    std::ofstream(dir / "room_camera.json") << R"({"obj": "room.obj", "camera": {"fov": 30}})";

    const Scene r = load_scene(room);
    EXPECT_FALSE(r.has_camera);
    expect_inside_looking_along_x(choose_start_view(r));
    expect_same_camera(r.camera, choose_start_view(r).camera);
    const Scene rj = load_scene((dir / "room.json").string());
    expect_same_camera(rj.camera, r.camera);
    const Scene rc = load_scene((dir / "room_camera.json").string());
    CameraDesc framed = rc.framing_camera();  // as before: the framing, its fields overridden by "camera"
    framed.vfov_deg = 30.f;
    expect_same_camera(rc.camera, framed);
    const Scene sp = load_scene(sphere);
    expect_same_camera(sp.camera, sp.framing_camera());

    EXPECT_FALSE(r.default_sky_warning) << "the lamp lights it";

    // Without its lamp the sealed room would be lit only by a sky that cannot reach inside: it is framed from
    // outside, and a warning says why. A camera given in the file still wins; the sphere and the same room open to
    // the sky through its ceiling (below) start as before, without that warning.
    auto outside_warning = [](const Scene& s) {
        for (const std::string& w : s.warnings)
            if (w.find("starts outside") != std::string::npos) return true;
        return false;
    };
    EXPECT_FALSE(outside_warning(r));
    const Scene dark = load_scene(write_obj(room_with_pillar(), "dark_room.obj"));
    EXPECT_TRUE(choose_start_view(dark).inside);
    EXPECT_TRUE(choose_start_view(dark).sealed);
    expect_same_camera(dark.camera, dark.framing_camera());
    EXPECT_TRUE(outside_warning(dark));
    EXPECT_TRUE(dark.default_sky_warning);
    std::ofstream(dir / "dark_room.json") << R"({"obj": "dark_room.obj"})";
    const Scene dj = load_scene((dir / "dark_room.json").string());
    expect_same_camera(dj.camera, dark.framing_camera());
    EXPECT_TRUE(outside_warning(dj));
    // A material override that makes its walls emit lets it start inside again.
    std::ofstream(dir / "dark_room_lit.json")
        << R"({"obj": "dark_room.obj", "materials": {"default": {"emission": [0.1, 0.1, 0.1]}}})";
    const Scene dl = load_scene((dir / "dark_room_lit.json").string());
    expect_same_camera(dl.camera, choose_start_view(dl).camera);
    EXPECT_TRUE(choose_start_view(dl).inside);
    EXPECT_FALSE(outside_warning(dl));
    EXPECT_FALSE(outside_warning(rc));
    EXPECT_FALSE(outside_warning(sp));
    EXPECT_TRUE(sp.default_sky_warning) << "the sphere is lit by the default sky too";
    // A tall court open at the top (an atrium): inside, but the sky reaches the eye directly.
    Scene atrium_src;
    add_box(atrium_src, vec3(0.f), vec3(10.f, 12.f, 4.f), true, test::add_material(atrium_src, Material{}), 3);
    const StartView atrium = choose_start_view(atrium_src);
    EXPECT_TRUE(atrium.inside);
    EXPECT_FALSE(atrium.sealed);
    const Scene ra = load_scene(write_obj(atrium_src, "atrium.obj"));
    EXPECT_TRUE(ra.default_sky_warning);
    EXPECT_FALSE(outside_warning(ra));
    expect_same_camera(ra.camera, atrium.camera);
    fs::remove_all(dir);
}

// pathview render's hint when the scene's own lights leave the view dark (no sky or sun): a floor lit by a lamp of a
// few square centimetres far above gets it, in one line naming the way out; the same scene with --environment 0.5,
// and the built-in Cornell box, do not.
TEST(StartView, RenderHintsAtFillLightWhenTheSceneLightsLeaveTheViewDark) {
    const test::TestDir dir("pathview_dark_hint");
    dir.write("dark.mtl", "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 1 1 1\n");
    const std::string obj = dir.write("dark.obj",
                                      "mtllib dark.mtl\n"
                                      "v -10 0 -10\nv 10 0 -10\nv 10 0 10\nv -10 0 10\n"
                                      "v -0.1 5 -0.1\nv 0.1 5 -0.1\nv 0.1 5 0.1\nv -0.1 5 0.1\n"
                                      "usemtl floor\nf 1 4 3 2\nusemtl lamp\nf 5 6 7 8\n");
    const std::string out = (dir.path / "o.exr").string();
    const std::string flags = " --spp 4 --width 32 --height 24 -o '" + out + "'";
    const test::RunResult dark = test::run_command(PATHVIEW_BINARY, "render '" + obj + "'" + flags);
    ASSERT_EQ(dark.exit_code, 0) << dark.err;
    const size_t at = dark.err.find("pathview: hint: the image is dark (mean displayed luminance ");
    ASSERT_NE(at, std::string::npos) << dark.err;
    EXPECT_NE(dark.err.find("--environment sky adds the default sky, --environment 0.5 a neutral grey fill\n", at),
              std::string::npos)
        << dark.err;
    const test::RunResult filled = test::run_command(PATHVIEW_BINARY, "render '" + obj + "' --environment 0.5" + flags);
    ASSERT_EQ(filled.exit_code, 0) << filled.err;
    EXPECT_EQ(filled.err.find("hint"), std::string::npos) << filled.err;
    const test::RunResult cornell = test::run_command(PATHVIEW_BINARY, "render" + flags);
    ASSERT_EQ(cornell.exit_code, 0) << cornell.err;
    EXPECT_EQ(cornell.err.find("hint"), std::string::npos) << cornell.err;
}

}  // namespace
}  // namespace pv
