#include "stress/stress_cases.h"

#include <fmt/format.h>

#include <cmath>
#include <functional>
#include <stdexcept>

#include "accel/kdtree/kdtree.h"
#include "accel/octree/octree_build.h"
#include "core/ray_offset.h"
#include "scenes/hash_random.h"
#include "stress/stress_meshes.h"

namespace trident {
namespace {

using CaseMaker = std::function<StressCase(std::size_t ray_count, HashRandom& random)>;

struct CaseEntry {
    StressCaseInfo info;
    CaseMaker make;
};

Vec3f random_in_ball(HashRandom& random, const Vec3f& centre, float radius) {
    for (;;) {
        const Vec3f p{random.uniform(-1.0f, 1.0f), random.uniform(-1.0f, 1.0f), random.uniform(-1.0f, 1.0f)};
        if (dot(p, p) <= 1.0f) return centre + p * radius;
    }
}

Vec3f random_direction(HashRandom& random) {
    for (;;) {
        const Vec3f p{random.uniform(-1.0f, 1.0f), random.uniform(-1.0f, 1.0f), random.uniform(-1.0f, 1.0f)};
        const float len2 = dot(p, p);
        if (len2 > 1e-4f && len2 <= 1.0f) return p / std::sqrt(len2);
    }
}

/// A point on triangle i, uniform over it.
Vec3f random_point_on(const Triangle& tri, HashRandom& random) {
    float u = random.uniform(), v = random.uniform();
    if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
    return tri.a + (tri.b - tri.a) * u + (tri.c - tri.a) * v;
}

/// Rays from the interior ball aimed at random surface points, at vertices and at points of the
/// edges (shared by two triangles in a closed mesh), in equal shares; every one must hit.
StressCase aimed_from_inside(std::string name, const ClosedMesh& closed, std::size_t ray_count, HashRandom& random) {
    StressCase c{std::move(name), closed.mesh, {}, {}, {}};
    const Mesh& mesh = closed.mesh;
    const auto triangle_count = std::uint32_t(mesh.triangle_count());
    for (std::size_t i = 0; i < ray_count; ++i) {
        const Vec3f origin = random_in_ball(random, closed.interior_centre, closed.interior_radius);
        const std::uint32_t id = random.below(triangle_count);
        const IndexTriple& corners = mesh.triangles[id];
        Vec3f target;
        switch (i % 3) {
            case 0: target = random_point_on(triangle_of(mesh, id), random); break;
            case 1: target = mesh.vertex(random.below(2) ? corners.v0 : corners.v1); break;
            default: {
                const float s = i % 2 ? 0.5f : random.uniform();
                target = mesh.vertex(corners.v0) + (mesh.vertex(corners.v1) - mesh.vertex(corners.v0)) * s;
            }
        }
        const Vec3f dir = target - origin;
        c.add_ray({origin, dot(dir, dir) > 0.0f ? dir : Vec3f(1.0f, 0.0f, 0.0f)}, true);
    }
    return c;
}

/// Axis-parallel rays with +0 and -0 in the other components, from interior points on the
/// lattice of the cube's tessellation (so they run along the planes and lines where its triangles
/// meet) and from random interior points; every one must hit.
StressCase axis_parallel(std::size_t ray_count, HashRandom& random) {
    constexpr std::uint32_t kCells = 8;
    const ClosedMesh cube = tessellated_cube(kCells);
    StressCase c{"axis_parallel", cube.mesh, {}, {}, {}};
    for (std::size_t i = 0; i < ray_count; ++i) {
        Vec3f origin = random_in_ball(random, Vec3f(0.0f), 0.9f);
        if (i % 2 == 0)  // snap to lattice planes: -1 + 2 k / kCells, k = 1..kCells-1
            for (int axis = 0; axis < 3; ++axis)
                if (random.below(2)) origin[axis] = -1.0f + 2.0f * float(1 + random.below(kCells - 1)) / float(kCells);
        const int axis = int(random.below(3));
        Vec3f dir(random.below(2) ? 0.0f : -0.0f, random.below(2) ? 0.0f : -0.0f, random.below(2) ? 0.0f : -0.0f);
        dir[axis] = random.below(2) ? 1.0f : -1.0f;
        c.add_ray({origin, dir}, true);
    }
    return c;
}

/// Rays lying in the kd-tree's split planes (direction component +-0 across the plane, origin
/// on it) from inside the jittered sphere; every one must hit.
StressCase split_planes(std::size_t ray_count, HashRandom& random) {
    const ClosedMesh sphere = jittered_sphere(12, 0.1f, 7);
    StressCase c{"split_planes", sphere.mesh, {}, {}, {}};
    const KdTree tree = KdTree::build(sphere.mesh);
    std::vector<std::pair<int, float>> planes;
    for (const KdNode& node : tree.nodes())
        if (!node.is_leaf() && std::abs(node.split()) < 0.45f) planes.emplace_back(node.axis(), node.split());
    if (planes.empty()) throw std::logic_error("split_planes: the kd-tree has no split inside the sphere");
    for (std::size_t i = 0; i < ray_count; ++i) {
        const auto& [axis, split] = planes[random.below(std::uint32_t(planes.size()))];
        Vec3f origin = random_in_ball(random, Vec3f(0.0f), 0.45f);
        origin[axis] = split;
        Vec3f dir = random_direction(random);
        dir[axis] = random.below(2) ? 0.0f : -0.0f;
        c.add_ray({origin, dot(dir, dir) > 0.0f ? dir : Vec3f(1.0f, 0.0f, 0.0f)}, true);
    }
    return c;
}

/// Rays through the centres of octree cells (levels 1 to 6 of the root cube the octree builds)
/// and lying in cell boundary planes, from inside the jittered sphere; every one must hit.
StressCase octree_centres(std::size_t ray_count, HashRandom& random) {
    const ClosedMesh sphere = jittered_sphere(12, 0.1f, 11);
    StressCase c{"octree_centres", sphere.mesh, {}, {}, {}};
    const OctreeCube cube = octree_root_cube(gather_triangles(sphere.mesh));
    auto lattice_point = [&](int level, bool centre) {  // a cell centre or a cell corner at `level`
        const float cells = float(1u << level);
        Vec3f p;
        for (int axis = 0; axis < 3; ++axis) {
            const float k = float(random.below(1u << level)) + (centre ? 0.5f : 0.0f);
            p[axis] = cube.lo[axis] + cube.size * (k / cells);
        }
        return p;
    };
    while (c.rays.size() < ray_count) {
        const int level = 1 + int(random.below(6));
        const Vec3f a = lattice_point(level, true);
        if (length(a) > 0.45f) continue;
        Ray ray{a, random_direction(random)};
        switch (c.rays.size() % 3) {
            case 0: break;  // from a cell centre in a random direction
            case 1: {       // from a cell centre through another
                const Vec3f b = lattice_point(level, true);
                if (b == a) continue;
                ray.dir = b - a;
                break;
            }
            default: {  // from a cell corner, lying in one of its boundary planes
                ray.origin = lattice_point(level, false);
                if (length(ray.origin) > 0.45f) continue;
                ray.dir[int(random.below(3))] = random.below(2) ? 0.0f : -0.0f;
                if (!(dot(ray.dir, ray.dir) > 0.0f)) continue;
            }
        }
        c.add_ray(ray, true);
    }
    return c;
}

/// Rays grazing the jittered sphere (tangent at a surface point, nudged by up to 1e-5 in or out)
/// and rays lying in, or a few ulps beside, the cube's face planes; checked against the reference.
StressCase grazing(std::size_t ray_count, HashRandom& random) {
    const ClosedMesh sphere = jittered_sphere(10, 0.05f, 13);
    const ClosedMesh cube = placed(tessellated_cube(4), 1.0f, Vec3f(4.0f, 0.0f, 0.0f));
    StressCase c{"grazing", sphere.mesh, {}, {}, {}};
    c.mesh.append(cube.mesh);
    const auto sphere_triangles = std::uint32_t(sphere.mesh.triangle_count());
    for (std::size_t i = 0; i < ray_count; ++i) {
        if (i % 2 == 0) {
            const Triangle tri = triangle_of(sphere.mesh, random.below(sphere_triangles));
            const Vec3f p = random_point_on(tri, random);
            const Vec3f n = normalize(tri.geometric_normal());
            Vec3f tangent = cross(n, random_direction(random));
            if (!(dot(tangent, tangent) > 1e-6f)) tangent = cross(n, Vec3f(0.0f, 0.0f, 1.0f));
            tangent = normalize(tangent) + n * random.uniform(-1e-5f, 1e-5f);
            c.add_ray({p - tangent * 3.0f, tangent}, false);
        } else {  // along a face plane of the cube (x = 3 or 5, y or z = +-1), from outside it
            const int axis = 1 + int(random.below(2));
            Vec3f origin(3.0f + random.uniform(0.0f, 2.0f), random.uniform(-1.0f, 1.0f), random.uniform(-1.0f, 1.0f));
            float plane = random.below(2) ? 1.0f : -1.0f;
            const int nudge = int(random.below(5)) - 2;  // ulps off the plane; 0: exactly in it
            for (int k = 0; k < std::abs(nudge); ++k) plane = std::nextafter(plane, nudge > 0 ? 2.0f : -2.0f);
            origin[axis] = plane;
            const int along = axis == 1 ? 2 : 1;
            origin[along] = random.below(2) ? -3.0f : 3.0f;
            Vec3f dir(random.uniform(-0.2f, 0.2f), 0.0f, 0.0f);
            dir[along] = origin[along] > 0.0f ? -1.0f : 1.0f;
            c.add_ray({origin, dir}, false);
        }
    }
    return c;
}

/// Rays starting on a triangle of the closed teapot, moved off it with offset_ray_origin: into
/// the solid (must hit, and never the start triangle) or out of it (never the start triangle).
StressCase surface_origins(std::size_t ray_count, HashRandom& random) {
    const ClosedMesh teapot = closed_teapot(24);
    StressCase c{"surface_origins", teapot.mesh, {}, {}, {}};
    const auto triangles = std::uint32_t(teapot.mesh.triangle_count());
    for (std::size_t i = 0; i < ray_count; ++i) {
        const TriangleId id = random.below(triangles);
        const Triangle tri = triangle_of(teapot.mesh, id);
        const Vec3f n = normalize(tri.geometric_normal());  // outward: the mesh is wound outwards
        const bool inward = i % 2 == 0;
        const Vec3f side = inward ? -n : n;
        Vec3f dir = random_direction(random);
        if (dot(dir, side) < 0.0f) dir = -dir;
        // Inward rays start inside the part they leave, but parts interpenetrate: the start may
        // also lie inside another part; it is inside the mesh either way, so every one must hit.
        c.add_ray({offset_ray_origin(random_point_on(tri, random), side), dir}, inward, id);
    }
    return c;
}

/// Random rays into the box `box` (from outside it) and rays aimed at random points of the mesh's
/// triangles, half and half: the ray mix of the non-closed cases.
void add_rays_into(StressCase& c, const Aabb& box, std::size_t ray_count, HashRandom& random) {
    const float radius = length(box.extent()) + 1e-3f;
    const auto triangles = std::uint32_t(c.mesh.triangle_count());
    for (std::size_t i = 0; i < ray_count; ++i) {
        const Vec3f dir = random_direction(random);
        Vec3f target;
        if (i % 2 == 0 && triangles > 0) {
            target = random_point_on(triangle_of(c.mesh, random.below(triangles)), random);
        } else {
            const Vec3f e = box.extent();
            target = box.lo + Vec3f(random.uniform() * e.x, random.uniform() * e.y, random.uniform() * e.z);
        }
        c.add_ray({target - dir * radius, dir}, false);
    }
}

Mesh random_soup(std::size_t count, float size, const Vec3f& offset, HashRandom& random) {
    Mesh mesh;
    for (std::size_t i = 0; i < count; ++i) {
        const Vec3f centre = offset + Vec3f(random.uniform(-1.0f, 1.0f), random.uniform(-1.0f, 1.0f),
                                            random.uniform(-1.0f, 1.0f));
        const auto a = mesh.add_vertex(centre + random_direction(random) * (size * random.uniform()));
        const auto b = mesh.add_vertex(centre + random_direction(random) * (size * random.uniform()));
        const auto d = mesh.add_vertex(centre + random_direction(random) * (size * random.uniform()));
        mesh.add_triangle(a, b, d);
    }
    return mesh;
}

/// Valid triangles mixed with zero-area ones (a repeated corner, three collinear corners, a
/// repeated vertex position under two indices) and duplicates of valid ones, a quarter of the
/// rays aimed exactly at the degenerate triangles' points; none may ever be hit.
StressCase degenerate(std::size_t ray_count, HashRandom& random) {
    StressCase c{"degenerate", random_soup(400, 0.3f, Vec3f(0.0f), random), {}, {}, {}};
    Mesh& mesh = c.mesh;
    const auto valid = std::uint32_t(mesh.triangle_count());
    for (std::uint32_t i = 0; i < 400; ++i) {
        const IndexTriple t = mesh.triangles[random.below(valid)];
        const Vec3f a = mesh.vertex(t.v0), b = mesh.vertex(t.v1);
        switch (i % 5) {
            case 0: mesh.add_triangle(t.v0, t.v0, t.v1); break;  // repeated corner
            case 1: mesh.add_triangle(t.v0, t.v1, mesh.add_vertex(a + (b - a) * 0.5f)); break;  // collinear (midpoint)
            case 2: mesh.add_triangle(t.v0, t.v1, mesh.add_vertex(a + (b - a) * 2.0f)); break;  // collinear (beyond)
            case 3: mesh.add_triangle(t.v0, mesh.add_vertex(a), t.v1); break;  // same point, two indices
            default: mesh.add_triangle(t.v0, t.v1, t.v2);  // duplicate of a valid triangle
        }
    }
    const Aabb box = mesh.bounds();
    add_rays_into(c, box, ray_count - ray_count / 4, random);
    const auto all = std::uint32_t(mesh.triangle_count());
    while (c.rays.size() < ray_count) {
        const Triangle tri = triangle_of(mesh, valid + random.below(all - valid));
        const Vec3f target = random.below(2) ? tri.a : tri.a + (tri.b - tri.a) * random.uniform();
        const Vec3f dir = random_direction(random);
        c.add_ray({target - dir * 4.0f, dir}, false);
    }
    return c;
}

/// All triangles in the plane z = 0: rays from above and below, and rays lying in the plane.
StressCase coplanar(std::size_t ray_count, HashRandom& random) {
    StressCase c{"coplanar", random_soup(1000, 0.2f, Vec3f(0.0f), random), {}, {}, {}};
    for (float& z : c.mesh.z) z = 0.0f;
    add_rays_into(c, c.mesh.bounds(), ray_count - ray_count / 4, random);
    while (c.rays.size() < ray_count) {
        Vec3f dir = random_direction(random);
        dir.z = random.below(2) ? 0.0f : -0.0f;
        if (!(dot(dir, dir) > 0.0f)) continue;
        const Vec3f target(random.uniform(-1.0f, 1.0f), random.uniform(-1.0f, 1.0f), 0.0f);
        c.add_ray({target - dir * 4.0f, dir}, false);
    }
    return c;
}

/// Every triangle has the point (0.1, 0.2, 0.3) as a corner (a fan of random orientations); half
/// the rays are aimed exactly at that point.
StressCase one_point(std::size_t ray_count, HashRandom& random) {
    const Vec3f p(0.1f, 0.2f, 0.3f);
    StressCase c{"one_point", {}, {}, {}, {}};
    const std::uint32_t centre = c.mesh.add_vertex(p);
    for (int i = 0; i < 500; ++i)
        c.mesh.add_triangle(centre, c.mesh.add_vertex(p + random_direction(random) * random.uniform(0.1f, 1.0f)),
                            c.mesh.add_vertex(p + random_direction(random) * random.uniform(0.1f, 1.0f)));
    add_rays_into(c, c.mesh.bounds(), ray_count / 2, random);
    while (c.rays.size() < ray_count) {
        const Vec3f dir = random_direction(random);
        c.add_ray({p - dir * 3.0f, dir}, false);
    }
    return c;
}

/// One triangle spanning [-1e3, 1e3] among 2000 triangles a thousandth of a unit across.
StressCase huge_among_tiny(std::size_t ray_count, HashRandom& random) {
    StressCase c{"huge_among_tiny", random_soup(2000, 1e-3f, Vec3f(0.0f), random), {}, {}, {}};
    c.mesh.add_triangle(c.mesh.add_vertex({-1e3f, -1e3f, 0.01f}), c.mesh.add_vertex({1e3f, -1e3f, -0.01f}),
                        c.mesh.add_vertex({0.0f, 1e3f, 0.0f}));
    Aabb small_ones;
    small_ones.extend(Vec3f(-1.1f));
    small_ones.extend(Vec3f(1.1f));
    add_rays_into(c, small_ones, ray_count, random);
    return c;
}

/// Slivers running the length of the scene (10 units long, 1e-4 wide) in every direction, crossing.
StressCase long_thin(std::size_t ray_count, HashRandom& random) {
    StressCase c{"long_thin", {}, {}, {}, {}};
    for (int i = 0; i < 600; ++i) {
        const Vec3f dir = random_direction(random) * 5.0f;
        const Vec3f centre(random.uniform(-0.5f, 0.5f), random.uniform(-0.5f, 0.5f), random.uniform(-0.5f, 0.5f));
        const Vec3f width = normalize(cross(dir, random_direction(random))) * 1e-4f;
        c.mesh.add_triangle(c.mesh.add_vertex(centre - dir), c.mesh.add_vertex(centre + dir),
                            c.mesh.add_vertex(centre + width));
    }
    add_rays_into(c, c.mesh.bounds(), ray_count, random);
    return c;
}

StressCase soup(std::string name, float size, const Vec3f& offset, std::size_t ray_count, HashRandom& random) {
    StressCase c{std::move(name), random_soup(2000, size, offset, random), {}, {}, {}};
    add_rays_into(c, c.mesh.bounds(), ray_count, random);
    return c;
}

std::vector<CaseEntry> case_table() {
    std::vector<CaseEntry> table;
    auto closed = [&](std::string name, std::string what, std::function<ClosedMesh()> make) {
        table.push_back({{name, what}, [name, make](std::size_t n, HashRandom& random) {
                             return aimed_from_inside(name, make(), n, random);
                         }});
    };
    const auto sphere = [] { return jittered_sphere(10, 0.1f, 3); };
    const auto cube = [] { return tessellated_cube(8); };
    const auto teapot = [] { return closed_teapot(24); };
    closed("sphere", "jittered geodesic sphere (2000 triangles), rays from inside at surface points, vertices, edges",
           sphere);
    closed("cube", "cube, 8x8 quads a face, rays from inside at surface points, vertices, edges", cube);
    closed("teapot", "closed teapot (24 segments), rays from inside at surface points, vertices, edges", teapot);
    closed("asteroid", "closed asteroid (5120 triangles), rays from inside at surface points, vertices, edges",
           [] { return closed_asteroid(16, 5); });
    struct Placement {
        const char* label;
        float scale;
        float offset;
    };
    const Placement placements[] = {{"far1e3", 1.0f, 1e3f}, {"far1e4", 1.0f, 1e4f}, {"far1e5", 1.0f, 1e5f},
                                    {"far1e6", 1.0f, 1e6f}, {"scale1e-4", 1e-4f, 0.0f}, {"scale1e4", 1e4f, 0.0f}};
    const std::pair<const char*, std::function<ClosedMesh()>> meshes[] = {
        {"sphere", sphere}, {"cube", cube}, {"teapot", teapot}};
    for (const Placement& at : placements)
        for (const auto& [mesh_name, make] : meshes) {
            const bool extra = std::string_view(mesh_name) != "sphere" &&
                               (std::string_view(at.label) == "far1e4" || std::string_view(at.label) == "far1e5");
            if (extra) continue;  // the intermediate offsets for the sphere only
            const Vec3f offset(at.offset, -0.5f * at.offset, 0.25f * at.offset);
            closed(fmt::format("{}_{}", mesh_name, at.label),
                   fmt::format("{} scaled by {:g}, moved by ({:g}, {:g}, {:g}), rays from inside", mesh_name, at.scale,
                               offset.x, offset.y, offset.z),
                   [make, at, offset] { return placed(make(), at.scale, offset); });
        }
    auto add = [&](std::string name, std::string what, CaseMaker make) {
        table.push_back({{std::move(name), std::move(what)}, std::move(make)});
    };
    add("axis_parallel", "axis-parallel rays with +0/-0 components inside the cube, along its tessellation planes",
        axis_parallel);
    add("split_planes", "rays lying in the kd-tree's split planes, from inside the sphere", split_planes);
    add("octree_centres", "rays through octree cell centres and in cell boundary planes, from inside the sphere",
        octree_centres);
    add("grazing", "rays tangent to the sphere and in or beside the cube's face planes", grazing);
    add("surface_origins", "rays starting on the teapot's surface (offset_ray_origin), in and out", surface_origins);
    add("degenerate", "zero-area, collinear, repeated-vertex and duplicate triangles among valid ones", degenerate);
    add("coplanar", "all triangles in one plane, rays across and within it", coplanar);
    add("one_point", "500 triangles sharing one corner, rays aimed at it", one_point);
    add("huge_among_tiny", "one triangle 2000 units across among 2000 tiny ones", huge_among_tiny);
    add("long_thin", "600 slivers 10 units long and 1e-4 wide crossing the scene", long_thin);
    add("soup", "2000 random triangles", [](std::size_t n, HashRandom& random) {
        return soup("soup", 0.2f, Vec3f(0.0f), n, random);
    });
    add("soup_far", "2000 random triangles around (1e4, 1e4, 1e4)", [](std::size_t n, HashRandom& random) {
        return soup("soup_far", 0.2f, Vec3f(1e4f), n, random);
    });
    return table;
}

}  // namespace

std::vector<StressCaseInfo> stress_cases() {
    std::vector<StressCaseInfo> infos;
    for (const CaseEntry& entry : case_table()) infos.push_back(entry.info);
    return infos;
}

StressCase make_stress_case(std::string_view name, std::size_t ray_count, std::uint64_t seed) {
    for (const CaseEntry& entry : case_table()) {
        if (entry.info.name != name) continue;
        std::uint64_t name_hash = 0;  // each case its own stream, independent of the case list
        for (const char ch : name) name_hash = hash_combine(name_hash, std::uint64_t(std::uint8_t(ch)));
        HashRandom random(hash_combine(seed, name_hash));
        return entry.make(ray_count, random);
    }
    throw std::invalid_argument(fmt::format("stress case '{}': no such case", name));
}

}  // namespace trident
