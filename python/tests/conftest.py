"""Shared set-up of the trident module's tests: where the build and ../shared are, small meshes."""
import os
import pathlib

import numpy as np
import pytest

import trident

REPO = pathlib.Path(__file__).resolve().parents[2]
BINARY_DIR = pathlib.Path(os.environ.get("TRIDENT_BINARY_DIR", REPO / "build"))
SHARED_DIR = pathlib.Path(os.environ.get("TRIDENT_SHARED_DIR", REPO.parent / "shared"))
STRUCTURES = ["bvh", "bvh2", "kdtree", "octree", "brute"]
WIDTHS = trident.simd_widths()


def triangle_soup(count, seed):
    """`count` random triangles of random sizes in the unit cube, as (vertices, triangles)."""
    rng = np.random.default_rng(seed)
    centres = rng.uniform(-1.0, 1.0, (count, 1, 3))
    corners = centres + rng.normal(0.0, 0.25, (count, 3, 3))
    return corners.reshape(-1, 3).astype(np.float32), np.arange(3 * count, dtype=np.int32).reshape(-1, 3)


def random_rays(count, seed):
    """Rays from a box around the soup towards points inside it, directions not normalized."""
    rng = np.random.default_rng(seed)
    origins = rng.uniform(-2.0, 2.0, (count, 3))
    directions = rng.uniform(-0.8, 0.8, (count, 3)) - origins * rng.uniform(0.2, 1.5, (count, 1))
    return origins.astype(np.float32), directions.astype(np.float32)


def write_obj(path, vertices, triangles):
    """The mesh as an OBJ file; 9 significant digits give back every float32 exactly."""
    lines = [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in triangles]
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.fixture(scope="session")
def soup():
    return triangle_soup(60, seed=5)
