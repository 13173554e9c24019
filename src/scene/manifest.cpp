#include "scene/manifest.h"

#include <fmt/format.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "scene/scene_error.h"

namespace trident {
namespace {

Vec3f read_vec3(const nlohmann::json& value, const std::string& where) {
    if (!value.is_array() || value.size() != 3)
        throw SceneError(fmt::format("{}: expected an array of 3 numbers", where));
    Vec3f out;
    for (int i = 0; i < 3; ++i) {
        if (!value[std::size_t(i)].is_number()) throw SceneError(fmt::format("{}: expected an array of 3 numbers", where));
        out[i] = value[std::size_t(i)].get<float>();
    }
    if (!is_finite(out)) throw SceneError(fmt::format("{}: non-finite value", where));
    return out;
}

ManifestEntry read_entry(const nlohmann::json& json, const std::filesystem::path& manifest, std::size_t index) {
    const std::string where = fmt::format("{}: entry {}", manifest.string(), index + 1);
    if (!json.is_object()) throw SceneError(where + ": not an object");
    ManifestEntry entry;
    if (!json.contains("name") || !json["name"].is_string()) throw SceneError(where + ": no \"name\"");
    entry.name = json["name"].get<std::string>();
    const std::string named = fmt::format("{}: scene '{}'", manifest.string(), entry.name);
    if (!json.contains("file") || !json["file"].is_string()) throw SceneError(named + ": no \"file\"");
    entry.file = manifest.parent_path() / json["file"].get<std::string>();
    if (json.contains("triangles") && json["triangles"].is_number_unsigned())
        entry.expected_triangles = json["triangles"].get<std::size_t>();
    if (json.contains("kind") && json["kind"].is_string()) entry.kind = json["kind"].get<std::string>();
    if (!json.contains("camera") || !json["camera"].is_object()) throw SceneError(named + ": no \"camera\"");
    const nlohmann::json& camera = json["camera"];
    for (const char* key : {"eye", "target", "up"})
        if (!camera.contains(key)) throw SceneError(fmt::format("{}: camera has no \"{}\"", named, key));
    entry.camera.eye = read_vec3(camera["eye"], named + ": camera eye");
    entry.camera.target = read_vec3(camera["target"], named + ": camera target");
    entry.camera.up = read_vec3(camera["up"], named + ": camera up");
    if (camera.contains("fov_y_deg")) {
        if (!camera["fov_y_deg"].is_number()) throw SceneError(named + ": camera fov_y_deg is not a number");
        entry.camera.fov_y_deg = camera["fov_y_deg"].get<float>();
    }
    if (!(entry.camera.fov_y_deg > 0.0f && entry.camera.fov_y_deg < 180.0f))
        throw SceneError(named + ": camera fov_y_deg must lie in (0, 180)");
    if (entry.camera.eye == entry.camera.target) throw SceneError(named + ": camera eye equals its target");
    if (camera.contains("resolution")) {
        const auto& r = camera["resolution"];
        if (r.is_array() && r.size() == 2 && r[0].is_number_unsigned() && r[1].is_number_unsigned())
            entry.resolution = std::array<std::uint32_t, 2>{r[0].get<std::uint32_t>(), r[1].get<std::uint32_t>()};
    }
    if (json.contains("light") && json["light"].is_object() && json["light"].contains("position"))
        entry.light = PointLight{read_vec3(json["light"]["position"], named + ": light position")};
    return entry;
}

}  // namespace

std::vector<ManifestEntry> load_manifest(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) throw SceneError(fmt::format("{}: cannot open the manifest", path.string()));
    nlohmann::json json;
    try {
        json = nlohmann::json::parse(in);
    } catch (const nlohmann::json::parse_error& e) {
        throw SceneError(fmt::format("{}: not valid JSON (byte {})", path.string(), e.byte));
    }
    if (!json.is_array()) throw SceneError(fmt::format("{}: expected a JSON array of scenes", path.string()));
    std::vector<ManifestEntry> entries;
    for (std::size_t i = 0; i < json.size(); ++i) entries.push_back(read_entry(json[i], path, i));
    return entries;
}

}  // namespace trident
