"""Bad input is a Python exception with the C++ side's message, never a crash or a wrong answer."""
import numpy as np
import pytest

import trident


@pytest.fixture(scope="module")
def scene(soup):
    return trident.Scene(*soup)


def test_mesh_shape_dtype_and_values(soup):
    vertices, triangles = soup
    with pytest.raises(ValueError, match=r"vertices: expected shape \(N, 3\), got \(180, 2\)"):
        trident.Scene(vertices[:, :2], triangles)
    with pytest.raises(ValueError, match=r"triangles: expected shape \(N, 3\)"):
        trident.Scene(vertices, triangles.reshape(-1))
    with pytest.raises(ValueError, match="triangles: dtype float32 is not an integer type"):
        trident.Scene(vertices, triangles.astype(np.float32))
    with pytest.raises(ValueError, match="vertices: dtype <U1 is not numeric"):
        trident.Scene(np.full((3, 3), "a"), [[0, 1, 2]])
    bad = vertices.copy()
    bad[4, 1] = np.nan
    with pytest.raises(ValueError, match="Scene: vertex 5 has a non-finite coordinate"):
        trident.Scene(bad, triangles)
    with pytest.raises(ValueError, match="Scene: vertex 1 has a non-finite coordinate"), np.errstate(over="ignore"):
        trident.Scene(np.full((3, 3), 1e300), [[0, 1, 2]])  # beyond float32: infinite
    with pytest.raises(ValueError, match="Scene: the mesh has no triangles"):
        trident.Scene(vertices, np.zeros((0, 3), np.int32))


@pytest.mark.parametrize("index, dtype", [(180, np.int32), (-1, np.int32), (1 << 33, np.int64), (-5, np.int64),
                                          (4000000000, np.uint32), (181, np.uint16)])
def test_triangle_index_out_of_range_is_an_index_error(soup, index, dtype):
    vertices, triangles = soup
    bad = triangles.astype(dtype)
    bad[2, 1] = index
    with pytest.raises(IndexError, match="Scene: triangle 3 references a vertex beyond the 180 vertices"):
        trident.Scene(vertices, bad)


def test_structure_and_options(soup):
    with pytest.raises(ValueError, match="accel sah: unknown structure"):
        trident.Scene(*soup, accel="sah")
    with pytest.raises(TypeError, match=r"unknown option max_depth \(options: builder, bin_count"):
        trident.Scene(*soup, accel="bvh", max_depth=3)
    with pytest.raises(ValueError):
        trident.Scene(*soup, accel="bvh", width=3)
    with pytest.raises(TypeError, match="unknown option bin_count \\(options: none\\)"):
        trident.Scene(*soup, accel="brute", bin_count=8)
    with pytest.raises(ValueError, match=r"bin_count 2 is outside \[8, 64\]"):
        trident.Scene(*soup, bin_count=2)
    with pytest.raises(ValueError, match="empty_bonus must be in"):
        trident.Scene(*soup, accel="kdtree", empty_bonus=1.5)
    with pytest.raises(ValueError, match="overlap=sphere: expected one of triangle, box"):
        trident.Scene(*soup, accel="octree", overlap="sphere")
    with pytest.raises(ValueError, match="octree: the maximum depth must be between 1 and 12"):
        trident.Scene(*soup, accel="octree", max_depth=13)
    with pytest.raises(TypeError, match="bin_count='many': wrong type"):
        trident.Scene(*soup, bin_count="many")


def test_rays(scene):
    with pytest.raises(ValueError, match=r"rays: expected shape \(\.\.\., 6\), got \(4, 5\)"):
        scene.intersect(np.zeros((4, 5), np.float32))
    with pytest.raises(ValueError, match=r"origins: shape \(4, 3\) matches neither the directions' \(5, 3\) nor \(3,\)"):
        scene.occluded(np.zeros((4, 3)), np.ones((5, 3)))
    with pytest.raises(ValueError, match="directions: dtype complex128 is not numeric"):
        scene.count_hits(np.zeros(3), np.ones((5, 3), complex))
    rays = np.tile(np.array([0, 0, 3, 0, 0, -1], np.float32), (10, 1))
    for column, value in ((0, np.nan), (4, np.inf), (3, 0.0)):
        bad = rays.copy()
        bad[7, column] = value
        if column == 3:
            bad[7, 3:] = 0.0
        for query in (scene.intersect, scene.occluded, scene.count_hits):
            with pytest.raises(ValueError, match="ray 7: the origin or the direction is not finite, or the direction is zero"):
                query(bad)
    with pytest.raises(ValueError, match="tmin -1: must be finite and >= 0"):
        scene.intersect(rays, tmin=-1.0)
    with pytest.raises(ValueError, match="tmax: must not be NaN"):
        scene.intersect(rays, tmax=float("nan"))
    with pytest.raises(ValueError, match="threads -1"):
        scene.intersect(rays, threads=-1)
    with pytest.raises(ValueError, match="simd 5: expected auto\\|scalar\\|4\\|8\\|16"):
        scene.intersect(rays, simd=5)
    with pytest.raises(ValueError, match="points: point 1 is not finite"):
        scene.contains([[0, 0, 0], [np.nan, 0, 0]])
    with pytest.raises(ValueError, match=r"points: expected shape \(\.\.\., 3\)"):
        scene.contains(np.zeros((2, 2)))


def test_files(tmp_path):
    with pytest.raises(FileNotFoundError, match="missing.obj: no such file"):
        trident.load_obj(tmp_path / "missing.obj")
    with pytest.raises(FileNotFoundError, match="missing.hits"):
        trident.read_hit_buffer(tmp_path / "missing.hits")
    (tmp_path / "short.hits").write_bytes(b"RTHITS1\0\x02\0\0\0")
    with pytest.raises(RuntimeError, match="short.hits"):
        trident.read_hit_buffer(tmp_path / "short.hits")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n")
    with pytest.raises(ValueError, match="bad.obj: face 1 references vertex 7, but the file has 3 vertices"):
        trident.load_obj(bad)
    bad.write_text("v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.raises(ValueError, match="bad.obj:2: malformed vertex coordinate"):
        trident.load_obj(bad)


def test_camera():
    args = dict(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), fov_y_deg=60, width=8, height=4)
    assert trident.camera_rays(**args).shape == (4, 8, 6)
    for change, message in ((dict(fov_y_deg=180), "fov_y_deg 180"), (dict(width=0), "width/height 0x4"),
                            (dict(height=20000), "each must lie in 1..16384"), (dict(target=(0, 0, 5)), "eye equals target"),
                            (dict(up=(0, 0, 2)), "up is zero or parallel"), (dict(eye=(0, np.nan, 1)), "eye: not finite"),
                            (dict(up=(0, 1)), r"up: expected 3 numbers, got shape \(2,\)")):
        with pytest.raises(ValueError, match=message):
            trident.camera_rays(**{**args, **change})
