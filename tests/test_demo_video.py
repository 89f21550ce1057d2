"""``rigidrs demo --video``: the knock-down scene drawn into a file without a display;
the video has a frame per recorded frame (30 per simulated second for 3 s) and the
picture shows the coloured bodies on the ground."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rigidrs as rr
from rigidrs import cli


def test_demo_writes_a_video(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    import imageio.v2 as iio

    path = tmp_path / "demo.mp4"
    assert cli.main(["demo", "--video", str(path), "--only-video"]) == 0
    assert str(path) in capsys.readouterr().out
    frames = [f for f in iio.get_reader(path)]
    assert len(frames) == 3 * 30 + 1  # t = 0, 1/30, ..., 3 s
    assert frames[0].shape == (480, 640, 3)


def test_demo_picture_shows_the_bodies(tmp_path: Path) -> None:
    import imageio.v2 as iio

    path = tmp_path / "demo.png"
    assert cli.main(["demo", "--video", str(path), "--only-video"]) == 0
    def saturation(img: np.ndarray) -> np.ndarray:
        img = img.astype(float)
        return (img.max(axis=2) - img.min(axis=2)) / np.maximum(img.max(axis=2), 1)

    # Sky and ground alone, from the demo's camera, are grey or pale (the empty scene's
    # picture: saturation ≤ 0.12); the bodies are the palette's saturated colours, and
    # 17 bodies of 0.4-0.6 m seen from 6 m cover several percent of the picture (9 %).
    ground = rr.Scene()
    ground.add_body(rr.Plane(), fixed=True)
    empty = rr.render(ground, camera=rr.Camera(eye=(4.6, 4.2, 2.3), target=(0.0, 0.2, 0.6)))
    assert saturation(empty).max() < 0.35
    assert (saturation(iio.imread(path)) > 0.35).mean() > 0.02
    assert cli.main(["demo", "--video", str(tmp_path / "x.avi"), "--only-video"]) == 2
