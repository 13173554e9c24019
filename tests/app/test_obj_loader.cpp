#include <doctest/doctest.h>

#include "scene/obj_loader.h"
#include "scene/scene_error.h"
#include "support/temp_files.h"

using namespace trident;
using trident::testing::write_file;

namespace {
std::string load_error(const std::string& name, const std::string& text) {
    try {
        load_obj(write_file(name, text));
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST_CASE("a quad and a triangle load as three triangles in file order") {
    const Mesh mesh = load_obj(write_file("order.obj",
                                          "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 5 5 5\n"
                                          "f 1 2 3 4\n"
                                          "g second\nf 5 1 2\n"));
    REQUIRE(mesh.triangle_count() == 3);
    CHECK(mesh.vertex_count() == 5);
    // The quad comes first (two triangles), then the group's triangle, whatever the groups.
    CHECK(mesh.triangles[2].v0 == 4);
    CHECK(mesh.triangles[2].v1 == 0);
    CHECK(mesh.triangles[2].v2 == 1);
    CHECK_FALSE(mesh.has_normals());
}

TEST_CASE("negative (relative) indices and per-corner normals are read") {
    const Mesh mesh = load_obj(write_file("normals.obj",
                                          "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 -1\n"
                                          "f -3//1 -2//1 -1//2\n"));
    REQUIRE(mesh.triangle_count() == 1);
    CHECK(mesh.triangles[0].v2 == 2);
    REQUIRE(mesh.has_normals());
    CHECK(mesh.normal(mesh.normal_triangles[0].v2).z == -1.0f);
}

TEST_CASE("normals present on only some faces are dropped, not half-used") {
    const Mesh mesh = load_obj(write_file("partial.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 1 2 3\n"));
    CHECK(mesh.triangle_count() == 2);
    CHECK_FALSE(mesh.has_normals());
}

TEST_CASE("bad input gives one line naming the file") {
    SUBCASE("missing file") {
        std::string message;
        try { load_obj("/nonexistent/dir/nothing.obj"); } catch (const SceneError& e) { message = e.what(); }
        CHECK(message == "/nonexistent/dir/nothing.obj: no such file");
    }
    SUBCASE("a face index beyond the vertices") {
        const std::string message = load_error("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
        CHECK(message.find("range.obj") != std::string::npos);
        CHECK(message.find("vertex") != std::string::npos);
    }
    SUBCASE("NaN coordinates, with the line") {
        const std::string message = load_error("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
        CHECK(message.find("nan.obj:2:") != std::string::npos);
    }
    SUBCASE("infinite and out-of-float-range coordinates") {
        CHECK(load_error("inf.obj", "v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n").find("inf.obj:2:") != std::string::npos);
        CHECK(load_error("huge.obj", "v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n").find("huge.obj:2:") != std::string::npos);
    }
    SUBCASE("malformed coordinate") {
        CHECK(load_error("text.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n").find("text.obj:2: malformed") !=
              std::string::npos);
    }
    SUBCASE("no triangles") {
        CHECK(load_error("empty.obj", "# nothing\nv 0 0 0\n").find("no triangles") != std::string::npos);
        CHECK(load_error("blank.obj", "").find("no triangles") != std::string::npos);
    }
    SUBCASE("a face with fewer than three corners") {
        CHECK_FALSE(load_error("short.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\nf 1 2 3\n").empty());
    }
    SUBCASE("a zero face index") {
        CHECK_FALSE(load_error("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n").empty());
    }
}
