"""The examples run as a user runs them."""
import os
import subprocess
import sys

import numpy as np

import trident
from conftest import REPO


def test_depth_image_example_writes_a_depth_image(tmp_path):
    vertices, triangles, _, _ = trident.closed_mesh("asteroid")
    obj = tmp_path / "asteroid.obj"
    lines = [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in vertices] + [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in triangles]
    obj.write_text("\n".join(lines) + "\n")
    image = tmp_path / "depth.png"
    result = subprocess.run([sys.executable, str(REPO / "examples" / "depth_image.py"), str(obj), str(image), "--width",
                             "64", "--height", "48"], capture_output=True, text=True, env=os.environ)
    assert result.returncode == 0, result.stderr
    assert "rays hit" in result.stdout
    import matplotlib.image
    pixels = matplotlib.image.imread(image)
    assert pixels.shape[:2] == (48, 64) and np.ptp(pixels[..., :3]) > 0.1  # depth varies across the image
