#include "scene/obj_loader.h"

#include <fmt/format.h>
#include <tiny_obj_loader.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <string_view>

#include "scene/scene_error.h"

namespace trident {
namespace {

std::string first_line(const std::string& text) {
    std::string line = text.substr(0, text.find('\n'));
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '.')) line.pop_back();
    return line;
}

/// tinyobjloader reads numbers with its own parser, which does not reject "nan", "inf" or values
/// beyond float range; so scan the `v` lines ourselves and report such a value with its line.
void check_vertex_lines(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::size_t line_number = 0;
    for (std::size_t pos = 0; pos < text.size();) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        ++line_number;
        const char* p = text.data() + pos;
        const char* const line_end = text.data() + end;
        pos = end + 1;
        if (line_end - p < 2 || p[0] != 'v' || (p[1] != ' ' && p[1] != '\t')) continue;
        p += 2;
        for (int axis = 0; axis < 3; ++axis) {
            while (p < line_end && (*p == ' ' || *p == '\t')) ++p;
            const char* token_end = p;
            while (token_end < line_end && *token_end != ' ' && *token_end != '\t' && *token_end != '\r') ++token_end;
            const std::string_view token(p, std::size_t(token_end - p));
            double value = 0.0;
            const char* start = token.starts_with('+') ? p + 1 : p;
            const auto [rest, error] = std::from_chars(start, token_end, value);
            if (token.empty() || error != std::errc() || rest != token_end)
                throw SceneError(fmt::format("{}:{}: malformed vertex coordinate '{}'", path.string(), line_number, token));
            if (!std::isfinite(value) || std::abs(value) > double(std::numeric_limits<float>::max()))
                throw SceneError(fmt::format("{}:{}: vertex coordinate '{}' is not a finite single-precision number",
                                             path.string(), line_number, token));
            p = token_end;
        }
    }
}

}  // namespace

void validate_mesh(const Mesh& mesh, const std::string& what) {
    if (mesh.triangle_count() == 0) throw SceneError(fmt::format("{}: the mesh has no triangles", what));
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i)
        if (!is_finite(mesh.vertex(static_cast<std::uint32_t>(i))))
            throw SceneError(fmt::format("{}: vertex {} has a non-finite coordinate", what, i + 1));
    const std::size_t n = mesh.vertex_count();
    for (std::size_t i = 0; i < mesh.triangle_count(); ++i) {
        const IndexTriple& t = mesh.triangles[i];
        if (t.v0 >= n || t.v1 >= n || t.v2 >= n)
            throw SceneIndexError(
                fmt::format("{}: triangle {} references a vertex beyond the {} vertices", what, i + 1, n));
    }
}

Mesh load_obj(const std::filesystem::path& path) {
    const std::string name = path.string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw SceneError(fmt::format("{}: no such file", name));
    if (!std::ifstream(path).good()) throw SceneError(fmt::format("{}: cannot be read", name));
    check_vertex_lines(path);

    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(name, config)) {
        const std::string error = reader.Error().empty() ? "cannot be parsed" : first_line(reader.Error());
        throw SceneError(fmt::format("{}: {}", name, error));
    }
    // A face tinyobjloader skips (too few vertices, invalid index while triangulating) would shift
    // the file-order numbering of every later triangle: refuse the file instead.
    const std::string& warning = reader.Warning();
    for (const char* fatal : {"Degenerated face", "invalid vertex index", "Invalid"})
        if (warning.find(fatal) != std::string::npos)
            throw SceneError(fmt::format("{}: {}", name, first_line(warning.substr(warning.find(fatal)))));

    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    Mesh mesh;
    const std::size_t vertex_count = attrib.vertices.size() / 3;
    mesh.x.resize(vertex_count);
    mesh.y.resize(vertex_count);
    mesh.z.resize(vertex_count);
    for (std::size_t i = 0; i < vertex_count; ++i) {
        mesh.x[i] = attrib.vertices[3 * i];
        mesh.y[i] = attrib.vertices[3 * i + 1];
        mesh.z[i] = attrib.vertices[3 * i + 2];
    }
    bool all_faces_have_normals = !attrib.normals.empty();
    std::size_t face = 0;
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        const auto& indices = shape.mesh.indices;
        for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f, ++face) {
            const tinyobj::index_t* corner = &indices[3 * f];
            for (int k = 0; k < 3; ++k) {
                if (corner[k].vertex_index < 0 || std::size_t(corner[k].vertex_index) >= vertex_count)
                    throw SceneError(fmt::format("{}: face {} references vertex {}, but the file has {} vertices",
                                                 name, face + 1, corner[k].vertex_index + 1, vertex_count));
                if (corner[k].normal_index < 0 || std::size_t(corner[k].normal_index) >= attrib.normals.size() / 3)
                    all_faces_have_normals = false;
            }
            mesh.add_triangle(std::uint32_t(corner[0].vertex_index), std::uint32_t(corner[1].vertex_index),
                              std::uint32_t(corner[2].vertex_index));
            if (all_faces_have_normals)
                mesh.normal_triangles.push_back({std::uint32_t(corner[0].normal_index),
                                                 std::uint32_t(corner[1].normal_index),
                                                 std::uint32_t(corner[2].normal_index)});
        }
    }
    // Normals are used only when every face has them; a partial set is ignored (geometric normals serve).
    if (all_faces_have_normals) {
        const std::size_t normal_count = attrib.normals.size() / 3;
        for (std::size_t i = 0; i < normal_count; ++i) {
            mesh.nx.push_back(attrib.normals[3 * i]);
            mesh.ny.push_back(attrib.normals[3 * i + 1]);
            mesh.nz.push_back(attrib.normals[3 * i + 2]);
        }
    } else {
        mesh.normal_triangles.clear();
    }
    validate_mesh(mesh, name);
    return mesh;
}

}  // namespace trident
