"""Every query against a double-precision numpy brute force on small meshes, and against itself
across structures, packet widths and thread counts."""
import numpy as np
import pytest

import trident
from conftest import STRUCTURES, WIDTHS, random_rays, triangle_soup


def brute_force(vertices, triangles, origins, directions, tmin=0.0, tmax=np.inf):
    """Möller-Trumbore in float64 for every ray against every triangle: (t, hit, edge margin)."""
    corners = vertices.astype(np.float64)[triangles]
    a, e1, e2 = corners[:, 0], corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    o = origins.astype(np.float64)[:, None, :]
    d = directions.astype(np.float64)[:, None, :]
    p = np.cross(d, e2)
    det = np.einsum("ntk,tk->nt", p, e1)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = o - a
        q = np.cross(s, e1)
        u = np.einsum("ntk,ntk->nt", s, p) / det
        v = np.einsum("ntk,ntk->nt", d, q) / det
        t = np.einsum("tk,ntk->nt", e2, q) / det
    margin = np.minimum(np.minimum(u, v), 1.0 - u - v)
    hit = (det != 0) & (margin >= 0) & (t >= tmin) & (t <= tmax)
    return t, hit, margin


def reference(vertices, triangles, origins, directions, tmin=0.0, tmax=np.inf):
    """Closest t and triangle per ray, crossings, and which rays are clear of edges and ties."""
    t, hit, margin = brute_force(vertices, triangles, origins, directions, tmin, tmax)
    hit_t = np.where(hit, t, np.inf)
    order = np.sort(hit_t, axis=1)
    closest = np.argmin(hit_t, axis=1)
    in_range = (t >= tmin - 1e-3) & (t <= tmax + 1e-3)
    near_edge = np.any(in_range & (np.abs(margin) < 1e-5), axis=1)
    with np.errstate(invalid="ignore"):  # inf - inf for rays with no second hit
        near_tie = np.isfinite(order[:, 1]) & (order[:, 1] - order[:, 0] <= 1e-5 * order[:, 1])
    clear = ~near_edge & ~near_tie
    return {
        "t": order[:, 0],
        "triangle": np.where(np.isfinite(order[:, 0]), closest, -1),
        "count": hit.sum(axis=1),
        "clear": clear,
    }


@pytest.fixture(scope="module")
def soup_case():
    vertices, triangles = triangle_soup(60, seed=5)
    origins, directions = random_rays(3000, seed=9)
    ref = reference(vertices, triangles, origins, directions)
    assert ref["clear"].mean() > 0.9 and np.isfinite(ref["t"]).mean() > 0.3  # the comparison means something
    return vertices, triangles, origins, directions, ref


@pytest.mark.parametrize("accel", STRUCTURES)
@pytest.mark.parametrize("simd", WIDTHS)
def test_intersect_matches_double_precision_brute_force(soup_case, accel, simd):
    vertices, triangles, origins, directions, ref = soup_case
    hits = trident.Scene(vertices, triangles, accel=accel).intersect(origins, directions, simd=simd)
    clear = ref["clear"]
    np.testing.assert_array_equal(hits.triangle[clear], ref["triangle"][clear])
    hit = clear & np.isfinite(ref["t"])
    np.testing.assert_allclose(hits.t[hit], ref["t"][hit], rtol=1e-5)
    assert np.all(np.isinf(hits.t[hits.triangle == -1]))
    # The barycentrics rebuild the hit point, and the normal is the hit triangle's unit normal.
    corners = vertices.astype(np.float64)[triangles[hits.triangle[hit]]]
    point = corners[:, 0] + hits.u[hit, None] * (corners[:, 1] - corners[:, 0]) + hits.v[hit, None] * (
        corners[:, 2] - corners[:, 0])
    np.testing.assert_allclose(point, origins[hit] + hits.t[hit, None] * directions[hit], atol=1e-4)
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    np.testing.assert_allclose(hits.normal[hit], normal / np.linalg.norm(normal, axis=1)[:, None], atol=1e-5)
    assert np.all(hits.normal[hits.triangle == -1] == 0)


@pytest.mark.parametrize("accel", ["bvh", "bvh2"])
def test_spatial_splits_give_the_same_hits(soup_case, accel):
    vertices, triangles, origins, directions, ref = soup_case
    plain = trident.Scene(vertices, triangles, accel=accel, builder="binned")
    cut = trident.Scene(vertices, triangles, accel=accel, builder="spatial", spatial_split_budget=1.0)
    assert plain.stats["builder"] == "binned_sah" and cut.stats["builder"] == "spatial_sah"
    assert cut.stats["references"] >= plain.stats["references"]
    expected, hits = plain.intersect(origins, directions), cut.intersect(origins, directions)
    np.testing.assert_array_equal(hits.triangle, expected.triangle)
    np.testing.assert_array_equal(hits.t, expected.t)
    np.testing.assert_array_equal(cut.occluded(origins, directions), plain.occluded(origins, directions))
    np.testing.assert_array_equal(cut.count_hits(origins, directions), ref["count"])
    with pytest.raises(ValueError, match="spatial_split_budget"):
        trident.Scene(vertices, triangles, builder="spatial", spatial_split_budget=-1.0)


@pytest.mark.parametrize("accel", STRUCTURES)
def test_occluded_and_count_hits_match_brute_force(soup_case, accel):
    vertices, triangles, origins, directions, ref = soup_case
    scene = trident.Scene(vertices, triangles, accel=accel)
    clear = ref["clear"]
    for simd in WIDTHS:
        occluded = scene.occluded(origins, directions, simd=simd)
        np.testing.assert_array_equal(occluded[clear], np.isfinite(ref["t"])[clear])
        counts = scene.count_hits(origins, directions, simd=simd)
        np.testing.assert_array_equal(counts[clear], ref["count"][clear])
    assert ref["count"][clear].max() >= 3  # rays crossing several triangles were counted


def test_tmin_and_tmax_bound_every_query(soup_case):
    vertices, triangles, origins, directions, _ = soup_case
    ref = reference(vertices, triangles, origins, directions, tmin=0.3, tmax=0.9)
    scene = trident.Scene(vertices, triangles)
    clear = ref["clear"]
    hits = scene.intersect(origins, directions, tmin=0.3, tmax=0.9)
    np.testing.assert_array_equal(hits.triangle[clear], ref["triangle"][clear])
    np.testing.assert_array_equal(scene.occluded(origins, directions, tmin=0.3, tmax=0.9)[clear],
                                  np.isfinite(ref["t"])[clear])
    np.testing.assert_array_equal(scene.count_hits(origins, directions, tmin=0.3, tmax=0.9)[clear], ref["count"][clear])


@pytest.mark.parametrize("accel", STRUCTURES)
def test_results_do_not_depend_on_threads_or_ray_layout(soup_case, accel):
    vertices, triangles, origins, directions, _ = soup_case
    scene = trident.Scene(vertices, triangles, accel=accel)
    one = scene.intersect(origins, directions, threads=1)
    rays = np.concatenate([origins, directions], axis=1)
    for threads in (2, 3, 0):
        other = scene.intersect(rays, threads=threads)
        np.testing.assert_array_equal(other.triangle, one.triangle)
        np.testing.assert_array_equal(other.t, one.t)
        np.testing.assert_array_equal(scene.count_hits(origins, directions, threads=threads),
                                      scene.count_hits(origins, directions, threads=1))
    # An image-shaped batch (traced in tiles) and float64 input give the same hits.
    image = scene.intersect(origins.reshape(50, 60, 3).astype(np.float64), directions.reshape(50, 60, 3), threads=2)
    assert image.t.shape == (50, 60)
    np.testing.assert_array_equal(image.triangle.ravel(), one.triangle)
    np.testing.assert_array_equal(image.t.ravel(), one.t)


def test_one_origin_for_many_rays_and_a_single_ray(soup_case):
    vertices, triangles, _, directions, _ = soup_case
    scene = trident.Scene(vertices, triangles)
    eye = np.array([0.1, -0.2, 1.9], np.float32)
    shared = scene.intersect(eye, directions)
    each = scene.intersect(np.broadcast_to(eye, directions.shape).copy(), directions)
    np.testing.assert_array_equal(shared.t, each.t)
    single = scene.intersect(np.concatenate([eye, directions[7]]))
    assert single.t.shape == () and single.t == each.t[7] and single.triangle == each.triangle[7]
    assert sorted(single.keys()) == ["normal", "t", "triangle", "u", "v"] and single["t"] == single.t
    with pytest.raises(ValueError, match="read-only"):  # the normals are made from the triangles
        shared.triangle[0] = 10**6


@pytest.mark.parametrize("name", ["sphere", "teapot", "asteroid", "cube"])
def test_contains_on_closed_meshes(name):
    vertices, triangles, centre, radius = trident.closed_mesh(name)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    rng = np.random.default_rng(3)
    points = rng.uniform(lo - 0.1 * (hi - lo), hi + 0.1 * (hi - lo), (600, 3)).astype(np.float32)
    direction = np.array([[0.5362, -0.3144, 0.7834]])
    t, hit, margin = brute_force(vertices, triangles, points, np.repeat(direction, len(points), axis=0))
    parity = hit.sum(axis=1) % 2 == 1
    clear = ~np.any((t >= -1e-3) & (np.abs(margin) < 1e-5), axis=1) & ~np.any(hit & (np.abs(t) < 1e-4), axis=1)
    assert clear.mean() > 0.95 and 0.1 < parity.mean() < 0.9
    for accel in STRUCTURES:
        scene = trident.Scene(vertices, triangles, accel=accel)
        inside = scene.contains(points)
        np.testing.assert_array_equal(inside[clear], parity[clear])
        ball = np.asarray(centre) + 0.9 * radius * rng.uniform(-0.57, 0.57, (100, 3))
        assert scene.contains(ball).all()
        assert not scene.contains(hi + 1.0 + rng.uniform(0, 1, (10, 3))).any()


def test_stats_describe_the_structure(soup):
    vertices, triangles = soup
    for accel in STRUCTURES:
        stats = trident.Scene(vertices, triangles, accel=accel).stats
        # The stats name the tree itself: the wide BVH by its width (by default 16 where AVX2 runs,
        # else 8), the binary one bvh2.
        wide = "bvh16" if "8" in trident.simd_widths() else "bvh8"
        assert stats["structure"] == {"bvh": wide}.get(accel, accel) and stats["triangles"] == 60
        assert stats["bytes"] > 0 and stats["bytes_per_triangle"] == pytest.approx(stats["bytes"] / 60)
        for key in ("build_ms", "nodes", "leaves", "depth", "sah"):
            assert key in stats
    assert trident.Scene(vertices, triangles, accel="octree", max_depth=2).stats["depth"] <= 2
    assert trident.Scene(vertices, triangles, width=4).stats["structure"] == "bvh4"
    assert trident.Scene(vertices, triangles, width=2).stats["structure"] == "bvh2"
    sweep = trident.Scene(vertices, triangles, builder="sweep", max_leaf_size=2).stats
    assert sweep["max_leaf_size"] <= 2
    kd = trident.Scene(vertices, triangles, accel="kdtree", max_depth=3, perfect_splits=True).stats
    assert kd["depth"] <= 3


def test_load_obj_triangulates_in_file_order(tmp_path):
    path = tmp_path / "quad.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nf 1 2 3 4\nf 1 2 5\n")
    vertices, triangles = trident.load_obj(path)
    assert vertices.dtype == np.float32 and vertices.shape == (5, 3)
    assert triangles.dtype == np.int32 and triangles.shape == (3, 3)
    np.testing.assert_array_equal(triangles[2], [0, 1, 4])
    hits = trident.Scene(vertices, triangles).intersect([[0.6, 0.3, 1.0, 0.0, 0.0, -1.0]])
    assert hits.triangle[0] in (0, 1) and hits.t[0] == pytest.approx(1.0)


@pytest.mark.parametrize("simd", WIDTHS)
def test_an_image_of_rays_equals_the_list_at_every_width(soup_case, simd):
    """Images are traced in tiles of packet blocks; 50 x 60 cuts blocks and tiles at its edges."""
    vertices, triangles, origins, directions, _ = soup_case
    scene = trident.Scene(vertices, triangles)
    listed = scene.intersect(origins, directions, simd="scalar", threads=1)
    image = scene.intersect(origins.reshape(50, 60, 3), directions.reshape(50, 60, 3), simd=simd, threads=2)
    np.testing.assert_array_equal(image.triangle.ravel(), listed.triangle)
    np.testing.assert_array_equal(image.t.ravel(), listed.t)
    np.testing.assert_array_equal(image.u.ravel(), listed.u)
    np.testing.assert_array_equal(
        scene.occluded(origins.reshape(50, 60, 3), directions.reshape(50, 60, 3), simd=simd).ravel(),
        scene.occluded(origins, directions, simd="scalar"))
    # Rays as one (..., 6) array take the packets' own load of six-float rays where the block is full.
    rays = np.concatenate([origins, directions], axis=1)
    for shaped in (rays.reshape(50, 60, 6), rays):
        packed = scene.intersect(shaped, simd=simd, threads=2)
        np.testing.assert_array_equal(packed.triangle.ravel(), listed.triangle)
        np.testing.assert_array_equal(packed.t.ravel(), listed.t)
        np.testing.assert_array_equal(scene.occluded(shaped, simd=simd).ravel(),
                                      scene.occluded(origins, directions, simd="scalar"))


@pytest.mark.parametrize("simd", WIDTHS)
def test_the_first_bad_ray_of_an_image_is_named(soup_case, simd):
    """Each band of tiles stops at its first bad ray; the batch names the first of all."""
    vertices, triangles, origins, directions, _ = soup_case
    scene = trident.Scene(vertices, triangles)
    rays = np.concatenate([origins, directions], axis=1).reshape(50, 60, 6).copy()
    rays[40, 7, 1] = np.nan  # ray 2407, in a later band
    rays[20, 59, 5] = np.inf  # ray 1259, at the right edge of a band
    for query in (scene.intersect, scene.occluded, scene.count_hits):
        with pytest.raises(ValueError, match="ray 1259: the origin or the direction is not finite"):
            query(rays, simd=simd, threads=2)


def test_an_empty_interval_traces_nothing_but_still_checks_the_rays(soup_case):
    vertices, triangles, origins, directions, _ = soup_case
    scene = trident.Scene(vertices, triangles)
    assert (scene.intersect(origins, directions, tmin=2.0, tmax=1.0).triangle == -1).all()
    assert not scene.occluded(origins, directions, tmin=1.0, tmax=1.0).any()
    assert (scene.count_hits(origins, directions, tmin=2.0, tmax=1.0) == 0).all()
    bad = directions.copy()
    bad[11] = 0.0
    with pytest.raises(ValueError, match="ray 11: "):
        scene.intersect(origins, bad, tmin=2.0, tmax=1.0)


@pytest.mark.parametrize("simd", WIDTHS)
def test_large_batches_reuse_result_memory_without_mixing_results(simd):
    """Hits of 4 MiB or more go to memory kept between calls and are written by streaming stores."""
    teapot = trident.builtin_scene("teapot")
    scene = trident.Scene(teapot["vertices"], teapot["triangles"])
    camera = teapot["camera"]
    rays = trident.camera_rays(camera["eye"], camera["target"], camera["up"], camera["fov_y_deg"], 512, 512)
    # Row by row, 8 KiB of hits a call: numpy's own memory and normal stores.
    rows = [scene.intersect(row, simd="scalar") for row in rays]
    expected_triangle = np.stack([row.triangle for row in rows])
    expected_t = np.stack([row.t for row in rows])
    assert (expected_triangle >= 0).sum() > 10000
    first = scene.intersect(rays, simd=simd, threads=2)
    away = rays.copy()
    away[..., 3:] *= -1.0  # every ray turned away from the teapot: all misses
    second = scene.intersect(away, simd=simd, threads=2)  # while the first is alive: other memory
    np.testing.assert_array_equal(first.triangle, expected_triangle)
    np.testing.assert_array_equal(first.t, expected_t)
    assert (second.triangle == -1).all() and np.isinf(second.t).all()
    t_view = first.t  # a view keeps the memory from being reused
    del first, second
    third = scene.intersect(rays, simd=simd, threads=2)  # reuses the second's memory
    np.testing.assert_array_equal(t_view, expected_t)
    np.testing.assert_array_equal(third.triangle, expected_triangle)
    np.testing.assert_array_equal(third.t, expected_t)
