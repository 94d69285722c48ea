"""Tests of the Python package (python/), run by tests/python/run.sh (CTest's
test_python) with CURRAY_BIN = the command line built alongside.

Known answers used here, independent of the code under test:
- the command line's d_<k>.csv and --trace CSV of the same render (the same
  C library, but a different front end: arrays must equal them exactly);
- the Kerr-Newman metric written out below in NumPy: every path point must be
  null, g(u, u) = 0, to a stated tolerance;
- a radial Schwarzschild ray: t(r) = -(r*(r_o) - r*(r)), r* = r + 2 ln(r/2 - 1);
- the rk4 integrator (t in its state) for the coordinate time mino computes
  by quadrature.
"""
import csv
import math
import re
import os
import subprocess

import numpy as np
import pytest
from astropy.io import fits

import curray

BIN = os.environ.get("CURRAY_BIN", "curray")
SRC = os.environ.get("CURRAY_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
W, H = 32, 24

# Scenes as text (YAML), written to files for the command line; the same
# scenes as dicts exercise the dict path.
KN_DICT = {
    "metric": {"m": 1, "a": 0.9, "q": 0.3},
    "sky_color": [0, 0, 0],
    "horizon_color": [255, 0, 0],
    "observer": {"r": 40, "theta": "80 deg", "phi": 0, "hfov": "40 deg"},
    "accretion": {"radius": [3, 12], "resolution": [2, 12], "color1": [0, 255, 0]},
}
KN_YAML = """metric:
  m: 1
  a: 0.9
  q: 0.3
sky_color: [0, 0, 0]
horizon_color: [255, 0, 0]
observer:
  r: 40
  theta: 80 deg
  phi: 0
  hfov: 40 deg
accretion:
  radius: [3, 12]
  resolution: [2, 12]
  color1: [0, 255, 0]
"""
INF_YAML = """metric: {m: 2, a: 1.4, q: 0}
observer: {r: inf, theta: 60 deg, phi: 0, hextent: 60}
accretion: {radius: [8, 24], resolution: [2, 12], color1: [0, 255, 0]}
"""
KEPLER_YAML = """metric: {m: 1, a: 0.7, q: 0}
observer: {r: 50, theta: 75 deg, phi: 0, hfov: 30 deg}
accretion: {model: keplerian, radius: [15], inside_isco: plunging}
"""
SPHERE_YAML = os.path.join(SRC, "scenes", "listing-7.1.3-sphere-around-horizon.yml")
DEMO_YAML = os.path.join(SRC, "scenes", "demo.yml")


@pytest.fixture(scope="module")
def scenes(tmp_path_factory):
    d = tmp_path_factory.mktemp("scenes")
    out = {}
    for name, text in (("kn", KN_YAML), ("inf", INF_YAML), ("kepler", KEPLER_YAML)):
        p = d / (name + ".yml")
        p.write_text(text)
        out[name] = str(p)
    out["sphere"] = SPHERE_YAML
    out["demo"] = DEMO_YAML
    return out


def run_cli(*args, ok=True):
    r = subprocess.run([BIN, "-a", "true", "-q", "--threads", "2"] + [str(a) for a in args],
                       capture_output=True, text=True)
    if ok:
        assert r.returncode == 0, r.stderr
    return r


def read_csv(path):
    with open(path) as fp:
        rows = list(csv.reader(fp))
    return rows[0], rows[1:]


# ---- render == the command line's CSV -------------------------------------

# rk4 cannot start at infinity: that pair is refused (test_bad_input_...), not rendered
@pytest.mark.parametrize("name,config", [
    (n, c) for n in ("kn", "inf", "sphere", "demo", "kepler")
    for c in ({}, {"integrator": "rk4"}, {"samples": 2})
    if not (n == "inf" and c.get("integrator") == "rk4")])
def test_render_equals_cli_csv(scenes, tmp_path, name, config):
    cfg = tmp_path / "config.yml"
    cfg.write_text("raytracer:\n" + "".join("  %s: %s\n" % kv for kv in config.items()))
    run_cli("-s", scenes[name], "-o", tmp_path, "-x", W, "-y", H, "-t", "d", "-c", cfg)
    header, rows = read_csv(tmp_path / "d_0.csv")
    img = curray.render(scenes[name], W, H, threads=2, **config)
    assert img["rgb"].shape == (H, W, 3) and img["rgb"].dtype == np.uint8
    for k in ("redshift", "hit_r", "hit_phi", "err_mean", "err_std"):
        assert img[k].shape == (H, W) and img[k].dtype == np.float64, k
    assert img["outcome"].dtype == np.uint8 and img["steps"].dtype == np.uint32
    # every CSV column has its array (a column added to the CSV must be added
    # to curray.render too)
    col = {h: i for i, h in enumerate(header)}
    known = {"x", "y", "r", "g", "b", "steps", "redshift", "err_mean", "err_std", "outcome",
             "hit_r", "hit_phi", "bolometric", "order", "theta_turns", "delay"}
    assert set(header) <= known, "CSV columns without a render() array: %s" % (
        set(header) - known)
    assert len(rows) == W * H
    a = np.array(rows, dtype=object)
    x = a[:, col["x"]].astype(int)
    y = a[:, col["y"]].astype(int)
    for c, k in (("r", 0), ("g", 1), ("b", 2)):
        assert np.array_equal(a[:, col[c]].astype(int), img["rgb"][y, x, k]), c
    assert np.array_equal(a[:, col["steps"]].astype(np.int64), img["steps"][y, x])
    for k in ("redshift", "err_mean", "err_std", "hit_r", "hit_phi", "bolometric", "delay"):
        assert np.array_equal(a[:, col[k]].astype(float), img[k][y, x], equal_nan=True), k
    for k in ("order", "theta_turns"):
        assert img[k].dtype == np.int16, k
        assert np.array_equal(a[:, col[k]].astype(int), img[k][y, x]), k
    names = np.array(curray.OUTCOMES)[img["outcome"][y, x]]
    assert np.array_equal(a[:, col["outcome"]].astype(str), names)


def test_render_dict_equals_file(scenes):
    a = curray.render(KN_DICT, W, H, threads=1)
    b = curray.render(scenes["kn"], W, H, threads=2)
    for k in a:
        assert np.array_equal(a[k], b[k], equal_nan=a[k].dtype.kind == "f"), k
    # a scene with every outcome of the tests below
    assert {"disc", "horizon", "sky"} <= {curray.OUTCOMES[o] for o in np.unique(a["outcome"])}


# ---- FITS -----------------------------------------------------------------

@pytest.mark.parametrize("name", ["kn", "inf", "kepler"])
def test_fits(scenes, tmp_path, name):
    run_cli("-s", scenes[name], "-o", tmp_path, "-x", W, "-y", H, "-t", "df", "-f", 2)
    for k in range(2):
        header, rows = read_csv(tmp_path / ("d_%d.csv" % k))
        col = {h: i for i, h in enumerate(header)}
        a = np.array(rows, dtype=object)
        grid = lambda c, t=float: a[:, col[c]].astype(t).reshape(H, W)
        with fits.open(tmp_path / ("f_%d.fits" % k)) as hd:
            names = [h.name for h in hd]
            assert names == ["PRIMARY", "REDSHIFT", "HIT_R", "HIT_PHI", "BOLO", "OUTCOME",
                             "STEPS", "NULLERR", "NULLSTD", "ORDER", "THTURNS", "DELAY"]
            p = hd[0].header
            assert p["METRIC"] == "Kerr-Newman" and p["UNITS"] == "G = c = 1"
            assert p["FRAME"] == k and p["NFRAMES"] == 2 and p["INTEGRAT"] == "mino"
            assert p["TOLERANC"] == 1e-7
            if name == "kepler":
                assert p["BH_SPIN"] == 0.7 and p["OBS_R"] == 50
            elif name == "kn":
                assert p["BH_MASS"] == 1 and p["BH_SPIN"] == 0.9 and p["BH_CHRG"] == 0.3
                assert p["OBS_INF"] is False and p["OBS_R"] == 40
                assert abs(p["HFOV"] - 40) < 1e-12 and 0 < p["VFOV"] < 40
                assert abs(p["OBS_TH"] - 80) < 1e-12
            else:  # lengths in units of M = 2
                assert p["BH_MASS"] == 2 and p["BH_SPIN"] == 0.7 and p["OBS_INF"] is True
                assert p["HEXTENT"] == 30 and abs(p["VEXTENT"] - 30 * H / W) < 1e-12
            for o, word in enumerate(curray.OUTCOMES):
                assert p["OUTCOME%d" % o] == word
            for ext, dtype in (("REDSHIFT", np.float64), ("HIT_R", np.float64),
                               ("HIT_PHI", np.float64), ("BOLO", np.float64),
                               ("OUTCOME", np.uint8),
                               ("STEPS", np.uint32), ("NULLERR", np.float64),
                               ("NULLSTD", np.float64), ("ORDER", np.int16),
                               ("THTURNS", np.int16), ("DELAY", np.float64)):
                d = hd[ext].data
                assert d.shape == (H, W) and d.dtype.type == dtype, ext  # big-endian
            assert hd["HIT_R"].header["BUNIT"] == "M"
            # FITS rows run bottom-up: data[::-1] is the CSV's row order
            up = lambda e: hd[e].data[::-1]
            nan_for = lambda v: np.where(v == -1.0, np.nan, v)
            assert np.array_equal(up("REDSHIFT"), nan_for(grid("redshift")), equal_nan=True)
            assert np.array_equal(up("HIT_R"), nan_for(grid("hit_r")), equal_nan=True)
            assert np.array_equal(up("HIT_PHI"), nan_for(grid("hit_phi")), equal_nan=True)
            assert np.array_equal(up("BOLO"), nan_for(grid("bolometric")), equal_nan=True)
            assert np.array_equal(up("STEPS"), grid("steps", np.int64))
            assert np.array_equal(up("NULLERR"), grid("err_mean"))
            assert np.array_equal(up("NULLSTD"), grid("err_std"))
            assert np.array_equal(up("DELAY"), grid("delay"), equal_nan=True)
            assert hd["DELAY"].header["BUNIT"] == "M"
            assert np.array_equal(up("ORDER"), grid("order", np.int64))
            assert np.array_equal(up("THTURNS"), grid("theta_turns", np.int64))
            words = np.array(curray.OUTCOMES)[up("OUTCOME")]
            assert np.array_equal(words, grid("outcome", str))
    # atomic: nothing but the outputs (no temporary left behind)
    assert sorted(os.listdir(tmp_path)) == ["d_0.csv", "d_1.csv", "f_0.fits", "f_1.fits", "log"]


# ---- ray paths ------------------------------------------------------------

def kn_metric(r, th, a, q, m=1.0):
    """Kerr-Newman in Boyer-Lindquist coordinates (signature -+++)."""
    s2, c2 = np.sin(th) ** 2, np.cos(th) ** 2
    sig = r * r + a * a * c2
    dl = r * r - 2 * m * r + a * a + q * q
    w = 2 * m * r - q * q
    return (-(1 - w / sig), -a * s2 * w / sig, sig / dl, sig,
            s2 * (r * r + a * a + a * a * s2 * w / sig))


def null_residual(p, a, q):
    """|g(u, u)| over the sum of the magnitudes of its terms, per point."""
    gtt, gtp, grr, gthth, gpp = kn_metric(p.r, p.theta, a, q)
    terms = np.array([gtt * p.ut ** 2, 2 * gtp * p.ut * p.uphi, grr * p.ur ** 2,
                      gthth * p.utheta ** 2, gpp * p.uphi ** 2])
    return np.abs(terms.sum(axis=0)) / np.abs(terms).sum(axis=0)


def pixels_by_outcome(img):
    """One pixel (i, j) per outcome word, the first in row order whose ray
    took steps (a sky ray that never comes inside the scene radius ends
    without a step; its path is traced again for the path alone)."""
    out = {}
    for j in range(H):
        for i in range(W):
            if img["steps"][j, i] > 0:
                out.setdefault(curray.OUTCOMES[img["outcome"][j, i]], (i, j))
    return out


# Null-condition tolerance per integrator: mino's first-integral residuals
# follow its tolerance 1e-7 (the error monitor of docs/configuration.md, "Integrators"),
# rk4 keeps E, L exact and its null error small; measured worst: mino 3.8e-8,
# rk4 2.0e-8 on the Kerr-Newman scene below.
NULL_TOL = {"mino": 1e-6, "rk4": 1e-6}


@pytest.mark.parametrize("integrator", ["mino", "rk4"])
def test_trace_null_and_ends(scenes, integrator):
    a, q = 0.9, 0.3
    r_plus = 1 + math.sqrt(1 - a * a - q * q)
    img = curray.render(scenes["kn"], W, H, integrator=integrator)
    pix = pixels_by_outcome(img)
    assert {"disc", "horizon", "sky"} <= set(pix)
    worst = 0.0
    for word in ("disc", "horizon", "sky"):
        i, j = pix[word]
        p = curray.trace(scenes["kn"], pixel=(i, j), width=W, height=H, integrator=integrator)
        assert p.outcome == word and len(p.r) >= 3
        # docs/command-line.md "Ray paths": the observer, then 8 points per mino step (its
        # dense output, the last step cut at the hit or the stop) or 1 per
        # rk4 step: exactly 1 + 8 steps or 1 + steps (steps as the image's)
        assert p.steps == img["steps"][j, i]
        assert len(p.r) == 1 + {"mino": 8, "rk4": 1}[integrator] * p.steps, (len(p.r), p.steps)
        assert np.all(np.isfinite(np.vstack([p[c] for c in curray.PATH_COLUMNS])))
        # starts at the observer, parameter and t increasing/decreasing
        assert p.r[0] == 40 and p.t[0] == 0 and p.param[0] == 0
        assert np.all(np.diff(p.param) > 0) and np.all(np.diff(p.t) < 0)
        res = null_residual(p, a, q)
        worst = max(worst, res.max())
        assert res.max() < NULL_TOL[integrator], (word, res.max())
        # Cartesian (2.2.8) from the BL columns
        rho = np.sqrt(p.r ** 2 + a * a)
        assert np.allclose(p.x, rho * np.sin(p.theta) * np.cos(p.phi), atol=1e-9 * rho)
        assert np.allclose(p.z, p.r * np.cos(p.theta), atol=1e-9 * rho)
        if word == "disc":  # ends on the disc where the image says
            assert abs(math.cos(p.theta[-1])) < 1e-9
            assert p.r[-1] == img["hit_r"][j, i] and 3 <= p.r[-1] <= 12
            assert abs(p.phi[-1] % (2 * math.pi) - img["hit_phi"][j, i]) < 1e-12
        elif word == "horizon":  # at the stop r+ + horizon_epsilon (0.005)
            # the last step is cut where it crosses the stop (bisection on
            # the step's own states: exact to rounding; measured 2e-16 M),
            # not left at the step's end inside it
            assert abs(p.r[-1] - (r_plus + 0.005)) < 1e-9, p.r[-1] - (r_plus + 0.005)
        else:  # left the scene radius (1 M beyond the disc's outer edge 12) outward
            assert p.r[-1] >= 13 * (1 - 1e-12) and p.ur[-1] > 0
    # a sky ray that never comes inside the scene radius ends in the image
    # without a step (mino's check at the start); its path is traced again for
    # the path alone, out to infinity, and its pixel stays the image's
    zero = [(i, j) for j in range(H) for i in range(W)
            if img["steps"][j, i] == 0 and curray.OUTCOMES[img["outcome"][j, i]] == "sky"]
    if integrator == "mino":
        assert zero
    for i, j in zero[:2]:
        p = curray.trace(scenes["kn"], pixel=(i, j), width=W, height=H, integrator=integrator)
        assert p.outcome == "sky" and p.steps == 0 and len(p.r) > 8
        assert p.r[0] == 40 and p.r[-1] > 1e3 and p.ur[-1] > 0
        assert null_residual(p, a, q).max() < NULL_TOL[integrator]
    print("worst null residual (%s): %.3g" % (integrator, worst))


def test_trace_matches_cli(scenes, tmp_path):
    for name, (i, j), config in (("kn", (16, 12), {}), ("kn", (3, 20), {"integrator": "rk4"}),
                                 ("inf", (20, 9), {}), ("sphere", (12, 15), {"samples": 2})):
        cfg = tmp_path / "config.yml"
        cfg.write_text("raytracer:\n" + "".join("  %s: %s\n" % kv for kv in config.items()))
        run_cli("-s", scenes[name], "-o", tmp_path, "-x", W, "-y", H, "--trace",
                "%d,%d" % (i, j), "-c", cfg)
        header, rows = read_csv(tmp_path / ("trace_%d_%d_0.csv" % (i, j)))
        assert tuple(header) == curray.PATH_COLUMNS
        cli = np.array(rows, dtype=float)
        p = curray.trace(scenes[name], pixel=(i, j), width=W, height=H, **config)
        py = np.column_stack([p[c] for c in curray.PATH_COLUMNS])
        assert np.array_equal(cli, py), name
        img = curray.render(scenes[name], W, H, **config)
        assert p.outcome == curray.OUTCOMES[img["outcome"][j, i]]
        if p.outcome in ("disc", "sphere"):
            assert p.hit_r == img["hit_r"][j, i]
    # --trace writes the path files only
    assert not any(f.startswith(("d_", "c_", "info")) for f in os.listdir(tmp_path))


def test_trace_radial_schwarzschild_time():
    """A ray from the image centre of a Schwarzschild hole seen from the
    equator runs radially: t(r) = -(r*(r_o) - r*(r)), r* = r + 2 ln(r/2 - 1)."""
    scene = {"metric": {"m": 1, "a": 0, "q": 0},
             "observer": {"r": 30, "theta": 90, "phi": 0, "hfov": 40}}
    rstar = lambda r: r + 2 * np.log(r / 2 - 1)
    for integ, tol in (("mino", 1e-9), ("rk4", 1e-8)):
        p = curray.trace(scene, pixel=(2, 2), width=5, height=5, integrator=integ)
        assert p.outcome == "horizon"
        assert np.allclose(p.theta, math.pi / 2, atol=1e-12)
        err = np.abs(p.t + (rstar(30.0) - rstar(p.r)))
        assert err.max() < tol * abs(p.t[-1]), (integ, err.max())


def test_trace_time_mino_vs_rk4(scenes):
    """mino's quadrature of t against rk4, which integrates t: the same disc
    point (to 1e-6 M) at the same coordinate time (1e-5 relative)."""
    img = curray.render(scenes["kn"], W, H)
    i, j = pixels_by_outcome(img)["disc"]
    pm = curray.trace(scenes["kn"], pixel=(i, j), width=W, height=H)
    pr = curray.trace(scenes["kn"], pixel=(i, j), width=W, height=H, integrator="rk4",
                      step_multiplier=1 / 128)
    assert pm.outcome == pr.outcome == "disc"
    assert abs(pm.r[-1] - pr.r[-1]) < 1e-5
    assert abs(pm.t[-1] - pr.t[-1]) < 1e-5 * abs(pr.t[-1])


def test_trace_from_infinity(scenes):
    """An observer at infinity: the path starts at the end of the first step
    (t counted from there) and is null; t is not defined at r = inf."""
    p = curray.trace(scenes["inf"], pixel=(20, 9), width=W, height=H)
    assert np.isfinite(p.r[0]) and p.t[0] == 0 and p.param[0] > 0
    assert null_residual(p, 0.7, 0.0).max() < NULL_TOL["mino"]


# ---- bad input --------------------------------------------------------------

def test_bad_input_raises_value_error_with_cli_message(scenes, tmp_path):
    bad = tmp_path / "bad.yml"
    bad.write_text("metric:\n  m: 1\n  a: 2\n  q: 0\nobserver: {r: 30, theta: 90, phi: 0, hfov: 70}\n")
    junk = tmp_path / "junk.yml"
    junk.write_text("metric: [unclosed\n")
    for path in (bad, junk, tmp_path / "missing.yml"):
        with pytest.raises(ValueError) as e:
            curray.render(str(path), 8, 8)
        r = run_cli("-s", path, "-o", tmp_path / "o", "-x", 8, "-y", 8, ok=False)
        assert r.returncode != 0
        assert "curray: " + str(e.value) in r.stderr, (str(e.value), r.stderr)
    # the observer at infinity with rk4 is refused the same way
    with pytest.raises(ValueError, match="rk4"):
        curray.render(scenes["inf"], 8, 8, integrator="rk4")


@pytest.mark.parametrize("call", [
    lambda: curray.render({"metric": {"m": 1}}, 8, 8),
    lambda: curray.render({"metric": {"m": 1, "a": 0, "q": 0}, "observer": {"r": "x"}}, 8, 8),
    lambda: curray.render(DEMO_YAML, 0, 8),
    lambda: curray.render(DEMO_YAML, 8, 70000),
    lambda: curray.render(DEMO_YAML, 8.5, 8),
    lambda: curray.render(DEMO_YAML, 8, 8, tolerance=-1),
    lambda: curray.render(DEMO_YAML, 8, 8, integrator="euler"),
    lambda: curray.render(DEMO_YAML, 8, 8, samples=17),
    lambda: curray.render(DEMO_YAML, 8, 8, threads=10 ** 6),
    lambda: curray.render(DEMO_YAML, 8, 8, colour="red"),
    lambda: curray.render(DEMO_YAML, 8, 8, frame=1, frames=1),
    lambda: curray.render(42, 8, 8),
    lambda: curray.render({"metric": {"m": object()}}, 8, 8),
    lambda: curray.trace(DEMO_YAML, pixel=(8, 0), width=8, height=8),
    lambda: curray.trace(DEMO_YAML, pixel=(-1, 0), width=8, height=8),
    lambda: curray.trace(DEMO_YAML, pixel=(1,), width=8, height=8),
    lambda: curray.trace(DEMO_YAML, pixel="ab", width=8, height=8),
])
def test_bad_input_value_error(call):
    with pytest.raises(ValueError) as e:
        call()
    assert str(e.value)


def _self_containing(where):
    """A valid scene dict with a dict (or a list of dicts) inside itself."""
    d = {"metric": {"m": 1, "a": 0, "q": 0},
         "observer": {"r": 30, "theta": 85, "phi": 0, "hfov": 70}}
    if where == "dict":
        d["observer"]["again"] = d["observer"]
    elif where == "top":
        d["again"] = d
    else:
        spheres = [{"r": 10}]
        spheres[0]["inner"] = spheres
        d["sphere"] = spheres
    return d


@pytest.mark.parametrize("call, text", [
    (lambda: curray.render(DEMO_YAML, 10 ** 30, 8), r"^width: 10{30} is out of range"),
    (lambda: curray.render(DEMO_YAML, 8, -10 ** 30), r"^height: -10{30} is out of range"),
    (lambda: curray.render(DEMO_YAML, 8, 8, frame=2 ** 63), r"^frame: \d+ is out of range"),
    (lambda: curray.render(DEMO_YAML, 8, 8, frames=10 ** 20), r"^frames: 10{20} is out of range"),
    (lambda: curray.trace(DEMO_YAML, pixel=(10 ** 30, 0), width=8, height=8),
     r"^pixel: 10{30} is out of range"),
    (lambda: curray.render(_self_containing("dict"), 8, 8),
     r"^scene: the value of observer.again contains itself"),
    (lambda: curray.render(_self_containing("top"), 8, 8),
     r"^scene: the value of again contains itself"),
    (lambda: curray.render(_self_containing("list"), 8, 8),
     r"^scene: the value of sphere.inner contains itself"),
])
def test_value_error_names_parameter(call, text):
    """Integers beyond a C long and a dict that contains itself are a
    ValueError naming the parameter or key (were OverflowError and
    RecursionError)."""
    with pytest.raises(ValueError, match=text):
        call()


def test_value_error_names_key_and_line():
    with pytest.raises(ValueError, match=r"tolerance"):
        curray.render(DEMO_YAML, 8, 8, tolerance=0)
    with pytest.raises(ValueError, match=r"^scene file \(scene dict\): observer.hfov"):
        curray.render({"metric": {"m": 1, "a": 0, "q": 0},
                       "observer": {"r": 30, "theta": 90, "phi": 0, "hfov": 400}}, 8, 8)


def test_cli_trace_bad_input(scenes, tmp_path):
    for arg, msg in (("8,0", "curray: --trace: pixel 8,0 is outside the 8x8 frame"),
                     ("1", "curray: --trace: expected a pixel I,J (column, row from 0), got '1'"),
                     ("1,-2", "expected a pixel I,J"), ("a,b", "expected a pixel I,J"),
                     ("1,2,3", "expected a pixel I,J")):
        r = run_cli("-s", scenes["kn"], "-o", tmp_path / "o", "-x", 8, "-y", 8, "--trace", arg,
                    ok=False)
        assert r.returncode == 2 and msg in r.stderr, (arg, r.stderr)
    assert not (tmp_path / "o").exists()  # refused before anything is written


def test_trace_to_sky_at_infinity(tmp_path):
    """A sky image without a boundary: rays leave to r = inf; the path ends at
    its last finite point, every value finite, still null, moving outward."""
    scene = {"metric": {"m": 1, "a": 0.5, "q": 0},
             "observer": {"r": 30, "theta": 80, "phi": 0, "hfov": 60},
             "skymap": {"image": os.path.join(SRC, "scenes", "sky.png")}}
    for ij in ((0, 0), (5, 20), (31, 23)):
        p = curray.trace(scene, pixel=ij, width=W, height=H)
        assert p.outcome == "sky"
        assert np.all(np.isfinite(np.vstack([p[c] for c in curray.PATH_COLUMNS])))
        assert p.r[-1] > 100 and p.ur[-1] > 0 and np.all(np.diff(p.t) < 0)
        assert null_residual(p, 0.5, 0.0).max() < NULL_TOL["mino"]


# ---- backends: backend="auto" | "cpu" | "cuda" ------------------------------

INFO = curray.backend_info()
NEEDS_GPU = pytest.mark.skipif(
    INFO["gpu"] is None, reason="no usable GPU here (backend_info: %s)" % INFO["why"])


def test_backend_choice_without_gpu(scenes):
    """Where no GPU can be used (CI, this machine), "auto" is the CPU: the
    same arrays as "cpu"; "cuda" is refused with the reason (the command
    line's --backend cuda message: no device, or a build without CUDA)."""
    if INFO["gpu"] is not None:
        pytest.skip("a GPU is usable here (GPU %d): test_backend_cuda_equals_cpu covers it"
                    % INFO["gpu"])
    assert INFO["why"], "no reason given why no GPU is used"
    if not INFO["cuda_built"]:
        assert "no CUDA support" in INFO["why"]
    a = curray.render(scenes["kn"], W, H, threads=2)
    b = curray.render(scenes["kn"], W, H, threads=2, backend="cpu")
    assert a.keys() == b.keys()
    for k in a:
        assert np.array_equal(a[k], b[k], equal_nan=a[k].dtype.kind == "f"), k
    with pytest.raises(ValueError) as e:
        curray.render(scenes["kn"], W, H, backend="cuda")
    assert str(e.value) == "backend cuda: " + INFO["why"]
    # no device, no driver, no CUDA in this build, an unusable GPU: all say so
    assert "CUDA" in INFO["why"] or "GPU" in INFO["why"], INFO["why"]


@pytest.mark.parametrize("backend", ["gpu", "CPU", "", 0, None])
def test_backend_name_refused(backend):
    with pytest.raises(ValueError, match=r"^backend: expected auto, cpu or cuda, got "):
        curray.render(DEMO_YAML, 8, 8, backend=backend)


def test_trace_has_no_backend_keyword():
    with pytest.raises(ValueError, match=r"unknown keyword argument 'backend'; .* frame, frames$"):
        curray.trace(DEMO_YAML, pixel=(0, 0), width=8, height=8, backend="cpu")


@NEEDS_GPU
@pytest.mark.parametrize("name", ["kn", "demo", "kepler"])
def test_backend_cuda_equals_cpu(scenes, name):
    """The GPU's arrays against the CPU's (the reference, DESIGN rule 3), with
    test_backends' tolerances: outcome and object equal but for at most
    0.1 % of the pixels (plus one), redshift within 1e-6 where they agree."""
    w, h = 96, 64
    cpu = curray.render(scenes[name], w, h, threads=2, backend="cpu")
    gpu = curray.render(scenes[name], w, h, backend="cuda")
    auto = curray.render(scenes[name], w, h)
    for k in gpu:
        assert np.array_equal(gpu[k], auto[k], equal_nan=gpu[k].dtype.kind == "f"), \
            "auto did not pick the GPU: " + k
    same = (cpu["outcome"] == gpu["outcome"]) & (cpu["object"] == gpu["object"])
    allowed = int(0.001 * w * h) + 1
    assert (~same).sum() <= allowed, "%d pixels differ in outcome" % (~same).sum()
    dz = np.abs(cpu["redshift"] - gpu["redshift"])[same]
    assert (~(dz <= 1e-6)).sum() <= allowed, "worst redshift difference %g" % dz.max()


# ---- Ctrl-C and memory -------------------------------------------------------

CTRL_C_CHILD = r"""
import sys, time
import curray
print("start", flush=True)
t0 = time.monotonic()
try:
    # 2.25 million pixels of 16 rays: minutes of CPU time, never done in 1 s
    curray.render(sys.argv[1], 1500, 1500, samples=16, threads=2, backend=sys.argv[2])
    print("finished %.1f s" % (time.monotonic() - t0), flush=True)
except KeyboardInterrupt:
    print("interrupted %.1f s" % (time.monotonic() - t0), flush=True)
img = curray.render(sys.argv[1], 8, 8, threads=1)
print("usable", img["rgb"].shape, flush=True)
"""


@pytest.mark.parametrize("backend", ["cpu", pytest.param("cuda", marks=NEEDS_GPU)])
def test_ctrl_c_stops_render(tmp_path, backend):
    """Ctrl-C (SIGINT) during a long render: KeyboardInterrupt within a few
    seconds (the render polls Python's signal handlers about every 0.25 s),
    and the interpreter goes on (a second render works)."""
    import signal
    import sys
    import time
    p = subprocess.Popen([sys.executable, "-c", CTRL_C_CHILD, DEMO_YAML, backend],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert p.stdout.readline().strip() == "start"
        time.sleep(1.0)
        assert p.poll() is None, p.communicate()
        t = time.monotonic()
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=30)
        took = time.monotonic() - t
    finally:
        if p.poll() is None:
            p.kill()
            p.communicate()
    assert p.returncode == 0, (p.returncode, out, err)
    assert out.startswith("interrupted") and "usable (8, 8, 3)" in out, (out, err)
    assert took < 5.0, "%.1f s from Ctrl-C to the end" % took


MEMORY_CHILD = r"""
import resource, sys
import curray
limit = int(sys.argv[2])
resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
try:
    curray.render(sys.argv[1], 8192, 8192, threads=1)
    print("rendered")
except MemoryError as e:
    print("MemoryError:", e)
"""


def test_huge_frame_memory_error():
    """A frame whose arrays cannot fit is refused before anything is
    allocated, with the command line's check and message (here against an
    address-space limit of 4 GiB, or half the machine's memory when that is
    less: 8192 x 8192 pixels need about 7.5 GiB), never left to the
    out-of-memory killer; sizes past the command line's limits are a
    ValueError as there."""
    import sys
    limit = min(4 << 30, os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE") // 2)
    r = subprocess.run([sys.executable, "-c", MEMORY_CHILD, DEMO_YAML, str(limit)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, (r.returncode, r.stdout, r.stderr)
    line = r.stdout.strip()
    assert line.startswith("MemoryError: a 8192x8192 frame needs about "), line
    assert line.endswith("GiB of memory, more than the %.2f GiB of the address-space limit "
                         "(ulimit -v); choose a smaller width, height" % (limit / (1 << 30))), line
    need = float(line.split("needs about ")[1].split(" GiB")[0])
    assert 6.0 < need < 10.0, need  # 8192^2 x (a pixel + the arrays' 66 bytes)
    with pytest.raises(ValueError, match=r"^width, height: expected 1 to 65536 pixels a side"):
        curray.render(DEMO_YAML, 100000, 100000)


# ---- orbit == curray orbit's CSV ---------------------------------------------

ORBIT = {"metric": {"m": 1, "a": 0.7, "q": 0.3},
         "particle": {"charge_to_mass": 0.8, "r": 9, "theta": 80, "phi": 10,
                      "velocity": [0.05, 0.02, 0.36], "measured_by": "zamo",
                      "tau": 500, "dtau": 2.5}}


def test_orbit_equals_cli_csv(tmp_path):
    f = tmp_path / "orbit.yml"
    f.write_text(curray._yaml(ORBIT))
    r = subprocess.run([BIN, "orbit", "-s", str(f), "-o", str(tmp_path / "o"), "-q"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    head, rows = read_csv(tmp_path / "o" / "orbit.csv")
    assert head == ["tau", "t", "r", "theta", "phi", "x", "y", "z",
                    "u^t", "u^r", "u^theta", "u^phi"]
    for w in (curray.orbit(ORBIT), curray.orbit(str(f))):
        assert len(w.tau) == len(rows) == 201
        for k, c in enumerate(curray.ORBIT_COLUMNS):
            assert np.array_equal(w[c], np.array([float(x[k]) for x in rows])), c
        assert w.ended == "span" and w.steps > 10
        # u.u = -1 and the Carter constant along it (independent of the C code)
        a, q = 0.7, 0.3
        s2, c2 = np.sin(w.theta) ** 2, np.cos(w.theta) ** 2
        sig = w.r ** 2 + a * a * c2
        dl = w.r ** 2 + a * a + q * q - 2 * w.r
        A = (w.r ** 2 + a * a) ** 2 - dl * a * a * s2
        gtt, gtp = -(dl - a * a * s2) / sig, -a * s2 * (2 * w.r - q * q) / sig
        gpp = A * s2 / sig
        uu = gtt * w.ut ** 2 + 2 * gtp * w.ut * w.uphi + gpp * w.uphi ** 2 + \
            sig / dl * w.ur ** 2 + sig * w.utheta ** 2
        assert np.max(np.abs(uu + 1)) < 1e-9
        K = (sig * w.utheta) ** 2 + c2 * (a * a * (1 - w.E ** 2) + w.L ** 2 / s2)
        assert np.max(np.abs(K - w.K)) < 1e-8 * (w.K + w.L ** 2)


@pytest.mark.parametrize("particle,text", [
    ({"velocity": [0, 0, 1.2]}, "particle.velocity: speed 1.2 is not below the speed of light"),
    ({"velocity": [0, 0, 0], "r": 1.2}, "particle.r: the start r = 1.2 is not outside"),
    ({"velocity": [0, 0, 0], "charge_to_mass": float("nan")}, "particle.charge_to_mass"),
    ({}, "particle: no initial data"),
    ({"velocity": [0, 0, 0], "circular": "prograde"}, "particle.circular: contradicts"),
])
def test_orbit_bad_input(particle, text):
    p = {"r": 9, "theta": 90, "tau": 10}
    p.update(particle)
    with pytest.raises(ValueError, match=text.replace(".", r"\.")):
        curray.orbit({"metric": {"m": 1, "a": 0.7, "q": 0.3}, "particle": p})


# ---- spectrum == the command line's s_<k>.csv --------------------------------

SPEC_YAML = """metric: {m: 1, a: 0.9, q: 0}
observer: {r: inf, theta: 60 deg, phi: 0, hextent: 40}
accretion: {model: keplerian, radius: [15], temperature: 1e7}
spectrum:
  line: {energy_kev: 6.4, emissivity_index: 2.5, bins: 30, range: [2, 8]}
  continuum: {f_col: 1.7, bins: 25}
"""
SPEC_DICT = {"metric": {"m": 1, "a": 0.9, "q": 0},
             "observer": {"r": float("inf"), "theta": "60 deg", "phi": 0, "hextent": 40},
             "accretion": {"model": "keplerian", "radius": [15], "temperature": 1e7},
             "spectrum": {"line": {"energy_kev": 6.4, "emissivity_index": 2.5, "bins": 30,
                                   "range": [2, 8]},
                          "continuum": {"f_col": 1.7, "bins": 25}}}


@pytest.mark.parametrize("name,config", [
    ("spec", {}), ("spec", {"samples": 2}), ("kepler", {}), ("kepler", {"integrator": "rk4"})])
def test_spectrum_equals_cli_csv(scenes, tmp_path, name, config):
    """Every value of s_0.csv, bit for bit (the CSV prints the shortest
    decimal that reads back as the same double), and the normalisation
    checked from the flux column: the line's normalised column integrates to
    1 over g = E / E0, the continuum's to 1 over E (keV), each proportional
    to its flux."""
    path = tmp_path / "s.yml"
    path.write_text(SPEC_YAML if name == "spec" else open(scenes["kepler"]).read())
    cfg = tmp_path / "config.yml"
    cfg.write_text("raytracer:\n" + "".join("  %s: %s\n" % kv for kv in config.items()))
    run_cli("-s", path, "-o", tmp_path / "o", "-x", W, "-y", H, "-t", "s", "-c", cfg)
    header, rows = read_csv(tmp_path / "o" / "s_0.csv")
    assert header == ["spectrum", "bin"] + list(curray.SPECTRUM_COLUMNS)
    sp = curray.spectrum(str(path), W, H, threads=2, **config)
    assert sp.rays > 0 and 0 < sp.inner_rays <= sp.rays
    e0 = 6.4
    assert sp.energy_kev == e0
    for part in ("line", "continuum"):
        mine = [r for r in rows if r[0] == part]
        d = sp[part]
        assert [int(r[1]) for r in mine] == list(range(len(mine)))
        for k, c in enumerate(curray.SPECTRUM_COLUMNS):
            want = np.array([float(r[2 + k]) for r in mine])
            if part == "continuum" and c == "g":
                assert c not in d and np.all(want == -1)
                continue
            assert d[c].dtype == np.float64 and d[c].shape == (len(mine),), (part, c)
            assert np.array_equal(d[c], want), (part, c)
        assert np.array_equal(d["edges"], np.append(d["e_lo_kev"], d["e_hi_kev"][-1]))
        w = d["e_hi_kev"] - d["e_lo_kev"]
        dx = w / e0 if part == "line" else w
        assert abs(np.sum(d["normalised"] * dx) - 1) < 1e-12, part
        total = np.sum(d["flux"] * w)
        assert np.allclose(d["normalised"], d["flux"] / total * (e0 if part == "line" else 1),
                           rtol=1e-12, atol=0), part
    # the dict scene is the file
    if name == "spec" and not config:
        sd = curray.spectrum(SPEC_DICT, W, H, threads=1)
        for part in ("line", "continuum"):
            for c in sp[part]:
                assert np.array_equal(sd[part][c], sp[part][c]), (part, c)


def test_spectrum_warning_and_defaults(scenes, tmp_path):
    """The default bins (200 line bins around E0 = 6.4 keV, 100 continuum
    bins) of a scene without a spectrum key, and the command line's console
    warning when fewer than 10 rays a line bin meet the inner disc."""
    sp = curray.spectrum(scenes["kepler"], 16, 12, threads=1)
    r = subprocess.run([BIN, "-a", "true", "--threads", "1", "-s", scenes["kepler"], "-o",
                        str(tmp_path), "-x", "16", "-y", "12", "-t", "s"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert sp.warning and "curray: warning: frame 0: " + sp.warning in r.stdout + r.stderr, (
        sp.warning, r.stdout, r.stderr)
    assert len(sp.line["e_kev"]) == 200 and len(sp.continuum["e_kev"]) == 100
    assert sp.line["e_lo_kev"][0] == pytest.approx(0.64) and sp.line["e_hi_kev"][-1] == \
        pytest.approx(9.6)
    assert sp.inner_rays < 2000
    assert "fewer than 10 per line bin (200 bins)" in sp.warning


@pytest.mark.parametrize("scene, text", [
    ({"metric": {"m": 1, "a": 0, "q": 0}, "observer": {"r": 30, "theta": 70, "phi": 0,
                                                       "hfov": 60}},
     r"^scene file \(scene dict\): accretion: the spectrum is that of a Keplerian disc, and "
     r"the scene has no disc"),
    ({"metric": {"m": 1, "a": 0, "q": 0}, "observer": {"r": 30, "theta": 70, "phi": 0,
                                                       "hfov": 60},
      "accretion": {"radius": [6, 12], "resolution": [2, 2], "color1": [255, 0, 0]}},
     r"^scene file \(scene dict\): accretion: .* the scene has a chessboard disc"),
    ({"spectrum": {"line": {"bins": 0}}}, r"spectrum\.line\.bins"),
    ({"spectrum": {"continuum": {"bins": -2}}}, r"spectrum\.continuum\.bins"),
    ({"spectrum": {"line": {"energy_kev": 0}}},
     r"spectrum\.line\.energy_kev: the line's rest energy must be positive"),
    ({"spectrum": {"line": {"range": [3, 3]}}}, r"spectrum\.line\.range: the range \[3, 3\] keV is empty"),
    ({"spectrum": {"continuum": {"range": [-1, 3]}}},
     r"spectrum\.continuum\.range\[0\]: a photon energy must be positive"),
])
def test_spectrum_bad_input(scene, text):
    s = dict(SPEC_DICT, spectrum={}) if "metric" not in scene else {}
    s.update(scene)
    with pytest.raises(ValueError, match=text):
        curray.spectrum(s, 8, 8)


# ---- orbit_picture == curray orbit -t c's orbit.png and orbit_image.csv -----

def read_png_rgb(path):
    """The pixels of an 8-bit RGB PNG without interlacing (what curray
    writes), decoded here with zlib and the five PNG row filters."""
    import struct
    import zlib
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat, w = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert (depth, colour, interlace) == (8, 2, 0)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw, stride = zlib.decompress(idat), 3 * w
    out = np.zeros((h, stride), dtype=np.int32)
    prev = np.zeros(stride, dtype=np.int32)
    for j in range(h):
        f = raw[j * (stride + 1)]
        line = np.frombuffer(raw, dtype=np.uint8, count=stride, offset=j * (stride + 1) + 1)
        cur = line.astype(np.int32)
        if f == 2:
            cur = (cur + prev) & 255
        elif f in (1, 3, 4):
            cur = cur.copy()
            for i in range(stride):
                a = cur[i - 3] if i >= 3 else 0
                b, c = prev[i], prev[i - 3] if i >= 3 else 0
                if f == 1:
                    pred = a
                elif f == 3:
                    pred = (a + b) // 2
                else:
                    p = a + b - c
                    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                    pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                cur[i] = (cur[i] + pred) & 255
        else:
            assert f == 0, f
        out[j] = cur
        prev = cur
    return out.reshape(h, w, 3).astype(np.uint8)


VIEW_YAML = os.path.join(SRC, "scenes", "orbits", "kerr-view.yml")
# kerr-eccentric.yml's orbit, shorter (a third of an orbit and more), seen
# through its view at 96 x 64
PIC = {"metric": {"m": 1, "a": 0.9, "q": 0},
       "particle": {"r": 15, "theta": 90, "velocity": [0, 0, 0.27], "tau": 300, "dtau": 4},
       "view": {"scene": VIEW_YAML, "line_width": 1.5, "orders": 2}}
PW, PH = 96, 64


def test_orbit_picture_equals_cli(tmp_path):
    """Every pixel of orbit.png and every value of orbit_image.csv; and the
    drawing checked from the images (independently of the C drawing code):
    every pixel that differs from the view's scene rendered alone lies
    within half the line width and a pixel of the antialiasing of a visible
    image, and every visible row image's pixel is changed."""
    f = tmp_path / "orbit.yml"
    f.write_text(curray._yaml(PIC))
    r = subprocess.run([BIN, "orbit", "-s", str(f), "-o", str(tmp_path / "o"), "-t", "c",
                        "-x", str(PW), "-y", str(PH), "-q"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    png = read_png_rgb(tmp_path / "o" / "orbit.png")
    head, rows = read_csv(tmp_path / "o" / "orbit_image.csv")
    assert head == list(curray.ORBIT_IMAGE_COLUMNS)
    for p in (curray.orbit_picture(PIC, PW, PH), curray.orbit_picture(str(f), width=PW,
                                                                        height=PH)):
        assert p.rgb.dtype == np.uint8 and p.rgb.shape == (PH, PW, 3)
        assert np.array_equal(p.rgb, png)
        assert len(p.tau) == len(rows) > 76  # at least one image of each of the 76 rows
        for k, c in enumerate(curray.ORBIT_IMAGE_COLUMNS):
            want = np.array([float(x[k]) for x in rows])
            assert np.array_equal(p[c].astype(np.float64), want), c
        assert p.order.dtype == np.int16 and p.visible.dtype == bool
        assert p.points == 76 and p.lost >= 0 and p.solves >= len(p.tau)
        assert set(p.order.tolist()) == {0, 1}
    bg = curray.render(VIEW_YAML, PW, PH)["rgb"]
    changed = np.argwhere(np.any(p.rgb != bg, axis=2))
    assert len(changed) > 50
    vis = p.visible
    pts = np.stack([p.i[vis], p.j[vis]], axis=1)
    for j, i in changed:
        d = np.min(np.hypot(pts[:, 0] - i, pts[:, 1] - j))
        # segments join images at most CR_OPIC_JOIN = 4 px apart: a pixel
        # on one is within 2 px of an end, plus half the width and the 0.5
        # px antialiasing
        assert d <= 2 + 0.75 + 0.5 + 1e-9, (i, j, d)
    for i, j in np.rint(pts[p.row[vis]]).astype(int):
        if 0 <= i < PW and 0 <= j < PH:
            assert np.any(p.rgb[j, i] != bg[j, i]), (i, j)


@pytest.mark.parametrize("change,text", [
    ({"view": None}, "(orbit dict): the lensed picture needs a camera: the orbit file has no view"),
    ({"view": {"scene": "/nonexistent/v.yml"}}, "view.scene: "),
    ({"view": {"scene": VIEW_YAML, "orders": 5}}, "view.orders"),
    ({"view": {"scene": VIEW_YAML, "line_width": 0}}, "view.line_width"),
    ({"metric": {"m": 1, "a": 0.8, "q": 0}},
     "view.scene: the scene's metric (m 1, a 0.9, q 0) is not the orbit file's (m 1, a 0.8"),
    ({"width": 0}, "width: expected a size from 1 to 8192 pixels, got 0"),
    ({"height": 8193}, "height: expected a size from 1 to 8192 pixels, got 8193"),
    ({"width": 2.5}, "width: expected an integer"),
])
def test_orbit_picture_bad_input(change, text):
    spec = {k: v for k, v in PIC.items()}
    size = {"width": 8, "height": 8}
    for k, v in change.items():
        if k in size:
            size[k] = v
        elif v is None:
            del spec[k]
        else:
            spec[k] = v
    with pytest.raises(ValueError, match=re.escape(text)):
        curray.orbit_picture(spec, **size)
    with pytest.raises(ValueError, match="orbit_picture: expected a dict or the path"):
        curray.orbit_picture(3)
