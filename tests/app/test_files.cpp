#include <doctest/doctest.h>

#include <cmath>

#include "render/hit_buffer.h"
#include "render/image.h"
#include "scene/manifest.h"
#include "scene/scene_error.h"
#include "scene/scene_source.h"
#include "support/temp_files.h"

using namespace trident;
using trident::testing::scratch_dir;
using trident::testing::write_file;

TEST_CASE("a PNG round-trips pixel for pixel") {
    Image image(7, 3);
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = {std::uint8_t(i * 11), std::uint8_t(255 - i), std::uint8_t(i * 3)};
    const auto path = scratch_dir() / "round.png";
    write_png(path, image);
    const Image back = read_png(path);
    REQUIRE(back.width == 7);
    REQUIRE(back.height == 3);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        CHECK(back.pixels[i].r == image.pixels[i].r);
        CHECK(back.pixels[i].g == image.pixels[i].g);
        CHECK(back.pixels[i].b == image.pixels[i].b);
    }
}

TEST_CASE("a hit buffer round-trips with the documented layout") {
    std::vector<Hit> hits(6);
    hits[1] = {42, 1.5f, 0.1f, 0.2f};
    hits[4] = {7, 1e-3f, 0.0f, 0.0f};
    const HitBuffer buffer = make_hit_buffer(3, 2, hits);
    CHECK(buffer.triangle[0] == -1);
    CHECK(std::isinf(buffer.t[0]));
    const auto path = scratch_dir() / "hits.bin";
    write_hit_buffer(path, buffer);
    CHECK(std::filesystem::file_size(path) == 16 + 6 * 8);
    const HitBuffer back = read_hit_buffer(path);
    CHECK(back.width == 3);
    CHECK(back.height == 2);
    CHECK(back.triangle == buffer.triangle);
    CHECK(back.t[1] == 1.5f);
    CHECK(back.t[4] == 1e-3f);
    const HitBufferComparison same = compare_hit_buffers(back, buffer);
    CHECK(same.hit_miss_differ == 0);
    CHECK(same.triangle_differ == 0);
    CHECK(same.max_relative_t_difference == 0.0);
}

TEST_CASE("hit buffer comparison counts the three kinds of disagreement") {
    HitBuffer a{2, 2, {-1, 3, 4, 5}, {kInfinity, 1.0f, 2.0f, 4.0f}};
    HitBuffer b{2, 2, {0, 3, 9, 5}, {1.0f, 1.0f, 2.0f, 5.0f}};
    const HitBufferComparison c = compare_hit_buffers(a, b);
    CHECK(c.hit_miss_differ == 1);
    CHECK(c.triangle_differ == 1);
    CHECK(c.max_relative_t_difference == doctest::Approx(0.2));
    CHECK_THROWS_AS(compare_hit_buffers(a, HitBuffer{1, 1, {0}, {1.0f}}), std::invalid_argument);
}

TEST_CASE("a truncated or foreign hit buffer is refused with the file's name") {
    CHECK_THROWS_WITH(read_hit_buffer(write_file("bad.bin", "NOTHITS1xxxxxxxx")),
                      doctest::Contains("bad magic"));
    CHECK_THROWS_WITH(read_hit_buffer(write_file("short.bin", std::string("RTHITS1\0\2\0\0\0\2\0\0\0", 16))),
                      doctest::Contains("truncated"));
}

TEST_CASE("a manifest in the format of BENCHMARK.md is read, and its faults named") {
    write_file("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const auto manifest = write_file("scenes.json", R"([{"name": "tri", "file": "tri.obj", "triangles": 1,
        "camera": {"eye": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 40},
        "light": {"position": [1, 2, 3]}}])");
    const auto entries = load_manifest(manifest);
    REQUIRE(entries.size() == 1);
    CHECK(entries[0].camera.fov_y_deg == 40.0f);
    REQUIRE(entries[0].light);
    CHECK(entries[0].light->position.z == 3.0f);
    const LoadedScene loaded = load_scene("tri", manifest);
    CHECK(loaded.scene.mesh.triangle_count() == 1);
    CHECK(loaded.scene.camera.eye.z == 3.0f);

    CHECK_THROWS_WITH(load_manifest(write_file("nocam.json", R"([{"name": "x", "file": "tri.obj"}])")),
                      doctest::Contains("scene 'x': no \"camera\""));
    CHECK_THROWS_WITH(load_manifest(write_file("broken.json", "[{")), doctest::Contains("not valid JSON"));
    CHECK_THROWS_AS(load_manifest(scratch_dir() / "absent.json"), SceneError);
    CHECK_THROWS_WITH(load_scene("nope", manifest), doctest::Contains("no scene named 'nope'"));
}

TEST_CASE("an OBJ without a camera is framed from its bounds") {
    const auto path = write_file("framed.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n");
    const LoadedScene loaded = load_scene(path.string());
    const CameraSpec& camera = loaded.scene.camera;
    CHECK(camera.target.x == doctest::Approx(0.0f));
    CHECK(length(camera.eye - camera.target) > std::sqrt(5.0f) * 0.5f);
    CHECK_FALSE(loaded.scene.light);
}
