// The Python module `trident`: the project's OBJ loader, its three structures (and brute force)
// and the benchmark's camera over numpy arrays, in the shape of Open3D's RaycastingScene and
// trimesh's ray queries. Arrays of float32 (int32 or uint32 for triangles) that are C-contiguous
// are read in place; others are converted. Tracing releases the GIL and runs on oneTBB's threads.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl/filesystem.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "accel/any_accel.h"
#include "camera/camera.h"
#include "ray_batch.h"
#include "result_memory.h"
#include "render/hit_buffer.h"
#include "render/trace.h"
#include "scene/obj_loader.h"
#include "scene/scene_error.h"
#include "scenes/builtin.h"
#include "stress/stress_meshes.h"

namespace py = pybind11;

namespace trident::python {
namespace {

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;
using Shape = std::vector<py::ssize_t>;

/// A path that does not name a file: FileNotFoundError, with the loader's message.
class MissingFile : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

std::string shape_text(const py::array& array) {
    std::string text = "(";
    for (py::ssize_t i = 0; i < array.ndim(); ++i) text += (i ? ", " : "") + std::to_string(array.shape(i));
    return text + (array.ndim() == 1 ? ",)" : ")");
}

/// `object` as a numpy array whose dtype kind is one of `kinds` ("iuf": integers or floats).
py::array numeric_array(py::handle object, const std::string& what, const char* kinds) {
    py::array array = py::array::ensure(object);
    if (!array) throw py::value_error(what + ": expected an array (or a nested sequence of numbers)");
    if (std::string(kinds).find(array.dtype().kind()) == std::string::npos)
        throw py::value_error(fmt::format("{}: dtype {} is not {}", what, std::string(py::str(array.dtype())),
                                          std::string(kinds) == "iu" ? "an integer type" : "numeric"));
    return array;
}

/// float32, C-contiguous: in place when it already is, a converted copy otherwise.
FloatArray float_array(py::handle object, const std::string& what) {
    return FloatArray::ensure(numeric_array(object, what, "iuf"));
}

/// An array of shape (..., last), e.g. (N, 3) points or (H, W, 6) rays.
void check_last_axis(const py::array& array, const std::string& what, py::ssize_t last, bool exactly_2d = false) {
    if (array.ndim() < 1 || array.shape(array.ndim() - 1) != last || (exactly_2d && array.ndim() != 2))
        throw py::value_error(fmt::format("{}: expected shape ({}{}), got {}", what, exactly_2d ? "N, " : "..., ", last,
                                          shape_text(array)));
}

Shape leading_shape(const py::array& array) { return Shape(array.shape(), array.shape() + array.ndim() - 1); }

std::size_t element_count(const Shape& shape) {
    std::size_t n = 1;
    for (const py::ssize_t d : shape) n *= std::size_t(d);
    return n;
}

Vec3f vec3_argument(py::handle object, const std::string& what) {
    const FloatArray array = float_array(object, what);
    if (array.ndim() != 1 || array.shape(0) != 3)
        throw py::value_error(fmt::format("{}: expected 3 numbers, got shape {}", what, shape_text(array)));
    const Vec3f v{array.at(0), array.at(1), array.at(2)};
    if (!is_finite(v)) throw py::value_error(what + ": not finite");
    return v;
}

// ---- Queries' common arguments --------------------------------------------------------------

/// The rays of a query and the arrays they are read from, kept alive while tracing.
struct RayInput {
    FloatArray origins, directions;
    RayArrays arrays;
    Shape shape;  // the results' shape: the rays' shape without its last axis
};

RayInput read_rays(py::handle origins, py::handle directions, double tmin, double tmax) {
    RayInput input;
    if (directions.is_none()) {
        input.origins = float_array(origins, "rays");
        check_last_axis(input.origins, "rays", 6);
        input.arrays.strided = {.origins = input.origins.data(),
                                .origin_stride = 6,
                                .directions = input.origins.data() + 3,
                                .direction_stride = 6};
        input.shape = leading_shape(input.origins);
    } else {
        input.origins = float_array(origins, "origins");
        input.directions = float_array(directions, "directions");
        check_last_axis(input.directions, "directions", 3);
        input.shape = leading_shape(input.directions);
        // One origin for every ray (a camera's eye), or one per ray.
        const bool shared_origin = input.origins.ndim() == 1 && input.origins.shape(0) == 3;
        if (!shared_origin) check_last_axis(input.origins, "origins", 3);
        if (!shared_origin && leading_shape(input.origins) != input.shape)
            throw py::value_error(fmt::format("origins: shape {} matches neither the directions' {} nor (3,)",
                                              shape_text(input.origins), shape_text(input.directions)));
        input.arrays.strided = {.origins = input.origins.data(),
                                .origin_stride = shared_origin ? 0u : 3u,
                                .directions = input.directions.data()};
    }
    if (!(std::isfinite(tmin) && tmin >= 0.0))
        throw py::value_error(fmt::format("tmin {}: must be finite and >= 0", tmin));
    if (std::isnan(tmax)) throw py::value_error("tmax: must not be NaN");
    input.arrays.strided.tmin = float(tmin);
    input.arrays.strided.tmax = float(tmax);
    // Two leading axes are an image (rows, columns) and are traced in the renderer's tiles.
    input.arrays.rows = input.shape.size() == 2 ? std::size_t(input.shape[0]) : 1;
    input.arrays.columns = element_count(input.shape) / std::max<std::size_t>(input.arrays.rows, 1);
    if (input.arrays.rows == 0) input.arrays.columns = 0;
    return input;
}

BatchTraversal read_traversal(const AnyAccel& accel, py::handle simd, int threads) {
    if (threads < 0) throw py::value_error(fmt::format("threads {}: expected 0 (all cores) or more", threads));
    const std::string name = py::str(simd);
    const std::optional<SimdWidth> width = parse_simd_width(name);
    if (!width) throw py::value_error(fmt::format("simd {}: expected {}", name, kSimdWidthChoices));
    if (!has_packet_traversal(accel, *width))
        throw py::value_error(
            fmt::format("simd {}: this CPU, this build or the {} has no such packets", name, to_string(accel.kind())));
    return {*width, threads};
}

/// A read-only numpy array of `shape` over `base`'s memory from `data` on, elements
/// `element_bytes` apart (a field of an array of structs), kept alive by `base`.
py::array strided_view(const py::array& base, const py::dtype& dtype, const Shape& shape, std::size_t element_bytes,
                       const void* data) {
    Shape strides(shape.size());
    py::ssize_t stride = py::ssize_t(element_bytes);
    for (std::size_t i = shape.size(); i-- > 0;) {
        strides[i] = stride;
        stride *= shape[i];
    }
    py::array view(dtype, shape, strides, data, base);
    view.attr("setflags")(py::arg("write") = false);  // Hits::normal() reads the triangles back
    return view;
}

// ---- Results -----------------------------------------------------------------------------------

static_assert(sizeof(Hit) == 16 && offsetof(Hit, triangle) == 0 && offsetof(Hit, t) == 4 && offsetof(Hit, u) == 8 &&
              offsetof(Hit, v) == 12);

/// Closest hits as the traversal wrote them (16-byte Hits in one buffer); t, triangle, u and v
/// are views of its fields, so returning them copies nothing. The normal is made when first read.
class Hits {
public:
    Hits(Shape shape, std::shared_ptr<const Mesh> mesh)
        : shape_(std::move(shape)),
          buffer_(streamed() ? pooled_float_array(element_count(shape_), 4)
                             : py::array_t<float>({py::ssize_t(element_count(shape_)), py::ssize_t(4)})),
          mesh_(std::move(mesh)) {}

    std::span<Hit> hits() { return {reinterpret_cast<Hit*>(buffer_.mutable_data()), element_count(shape_)}; }
    /// Whether the traversal writes the hits with streaming stores: large batches, in pooled memory.
    bool streamed() const { return element_count(shape_) * sizeof(Hit) >= kPooledResultBytes; }

    py::array t() const { return field(py::dtype::of<float>(), offsetof(Hit, t)); }
    py::array triangle() const { return field(py::dtype::of<std::int32_t>(), offsetof(Hit, triangle)); }
    py::array u() const { return field(py::dtype::of<float>(), offsetof(Hit, u)); }
    py::array v() const { return field(py::dtype::of<float>(), offsetof(Hit, v)); }

    /// The unit geometric normal, cross(b - a, c - a) normalized, of each hit triangle; 0 on a miss.
    py::array normal() {
        if (normal_) return *normal_;
        Shape shape = shape_;
        shape.push_back(3);
        py::array_t<float> out(shape);
        float* n = out.mutable_data();
        const std::span<const Hit> all = hits();
        for (std::size_t i = 0; i < all.size(); ++i) {
            Vec3f normal{0.0f, 0.0f, 0.0f};
            if (all[i].is_hit()) normal = normalize(triangle_of(*mesh_, all[i].triangle).geometric_normal());
            n[3 * i] = normal.x, n[3 * i + 1] = normal.y, n[3 * i + 2] = normal.z;
        }
        normal_ = out;
        return out;
    }

    py::array get(const std::string& key) {
        if (key == "t") return t();
        if (key == "triangle") return triangle();
        if (key == "u") return u();
        if (key == "v") return v();
        if (key == "normal") return normal();
        throw py::key_error(key);
    }

    std::size_t size() const { return element_count(shape_); }

private:
    py::array field(const py::dtype& dtype, std::size_t offset) const {
        return strided_view(buffer_, dtype, shape_, sizeof(Hit), buffer_.data() + offset / sizeof(float));
    }

    Shape shape_;
    py::array_t<float> buffer_;  // Hit i at floats 4i..4i+3
    std::shared_ptr<const Mesh> mesh_;
    std::optional<py::array> normal_;
};

// ---- Building ------------------------------------------------------------------------------------

/// A structure's build option as a keyword: its name and how a Python value is stored.
template <class Options>
struct Keyword {
    const char* name;
    std::function<void(Options&, py::handle)> store;
};

template <class Options, class T>
Keyword<Options> keyword(const char* name, T Options::*member) {
    return {name, [member](Options& options, py::handle value) { options.*member = value.cast<T>(); }};
}

template <class Options, class Enum>
Keyword<Options> choice(const char* name, Enum Options::*member, std::vector<std::pair<std::string, Enum>> names) {
    return {
        name, [name, member, names](Options& options, py::handle value) {
            std::string known;
            for (const auto& [text, choice] : names) {
                if (py::str(value).cast<std::string>() == text) return void(options.*member = choice);
                known += (known.empty() ? "" : ", ") + text;
            }
            throw py::value_error(fmt::format("{}={}: expected one of {}", name, std::string(py::str(value)), known));
        }};
}

std::vector<Keyword<BvhOptions>> bvh_keywords() {
    std::vector<std::pair<std::string, BvhBuilder>> builders;
    for (const BvhBuilderName& known : kBvhBuilderNames) builders.emplace_back(known.name, known.builder);
    return {
        choice("builder", &BvhOptions::builder, std::move(builders)),
        keyword("bin_count", &BvhOptions::bin_count),
        keyword("large_node_bin_count", &BvhOptions::large_node_bin_count),
        keyword("all_axes", &BvhOptions::all_axes),
        keyword("traversal_cost", &BvhOptions::traversal_cost),
        keyword("intersection_cost", &BvhOptions::intersection_cost),
        keyword("max_leaf_size", &BvhOptions::max_leaf_size),
        keyword("spatial_split_budget", &BvhOptions::spatial_split_budget),
        keyword("width", &BvhOptions::width)};
}

std::vector<Keyword<KdTreeOptions>> kdtree_keywords() {
    return {keyword("intersection_cost", &KdTreeOptions::intersection_cost),
            keyword("traversal_cost", &KdTreeOptions::traversal_cost),
            keyword("empty_bonus", &KdTreeOptions::empty_bonus),
            keyword("max_depth", &KdTreeOptions::max_depth),
            keyword("depth_offset", &KdTreeOptions::depth_offset),
            keyword("max_bad_refines", &KdTreeOptions::max_bad_refines),
            keyword("leaf_triangles", &KdTreeOptions::leaf_triangles),
            keyword("perfect_splits", &KdTreeOptions::perfect_splits)};
}

std::vector<Keyword<OctreeOptions>> octree_keywords() {
    return {keyword("max_depth", &OctreeOptions::max_depth), keyword("min_primitives", &OctreeOptions::min_primitives),
            choice("overlap", &OctreeOptions::overlap,
                   {{"triangle", OctreeOverlap::triangle}, {"box", OctreeOverlap::bounding_box}}),
            keyword("max_references", &OctreeOptions::max_references)};
}

/// Stores each keyword in `options`; a name the structure does not take is a TypeError, as for any
/// Python function, and a value of the wrong type names the option.
template <class Options>
void store_keywords(const py::kwargs& given, const std::vector<Keyword<Options>>& keywords, Options& options,
                    const std::string& accel) {
    for (const auto& [key, value] : given) {
        const std::string name = py::str(key);
        const auto found =
            std::find_if(keywords.begin(), keywords.end(), [&](const auto& k) { return name == k.name; });
        if (found == keywords.end()) {
            std::string known;
            for (const auto& k : keywords) known += (known.empty() ? "" : ", ") + std::string(k.name);
            throw py::type_error(fmt::format("Scene(accel=\"{}\"): unknown option {} (options: {})", accel, name,
                                             known.empty() ? "none" : known));
        }
        try {
            found->store(options, value);
        } catch (const py::cast_error&) {
            throw py::type_error(fmt::format("{}={}: wrong type", name, std::string(py::repr(value))));
        }
    }
}

AccelOptions read_accel_options(AccelKind kind, const py::kwargs& given) {
    AccelOptions options;
    switch (kind) {
        case AccelKind::brute:
            store_keywords<BvhOptions>(given, {}, options.bvh, "brute");
            break;
        case AccelKind::bvh:
        case AccelKind::bvh2:
            store_keywords(given, bvh_keywords(), options.bvh, to_string(kind));
            break;
        case AccelKind::kdtree:
            store_keywords(given, kdtree_keywords(), options.kdtree, "kdtree");
            break;
        case AccelKind::octree:
            store_keywords(given, octree_keywords(), options.octree, "octree");
            break;
    }
    return options;
}

/// vertices (V, 3) and triangles (T, 3) as the project's mesh, checked as loaded meshes are.
Mesh read_mesh(py::handle vertices_object, py::handle triangles_object) {
    const FloatArray vertices = float_array(vertices_object, "vertices");
    check_last_axis(vertices, "vertices", 3, true);
    Mesh mesh;
    const float* v = vertices.data();
    for (py::ssize_t i = 0; i < vertices.shape(0); ++i) mesh.add_vertex({v[3 * i], v[3 * i + 1], v[3 * i + 2]});

    const py::array triangles = numeric_array(triangles_object, "triangles", "iu");
    check_last_axis(triangles, "triangles", 3, true);
    const bool in_place = (py::isinstance<py::array_t<std::int32_t>>(triangles) ||
                           py::isinstance<py::array_t<std::uint32_t>>(triangles)) &&
                          (triangles.flags() & py::array::c_style);
    if (in_place) {
        // int32 read as uint32: a negative index becomes one beyond any vertex and is reported so.
        const auto* t = static_cast<const std::uint32_t*>(triangles.data());
        for (py::ssize_t i = 0; i < triangles.shape(0); ++i) mesh.add_triangle(t[3 * i], t[3 * i + 1], t[3 * i + 2]);
    } else {
        const auto wide = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(triangles);
        const std::int64_t* t = wide.data();
        constexpr std::uint32_t kBeyondAnyVertex = std::numeric_limits<std::uint32_t>::max();
        auto index = [](std::int64_t i) {
            return i < 0 || i > std::int64_t(kBeyondAnyVertex) ? kBeyondAnyVertex : std::uint32_t(i);
        };
        for (py::ssize_t i = 0; i < wide.shape(0); ++i)
            mesh.add_triangle(index(t[3 * i]), index(t[3 * i + 1]), index(t[3 * i + 2]));
    }
    validate_mesh(mesh, "Scene");
    return mesh;
}

class Scene {
public:
    Scene(py::handle vertices, py::handle triangles, const std::string& accel, const py::kwargs& options)
        : mesh_(std::make_shared<const Mesh>(read_mesh(vertices, triangles))), accel_(build(accel, options)) {}

    py::object intersect(py::handle origins, py::handle directions, double tmin, double tmax, int threads,
                         py::handle simd) const {
        const RayInput input = read_rays(origins, directions, tmin, tmax);
        Hits hits(input.shape, mesh_);
        BatchTraversal traversal = read_traversal(*accel_, simd, threads);
        traversal.stream_results = hits.streamed();
        {
            py::gil_scoped_release release;
            intersect_batch(*accel_, input.arrays, hits.hits(), traversal);
        }
        return py::cast(std::move(hits));
    }

    py::array occluded(py::handle origins, py::handle directions, double tmin, double tmax, int threads,
                       py::handle simd) const {
        const RayInput input = read_rays(origins, directions, tmin, tmax);
        const BatchTraversal traversal = read_traversal(*accel_, simd, threads);
        py::array_t<bool> out(input.shape);
        {
            py::gil_scoped_release release;
            occluded_batch(*accel_, input.arrays, bytes_of(out), traversal);
        }
        return out;
    }

    py::array count_hits(py::handle origins, py::handle directions, double tmin, double tmax, int threads,
                         py::handle simd) const {
        const RayInput input = read_rays(origins, directions, tmin, tmax);
        const BatchTraversal traversal = read_traversal(*accel_, simd, threads);
        py::array_t<std::int32_t> out(input.shape);
        {
            py::gil_scoped_release release;
            count_hits_batch(*accel_, input.arrays, {out.mutable_data(), std::size_t(out.size())}, traversal);
        }
        return out;
    }

    py::array contains(py::handle points_object, int threads, py::handle simd) const {
        const FloatArray points = float_array(points_object, "points");
        check_last_axis(points, "points", 3);
        for (py::ssize_t i = 0; i < points.size(); ++i)
            if (!std::isfinite(points.data()[i]))
                throw py::value_error(fmt::format("points: point {} is not finite", i / 3));
        const BatchTraversal traversal = read_traversal(*accel_, simd, threads);
        py::array_t<bool> out(leading_shape(points));
        {
            py::gil_scoped_release release;
            contains_batch(*accel_, points.data(), std::size_t(out.size()), bytes_of(out), traversal);
        }
        return out;
    }

    py::dict stats() const {
        const AccelStats& s = accel_->stats();
        py::dict out;
        out["structure"] = s.structure;
        out["triangles"] = s.triangles;
        out["build_ms"] = s.build_ms;
        out["nodes"] = s.nodes;
        out["leaves"] = s.leaves;
        out["empty_leaves"] = s.empty_leaves;
        out["depth"] = s.max_depth;
        out["references"] = s.references;
        out["max_leaf_size"] = s.max_leaf_size;
        out["mean_leaf_size"] = s.mean_leaf_size;
        out["sah"] = s.sah_cost;
        out["bytes"] = s.bytes;
        out["bytes_per_triangle"] = s.bytes_per_triangle();
        if (!s.builder.empty()) out["builder"] = s.builder;
        return out;
    }

    std::string accel() const { return to_string(accel_->kind()); }
    std::string repr() const { return "<trident.Scene " + accel_->stats().to_line() + ">"; }

private:
    static std::span<std::uint8_t> bytes_of(py::array_t<bool>& out) {
        static_assert(sizeof(bool) == 1);
        return {reinterpret_cast<std::uint8_t*>(out.mutable_data()), std::size_t(out.size())};
    }

    std::shared_ptr<const AnyAccel> build(const std::string& name, const py::kwargs& options) const {
        const std::optional<AccelKind> kind = parse_accel_kind(name);
        if (!kind) throw py::value_error(fmt::format("accel {}: unknown structure (brute, bvh, kdtree, octree)", name));
        const AccelOptions accel_options = read_accel_options(*kind, options);
        std::shared_ptr<const AnyAccel> accel;
        std::string warning;
        {
            py::gil_scoped_release release;
            accel = std::make_shared<const AnyAccel>(AnyAccel::build(*kind, *mesh_, accel_options));
            accel->visit([&](const auto& structure) {
                if constexpr (requires { structure.warning(); }) warning = structure.warning();
            });
        }
        // What a builder had to give up (the octree's reference guard), so nobody takes a truncated
        // tree for the real thing.
        if (!warning.empty() && PyErr_WarnEx(PyExc_RuntimeWarning, warning.c_str(), 1) < 0)
            throw py::error_already_set();
        return accel;
    }

    std::shared_ptr<const Mesh> mesh_;
    std::shared_ptr<const AnyAccel> accel_;
};

/// The mesh as numpy arrays: (vertices (V, 3) float32, triangles (T, 3) int32).
py::tuple mesh_arrays(const Mesh& mesh) {
    py::array_t<float> vertices({py::ssize_t(mesh.vertex_count()), py::ssize_t(3)});
    float* v = vertices.mutable_data();
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i)
        v[3 * i] = mesh.x[i], v[3 * i + 1] = mesh.y[i], v[3 * i + 2] = mesh.z[i];
    py::array_t<std::int32_t> triangles({py::ssize_t(mesh.triangle_count()), py::ssize_t(3)});
    std::int32_t* t = triangles.mutable_data();
    for (std::size_t i = 0; i < mesh.triangle_count(); ++i) {
        t[3 * i] = std::int32_t(mesh.triangles[i].v0);
        t[3 * i + 1] = std::int32_t(mesh.triangles[i].v1);
        t[3 * i + 2] = std::int32_t(mesh.triangles[i].v2);
    }
    return py::make_tuple(vertices, triangles);
}

/// read(path) without the GIL; its error becomes a FileNotFoundError when the file does not exist.
template <class Read>
auto read_file(const std::filesystem::path& path, Read&& read) {
    try {
        py::gil_scoped_release release;
        return read(path);
    } catch (const std::runtime_error& e) {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) throw MissingFile(e.what());
        throw;
    }
}

py::tuple load_obj(const std::filesystem::path& path) {
    return mesh_arrays(read_file(path, [](const auto& p) { return trident::load_obj(p); }));
}

py::tuple hit_buffer_arrays(const std::filesystem::path& path) {
    const HitBuffer buffer = read_file(path, [](const auto& p) { return read_hit_buffer(p); });
    const Shape shape{py::ssize_t(buffer.height), py::ssize_t(buffer.width)};
    py::array_t<std::int32_t> triangle(shape);
    py::array_t<float> t(shape);
    std::copy(buffer.triangle.begin(), buffer.triangle.end(), triangle.mutable_data());
    std::copy(buffer.t.begin(), buffer.t.end(), t.mutable_data());
    return py::make_tuple(triangle, t);
}

py::tuple vec3_tuple(const Vec3f& v) { return py::make_tuple(v.x, v.y, v.z); }

py::dict builtin_scene(const std::string& name) {
    const trident::Scene scene = make_builtin_scene(name);
    const py::tuple arrays = mesh_arrays(scene.mesh);
    py::dict out;
    out["vertices"] = arrays[0];
    out["triangles"] = arrays[1];
    out["camera"] =
        py::dict(py::arg("eye") = vec3_tuple(scene.camera.eye), py::arg("target") = vec3_tuple(scene.camera.target),
                 py::arg("up") = vec3_tuple(scene.camera.up), py::arg("fov_y_deg") = scene.camera.fov_y_deg);
    out["light"] = scene.light ? py::object(vec3_tuple(scene.light->position)) : py::none();
    return out;
}

py::tuple closed_mesh(const std::string& name) {
    // The stress suite's sizes (src/stress/stress_cases.cpp).
    const std::optional<ClosedMesh> closed = name == "sphere"     ? jittered_sphere(10, 0.1f, 3)
                                             : name == "cube"     ? tessellated_cube(8)
                                             : name == "teapot"   ? closed_teapot(24)
                                             : name == "asteroid" ? closed_asteroid(16, 5)
                                                                  : std::optional<ClosedMesh>();
    if (!closed) throw py::value_error("closed_mesh " + name + ": expected sphere, cube, teapot or asteroid");
    const py::tuple arrays = mesh_arrays(closed->mesh);
    return py::make_tuple(arrays[0], arrays[1], vec3_tuple(closed->interior_centre), closed->interior_radius);
}

constexpr std::uint32_t kMaxImageSide = 16384;  // as the trident CLI's --width and --height

py::array camera_rays(py::handle eye_object, py::handle target_object, py::handle up_object, double fov_y_deg,
                      std::int64_t width, std::int64_t height) {
    CameraSpec spec{vec3_argument(eye_object, "eye"), vec3_argument(target_object, "target"),
                    vec3_argument(up_object, "up"), float(fov_y_deg)};
    if (!(spec.fov_y_deg > 0.0f && spec.fov_y_deg < 180.0f))
        throw py::value_error(fmt::format("fov_y_deg {}: must lie in (0, 180)", fov_y_deg));
    if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide)
        throw py::value_error(fmt::format("width/height {}x{}: each must lie in 1..{}", width, height, kMaxImageSide));
    if (spec.eye == spec.target) throw py::value_error("camera_rays: eye equals target");
    if (!(dot(cross(spec.target - spec.eye, spec.up), cross(spec.target - spec.eye, spec.up)) > 0.0f))
        throw py::value_error("camera_rays: up is zero or parallel to the view direction");
    const Camera camera(spec, std::uint32_t(width), std::uint32_t(height));
    py::array_t<float> rays({py::ssize_t(height), py::ssize_t(width), py::ssize_t(6)});
    float* out = rays.mutable_data();
    {
        py::gil_scoped_release release;
        tbb::parallel_for(std::uint32_t(0), std::uint32_t(height), [&](std::uint32_t y) {
            for (std::uint32_t x = 0; x < camera.width(); ++x) {
                const Ray ray = camera.primary_ray(x, y);
                float* r = out + 6 * (std::size_t(y) * camera.width() + x);
                r[0] = ray.origin.x, r[1] = ray.origin.y, r[2] = ray.origin.z;
                r[3] = ray.dir.x, r[4] = ray.dir.y, r[5] = ray.dir.z;
            }
        });
    }
    return rays;
}

constexpr const char* kRaysDoc = R"(
    Rays are either `rays` of shape (..., 6), origin then direction, or `origins` (..., 3) (or
    (3,), one origin for all) with `directions` (..., 3). Directions need not be normalized: t is
    measured in units of the direction's length. Rays of shape (H, W, 6), e.g. camera_rays(),
    are traced in the renderer's 16x16 tiles with its packet blocks. Results have the rays' shape
    without the last axis. `threads` (0: all cores) bounds the threads, `simd` is the packet
    width: "auto" (the widest this CPU runs), "scalar", 4, 8 or 16. A non-finite origin or
    direction, or a zero direction, is a ValueError.)";

}  // namespace
}  // namespace trident::python

PYBIND11_MODULE(trident, m) {
    using namespace trident::python;
    namespace t = trident;
    m.doc() = "trident: ray casting over numpy with a BVH, a KD-tree, an octree or brute force.";

    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const MissingFile& e) {
            PyErr_SetString(PyExc_FileNotFoundError, e.what());
        } catch (const t::SceneIndexError& e) {
            PyErr_SetString(PyExc_IndexError, e.what());
        } catch (const t::SceneError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        }
    });

    m.def("load_obj", &load_obj, py::arg("path"),
          R"(Reads an OBJ file with trident's loader: (vertices (V, 3) float32, triangles (T, 3) int32).

Polygons are triangulated (a quad along its shorter diagonal, larger ones as a fan) and triangles
keep file order, the numbering of intersect()'s `triangle`. A missing file is a FileNotFoundError;
a malformed one (bad numbers, out-of-range face indices, non-finite coordinates, no triangles) a
ValueError naming the file and line.)");

    m.def(
        "simd_widths",
        [] {
            py::list widths;
            for (const t::SimdWidth width : t::kSimdWidths)
                if (t::is_runnable(width)) widths.append(t::to_string(width));
            return widths;
        },
        "The packet widths this build and CPU run, for the queries' simd= (\"scalar\" always).");

    m.def("builtin_scene", &builtin_scene, py::arg("name"),
          R"(One of trident's built-in procedural scenes (teapot, asteroid, hall, city), as the benchmark
uses it: a dict of vertices, triangles, camera (eye, target, up, fov_y_deg) and light.)");

    m.def("closed_mesh", &closed_mesh, py::arg("name"),
          R"(One of the stress suite's closed meshes: sphere (jittered geodesic), cube (tessellated),
teapot (closed) or asteroid, as (vertices, triangles, interior_centre, interior_radius): every
point within interior_radius of interior_centre lies inside.)");

    m.def("read_hit_buffer", &hit_buffer_arrays, py::arg("path"),
          R"(BENCHMARK.md's hit buffer (trident render --dump-hits, trident-bench --dump-hits) as
(triangle (H, W) int32, -1 on a miss; t (H, W) float32, inf on a miss).)");

    m.def("camera_rays", &camera_rays, py::arg("eye"), py::arg("target"), py::arg("up"), py::arg("fov_y_deg"),
          py::arg("width"), py::arg("height"),
          R"(The primary rays of BENCHMARK.md's pinhole camera, (height, width, 6) float32.

Pixel (x, y), y = 0 the top row, is rays[y, x]: origin the eye, direction normalized, computed in
single precision exactly as the benchmark and trident's renderer compute them.)");

    py::class_<Hits>(m, "Hits", "Closest hits of a batch of rays (Scene.intersect).")
        .def_property_readonly("t", &Hits::t, "hit distance along the direction, inf on a miss (float32)")
        .def_property_readonly("triangle", &Hits::triangle, "triangle index in the mesh's order, -1 on a miss (int32)")
        .def_property_readonly("u", &Hits::u, "barycentric weight of the triangle's second vertex (float32)")
        .def_property_readonly("v", &Hits::v, "barycentric weight of the triangle's third vertex (float32)")
        .def_property_readonly("normal", &Hits::normal,
                               "unit geometric normal cross(b - a, c - a) / |...| of the hit triangle, 0 on a miss "
                               "(shape (..., 3), made when first read)")
        .def("__getitem__", &Hits::get, py::arg("key"), "hits['t'] and so on, as Open3D's result dictionary")
        .def("keys", [](const Hits&) { return py::make_tuple("t", "triangle", "u", "v", "normal"); })
        .def("__len__", &Hits::size);

    const std::string rays_doc = kRaysDoc;
    py::class_<Scene>(m, "Scene")
        .def(py::init<py::handle, py::handle, const std::string&, const py::kwargs&>(), py::arg("vertices"),
             py::arg("triangles"), py::arg("accel") = "bvh",
             R"(Builds an acceleration structure over a triangle mesh.

vertices (V, 3) and triangles (T, 3) of vertex indices; accel is "bvh" (the wide BVH), "bvh2"
(the binary one), "kdtree", "octree" or "brute". Keywords set the structure's build options:
  bvh:    width (children per node: 2, 4, 8 or 16; default 16 where AVX2 runs, else 8),
          builder ("auto", the default: "spatial" where the mesh has large triangles and spatial splits
          lower the SAH, "binned" elsewhere, bvh2 always "binned"; or "binned", "sweep", "spatial"),
          bin_count, large_node_bin_count, all_axes, traversal_cost, intersection_cost, max_leaf_size,
          spatial_split_budget (bvh2 takes the same)
  kdtree: intersection_cost, traversal_cost, empty_bonus, max_depth, depth_offset,
          max_bad_refines, leaf_triangles, perfect_splits
  octree: max_depth, min_primitives, overlap ("triangle" or "box"), max_references
A wrong shape or dtype, a non-finite coordinate, a mesh without triangles or an option out of
range is a ValueError, an index beyond the vertices an IndexError, an unknown option a TypeError.)")
        .def(
            "intersect", &Scene::intersect, py::arg("origins"), py::arg("directions") = py::none(),
            py::arg("tmin") = 0.0, py::arg("tmax") = std::numeric_limits<double>::infinity(), py::arg("threads") = 0,
            py::arg("simd") = "auto",
            ("Closest hit of each ray in [tmin, tmax]: a Hits with t, triangle, u, v and normal.\n"
             "Hits of 4 MiB or more (262144 rays) use memory kept for the next batch of that size once\n"
             "they and their views are gone (at most two buffers).\n" +
             rays_doc)
                .c_str())
        .def("occluded", &Scene::occluded, py::arg("origins"), py::arg("directions") = py::none(),
             py::arg("tmin") = 0.0, py::arg("tmax") = std::numeric_limits<double>::infinity(), py::arg("threads") = 0,
             py::arg("simd") = "auto", ("Whether each ray hits anything in [tmin, tmax] (bool).\n" + rays_doc).c_str())
        .def("count_hits", &Scene::count_hits, py::arg("origins"), py::arg("directions") = py::none(),
             py::arg("tmin") = 0.0, py::arg("tmax") = std::numeric_limits<double>::infinity(), py::arg("threads") = 0,
             py::arg("simd") = "auto",
             ("Surfaces each ray crosses in [tmin, tmax] (int32); hits at one distance, as through an edge,\n"
              "count once.\n" +
              rays_doc)
                 .c_str())
        .def("contains", &Scene::contains, py::arg("points"), py::arg("threads") = 0, py::arg("simd") = "auto",
             R"(Whether each point of (..., 3) lies inside the mesh, which must be closed (bool).

Odd crossings along a fixed direction; where two directions disagree, a third decides.)")
        .def_property_readonly("stats", &Scene::stats,
                               "the structure's statistics: build_ms, nodes, leaves, depth, sah, bytes, "
                               "bytes_per_triangle and more; the BVHs' builder (\"auto\" resolved)")
        .def_property_readonly("accel", &Scene::accel, "the structure's name")
        .def("__repr__", &Scene::repr);
}
