"""The module's camera rays and hits against the trident renderer's own trace of the same camera:
`trident render --dump-hits` (BENCHMARK.md's hit buffer), identical triangle and t for every
structure and packet width."""
import json
import subprocess

import numpy as np
import pytest

import trident
from conftest import BINARY_DIR, SHARED_DIR, STRUCTURES, WIDTHS, write_obj

WIDTH, HEIGHT = 96, 54  # tiles cut at the bottom edge, as 1080 rows are


def render_hits(tmp_path, scene, accel, *extra):
    hits = tmp_path / f"{accel}.hits"
    subprocess.run([str(BINARY_DIR / "trident"), "render", scene, "--accel", accel, "--width", str(WIDTH), "--height",
                    str(HEIGHT), "--mode", "depth", "--output", str(tmp_path / "out.png"), "--dump-hits", str(hits),
                    *extra], check=True, capture_output=True)
    return trident.read_hit_buffer(hits)


def check_same_hits(tmp_path, scene_argument, vertices, triangles, camera, extra=()):
    rays = trident.camera_rays(camera["eye"], camera["target"], camera["up"], camera["fov_y_deg"], WIDTH, HEIGHT)
    assert rays.shape == (HEIGHT, WIDTH, 6) and rays.dtype == np.float32
    for accel in STRUCTURES:
        triangle, t = render_hits(tmp_path, scene_argument, accel, *extra)
        assert (triangle >= 0).mean() > 0.05  # the camera sees the mesh
        scene = trident.Scene(vertices, triangles, accel=accel)
        for simd in WIDTHS:
            hits = scene.intersect(rays, simd=simd)
            np.testing.assert_array_equal(hits.triangle, triangle, err_msg=f"{accel} {simd}")
            np.testing.assert_array_equal(hits.t, t, err_msg=f"{accel} {simd}")
        flat = scene.intersect(rays.reshape(-1, 6))  # a list of rays, packets of consecutive rays
        np.testing.assert_array_equal(flat.t.reshape(HEIGHT, WIDTH), t)


@pytest.mark.parametrize("name", ["teapot", "asteroid"])
def test_builtin_scene_hits_equal_the_renderers(tmp_path, name):
    scene = trident.builtin_scene(name)
    check_same_hits(tmp_path, name, scene["vertices"], scene["triangles"], scene["camera"])


def test_obj_scene_hits_equal_the_renderers(tmp_path):
    """An OBJ through the project's loader on both sides, with the camera of a manifest."""
    vertices, triangles, _, _ = trident.closed_mesh("teapot")
    obj = write_obj(tmp_path / "teapot.obj", vertices, triangles)
    camera = {"eye": [2.5, 2.0, 3.5], "target": [0.0, 0.9, 0.0], "up": [0.0, 1.0, 0.0], "fov_y_deg": 45}
    manifest = tmp_path / "scenes.json"
    manifest.write_text(json.dumps([{"name": "closed_teapot", "file": "teapot.obj", "camera": camera}]))
    loaded_vertices, loaded_triangles = trident.load_obj(obj)
    check_same_hits(tmp_path, "closed_teapot", loaded_vertices, loaded_triangles, camera,
                    extra=("--scenes", str(manifest)))


def test_shared_scene_hits_equal_the_renderers(tmp_path):
    manifest = SHARED_DIR / "scenes" / "scenes.json"
    if not manifest.exists():
        pytest.skip(f"{manifest} is absent")
    entry = next(e for e in json.loads(manifest.read_text()) if e["name"] == "teapot")
    vertices, triangles = trident.load_obj(manifest.parent / entry["file"])
    check_same_hits(tmp_path, "teapot", vertices, triangles, entry["camera"], extra=("--scenes", str(manifest)))
