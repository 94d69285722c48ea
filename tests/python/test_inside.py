"""curray.render and curray.trace with observers inside the horizon, against
the command line (run by tests/python/run.sh with CURRAY_BIN): the same C
library behind a different front end, so every array must equal the
d_<k>.csv of the same render exactly, and a traced path the --trace CSV.

Scenes: a Kerr-Newman free-faller between the horizons with a disc (rays
out through r+, and to the other side); a Reissner-Nordstrom free-faller
inside r- (rays through r- and r+); a Kerr free-faller inside r- (rays to
r = 0: outcome singularity); a Schwarzschild one with a sky image for the
other exterior (skymap.other_side); and a frame inside r- of a plunge
(observer.r: [infall, ...], frame 7 of 8).
"""
import csv
import os
import subprocess

import numpy as np
import pytest

import curray

BIN = os.environ.get("CURRAY_BIN", "curray")
SRC = os.environ.get("CURRAY_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
W, H = 40, 24
SKY = os.path.join(SRC, "scenes", "sky_grid.png")
STARS = os.path.join(SRC, "scenes", "sky.png")

SCENES = {
    "between": """metric: {m: 1, a: 0.6, q: 0.3}
observer: {r: 1.2, theta: 70 deg, phi: 0, hfov: 300 deg, motion: infall, projection: fisheye}
accretion: {radius: [3, 12], resolution: [2, 12], color1: [0, 255, 0]}
""",
    "rn_inner": """metric: {m: 1, a: 0, q: 0.8}
observer: {r: 0.36, theta: 80 deg, phi: 0, hfov: 300 deg, motion: infall, projection: fisheye}
accretion: {model: keplerian, radius: [6, 20]}
skymap: {image: %s}
""" % SKY,
    "kerr_inner": """metric: {m: 1, a: 0.9, q: 0}
observer: {r: 0.3, theta: 60 deg, phi: 0, hfov: 360 deg, motion: infall, projection: fisheye}
accretion: {radius: [3, 12], resolution: [2, 12], color1: [0, 255, 0]}
""",
    "other_sky": """metric: {m: 1, a: 0, q: 0}
observer: {r: 1, theta: 90 deg, phi: 0, hfov: 300 deg, motion: infall, projection: fisheye}
accretion: {radius: [6, 15], resolution: [2, 12], color1: [0, 200, 0]}
skymap: {image: %s, other_side: %s}
""" % (SKY, STARS),
}
PLUNGE = """metric: {m: 1, a: 0, q: 0.8}
observer: {r: [infall, 0.5, 0.33], theta: 80 deg, phi: 0, hfov: 300 deg, motion: infall,
           projection: fisheye}
"""


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("inside")
    out = {}
    for name, text in list(SCENES.items()) + [("plunge", PLUNGE)]:
        p = d / (name + ".yml")
        p.write_text(text)
        out[name] = str(p)
    return out


def run_cli(*args):
    r = subprocess.run([BIN, "-a", "true", "-q", "--threads", "2"] + [str(a) for a in args],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r


def cli_rows(path):
    with open(path) as fp:
        rows = list(csv.reader(fp))
    return {h: i for i, h in enumerate(rows[0])}, np.array(rows[1:], dtype=object)


def check_equal(col, a, img):
    x = a[:, col["x"]].astype(int)
    y = a[:, col["y"]].astype(int)
    for c, k in (("r", 0), ("g", 1), ("b", 2)):
        assert np.array_equal(a[:, col[c]].astype(int), img["rgb"][y, x, k]), c
    assert np.array_equal(a[:, col["steps"]].astype(np.int64), img["steps"][y, x])
    for k in ("redshift", "err_mean", "err_std", "hit_r", "hit_phi", "bolometric", "delay"):
        assert np.array_equal(a[:, col[k]].astype(float), img[k][y, x], equal_nan=True), k
    names = np.array(curray.OUTCOMES)[img["outcome"][y, x]]
    assert np.array_equal(a[:, col["outcome"]].astype(str), names)
    return names


@pytest.mark.parametrize("name,want", [
    ("between", {"other side", "disc"}), ("rn_inner", {"sky"}),
    ("kerr_inner", {"singularity", "other side"}), ("other_sky", {"other side", "disc"})])
def test_render_inside_equals_cli(files, tmp_path, name, want):
    run_cli("-s", files[name], "-o", tmp_path, "-x", W, "-y", H, "-t", "d")
    col, a = cli_rows(tmp_path / "d_0.csv")
    img = curray.render(files[name], W, H, threads=2)
    names = check_equal(col, a, img)
    # the scene shows what it is there for (rays through the horizons)
    assert want <= set(names), set(names)


def test_render_plunge_frame_inside_r_minus(files, tmp_path):
    run_cli("-s", files["plunge"], "-o", tmp_path, "-x", W, "-y", H, "-f", 8, "-t", "d")
    col, a = cli_rows(tmp_path / "d_7.csv")
    img = curray.render(files["plunge"], W, H, frame=7, frames=8, threads=2)
    check_equal(col, a, img)


def test_trace_inside_equals_cli(files, tmp_path):
    """A path from inside r- out through r- and r+ (and one to the other
    exterior's sky): --trace's CSV equals curray.trace's columns, and the
    path's radii pass both horizons."""
    for name in ("rn_inner", "other_sky"):
        i, j = W // 2 + 7, H // 2
        run_cli("-s", files[name], "-o", tmp_path, "-x", W, "-y", H, "--trace", "%d,%d" % (i, j))
        with open(tmp_path / ("trace_%d_%d_0.csv" % (i, j))) as fp:
            rows = list(csv.reader(fp))
        assert tuple(rows[0]) == curray.PATH_COLUMNS
        cli = np.array(rows[1:], dtype=float)
        p = curray.trace(files[name], pixel=(i, j), width=W, height=H)
        py = np.column_stack([p[c] for c in curray.PATH_COLUMNS])
        assert np.array_equal(cli, py), name
        img = curray.render(files[name], W, H, threads=2)
        assert p.outcome == curray.OUTCOMES[img["outcome"][j, i]]
        if name == "rn_inner":
            assert p.r.min() < 0.4 and p.r.max() > 1.6
