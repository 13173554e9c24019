"""The examples run as a user runs them."""
import os
import subprocess
import sys

import numpy as np

import trident
from conftest import REPO, write_obj


def test_depth_image_example_writes_a_depth_image(tmp_path):
    vertices, triangles, _, _ = trident.closed_mesh("asteroid")
    obj = write_obj(tmp_path / "asteroid.obj", vertices, triangles)
    image = tmp_path / "depth.png"
    result = subprocess.run([sys.executable, str(REPO / "examples" / "depth_image.py"), str(obj), str(image), "--width",
                             "64", "--height", "48"], capture_output=True, text=True, env=os.environ)
    assert result.returncode == 0, result.stderr
    assert "rays hit" in result.stdout
    import matplotlib.image
    pixels = matplotlib.image.imread(image)
    assert pixels.shape[:2] == (48, 64) and np.ptp(pixels[..., :3]) > 0.1  # depth varies across the image
