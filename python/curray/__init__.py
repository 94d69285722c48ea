"""curray from Python: render frames into NumPy arrays, trace one ray's path.

    import curray
    img = curray.render("scenes/demo.yml", 320, 240)          # or a dict
    img["rgb"]        # (240, 320, 3) uint8
    img["redshift"]   # (240, 320) float64, -1 where undefined (as in the CSV)
    p = curray.trace("scenes/demo.yml", pixel=(160, 60), width=320, height=240)
    p.x, p.y, p.z     # the ray's path in Cartesian coordinates (units of M)

curray.spectrum(scene, width, height) returns the spectrum of a Keplerian disc
(s_<k>.csv of -t s) as arrays.

All call curray's C library (the command line's scene loader, CPU and CUDA
backends and trace loop); bad input raises ValueError with the command line's
message, Ctrl-C stops a render with KeyboardInterrupt.
"""
import json
import math
import os
import re

import numpy as np

from . import _curray

__all__ = ["render", "spectrum", "SPECTRUM_COLUMNS", "trace", "orbit", "ORBIT_COLUMNS", "orbit_picture", "ORBIT_IMAGE_COLUMNS", "backend_info", "OUTCOMES", "PATH_COLUMNS", "CONFIG_KEYS",
           "__version__"]

_C = _curray._constants()
__version__ = _C["version"]
#: outcome names by code: outcome array value k means OUTCOMES[k]
OUTCOMES = _C["outcomes"]
#: columns of a ray path (see trace)
PATH_COLUMNS = tuple(_C["path_columns"].split(","))

#: keyword arguments of render/trace and the config.yml key each sets: every
#: raytracer setting (the C table settings.def) by its key, and threads
CONFIG_KEYS = {k.split(".")[1]: k for k in _C["settings"]}
CONFIG_KEYS["threads"] = "cpu.threads"

_PLAIN = re.compile(r"^[A-Za-z0-9_.+-][A-Za-z0-9 _.+-]*$")


def _scalar(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        v = float(v)
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return v if _PLAIN.match(v) and not v.endswith(" ") else json.dumps(v)
    raise ValueError("scene: cannot write a %s (%r) as a YAML value" % (type(v).__name__, v))


def _yaml(d, indent=0, path="", inside=()):
    """Block YAML of a dict (one key a line, so messages name a line). A list
    of dicts under a key repeats the key (scene files repeat `sphere:`).
    path: the keys above d ("observer."); inside: the ids of the dicts and
    lists above d, so that one that contains itself is a ValueError naming
    its key (not a RecursionError)."""
    pad = "  " * indent
    out = []
    inside = inside + (id(d),)
    for k, v in d.items():
        key = "%s%s" % (path, k)
        if isinstance(v, (dict, list, tuple)) and id(v) in inside:
            raise ValueError("scene: the value of %s contains itself" % key)
        if isinstance(v, dict):
            out.append("%s%s:\n%s" % (pad, k, _yaml(v, indent + 1, key + ".", inside)))
        elif isinstance(v, (list, tuple)) and v and all(isinstance(e, dict) for e in v):
            for e in v:
                if id(e) in inside:
                    raise ValueError("scene: the value of %s contains itself" % key)
                out.append("%s%s:\n%s" % (pad, k, _yaml(e, indent + 1, key + ".",
                                                         inside + (id(v),))))
        elif isinstance(v, (list, tuple, np.ndarray)):
            out.append("%s%s: [%s]\n" % (pad, k, ", ".join(_scalar(e) for e in v)))
        else:
            out.append("%s%s: %s\n" % (pad, k, _scalar(v)))
    return "".join(out)


def _file_args(v, what, dict_name, kind):
    """(text, is_path, name) of a YAML file given as a path or a dict of its
    keys (named dict_name in messages); what: the parameter, kind: the file."""
    if isinstance(v, dict):
        return _yaml(v), False, dict_name
    if isinstance(v, (str, bytes, os.PathLike)):
        path = os.fsdecode(v)
        return path, True, path
    raise ValueError("%s: expected a dict or the path of %s, got %s"
                     % (what, kind, type(v).__name__))


def _scene_args(scene):
    return _file_args(scene, "scene", "(scene dict)", "a YAML scene file")


def _config_text(config, others):
    sections = {}
    for k, v in config.items():
        if k not in CONFIG_KEYS:
            raise ValueError("unknown keyword argument '%s'; use any of %s, %s"
                             % (k, ", ".join(sorted(CONFIG_KEYS)), others))
        sec, key = CONFIG_KEYS[k].split(".")
        sections.setdefault(sec, {})[key] = v
    return _yaml(sections)


def _in_c_range(what, v):
    """An integer argument beyond the C library's 64-bit long is refused
    here, naming it (the C side would raise OverflowError without a name);
    within that range the C library checks the real limits."""
    if not -(2 ** 63) <= int(v) < 2 ** 63:
        raise ValueError("%s: %d is out of range (beyond 64 bits)" % (what, int(v)))


def _common(scene, width, height, frame, frames, config, others="frame, frames"):
    text, is_path, name = _scene_args(scene)
    for what, v in (("width", width), ("height", height), ("frame", frame), ("frames", frames)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
            raise ValueError("%s: expected an integer, got %r" % (what, v))
        _in_c_range(what, v)
    return dict(scene=text, is_path=is_path, name=name, config=_config_text(config, others),
                width=int(width), height=int(height), frame=int(frame), frames=int(frames))


_DTYPES = {"rgb": "u1", "redshift": "=f8", "outcome": "u1", "steps": "=u4", "err_mean": "=f8",
           "err_std": "=f8", "hit_r": "=f8", "hit_phi": "=f8", "bolometric": "=f8",
           "object": "=i2", "order": "=i2", "theta_turns": "=i2", "delay": "=f8"}


def backend_info():
    """What render(backend="auto") traces on here: a dict with cuda_built
    (whether this build carries the CUDA backend), gpu (the number of the
    GPU it would use, or None for the CPU) and why (why not a GPU: "no CUDA
    device found", "this build of curray has no CUDA support ...", ...; or
    a warning about skipped GPUs, or "")."""
    built, gpu, why = _curray._backend_info()
    return {"cuda_built": built, "gpu": gpu, "why": why}


def render(scene, width, height, frame=0, frames=1, backend="auto", **config):
    """Render frame `frame` of `frames` of `scene` at width x height pixels,
    with the GIL released.

    backend: as the command line's --backend: "auto" (a usable GPU when the
    build has CUDA and there is one, else the CPU), "cpu" (every core unless
    threads=N) or "cuda" (ValueError with the reason when no GPU can be
    used). One GPU: the first that the configuration enables and is usable
    (GPU 0 by default).

    scene: a dict with the keys of a scene file (README "Scene file"; a list
    of dicts under "sphere" gives several spheres) or the path of a YAML scene
    file. config: the raytracer settings of config.yml as keywords
    (CONFIG_KEYS: integrator, tolerance, samples, ..., threads).

    Returns a dict of arrays, row 0 at the top, column 0 at the left (the
    CSV's x, y): rgb (H, W, 3) uint8; redshift float64 (-1 where undefined,
    as in the CSV); outcome uint8 (codes into OUTCOMES); steps uint32;
    err_mean, err_std float64; hit_r, hit_phi float64 (-1 unless disc or
    sphere); bolometric float64 (g^4 F / F_max of a Keplerian disc hit, else
    -1, as in the CSV); object int16 (sphere index, disc face 0 top / 1
    bottom, -1); order, theta_turns int16 (the image order: equator
    crossings before the hit, or before the ray's end without one, and polar
    turning points before the same point; -1 where no ray was traced to an
    end, as in the CSV); delay float64 (the coordinate-time delay t_obs - t
    of a disc or sphere hit, renormalised for the observer at infinity; NaN
    otherwise, as the CSV's nan).
    Raises ValueError with the command line's message on bad input,
    MemoryError when the frame's arrays cannot fit in memory, and
    KeyboardInterrupt (the render stopped within about 0.25 s) on Ctrl-C.
    """
    args = _common(scene, width, height, frame, frames, config, "frame, frames, backend")
    if not isinstance(backend, str):
        raise ValueError("backend: expected auto, cpu or cuda, got %r" % (backend,))
    shape = (args["height"], args["width"])
    out = {}
    for k, buf in _curray._render(backend=backend, **args).items():
        out[k] = np.frombuffer(buf, dtype=_DTYPES[k]).reshape(shape + ((3,) if k == "rgb" else ()))
    return out


#: columns of each part of a spectrum (see spectrum), s_<k>.csv's after its
#: spectrum and bin columns (the continuum has no g)
SPECTRUM_COLUMNS = ("e_lo_kev", "e_hi_kev", "e_kev", "g", "flux", "normalised")


class Spectrum(dict):
    """A spectrum: line and continuum (dicts of arrays), energy_kev, rays,
    inner_rays, warning; also as attributes."""

    def __getattr__(self, k):
        try:
            return self[k]
        except KeyError:
            raise AttributeError(k) from None


def spectrum(scene, width, height, frame=0, frames=1, backend="auto", **config):
    """The observed spectrum of the Keplerian disc of frame `frame` of
    `frames` of `scene`, traced at width x height pixels as render traces it
    (with raytracer.samples = n > 1 every pixel's n x n sub-rays count): the
    values of the command line's s_<k>.csv (-t s) of the same render.
    Arguments as for render; the scene's spectrum key (spectrum.line:
    energy_kev, emissivity_index, bins, range; spectrum.continuum: f_col,
    bins, range) chooses the line and the bins, its defaults where absent.

    Returns a Spectrum (a dict, also with attributes):
    line: a dict of float64 arrays, one entry a bin: e_lo_kev, e_hi_kev (the
      bin's edges, keV), e_kev (its middle), g (e_kev / energy_kev), flux
      (the photon flux sum of g^3 r^-q dOmega per keV) and normalised (the
      profile per unit g, of integral 1 over g), and edges (the n + 1 edges);
    continuum: the same without g, e_kev the bin's geometric middle, flux
      the energy flux per keV (W m^-2 keV^-1; times (D/M)^2 for the observer
      at infinity), normalised of integral 1 over E in keV;
    energy_kev (the line's rest energy), rays (the rays that met the
    emitting disc), inner_rays (those between r_in and 2 r_in) and warning
    (the command line's console warning when too few rays cover the inner
    disc for a converged line profile, else None).
    Raises ValueError naming the key on bad input (a scene without a
    Keplerian disc: accretion; bad spectrum keys: spectrum.line.bins, ...).
    """
    args = _common(scene, width, height, frame, frames, config, "frame, frames, backend")
    if not isinstance(backend, str):
        raise ValueError("backend: expected auto, cpu or cuda, got %r" % (backend,))
    lraw, nl, craw, nc, e0, rays, inner, warning = _curray._spectrum(backend=backend, **args)
    out = Spectrum(energy_kev=e0, rays=rays, inner_rays=inner, warning=warning)
    for part, raw, n in (("line", lraw, nl), ("continuum", craw, nc)):
        a = np.frombuffer(raw, dtype="=f8").reshape(n, len(SPECTRUM_COLUMNS))
        d = {c: a[:, k].copy() for k, c in enumerate(SPECTRUM_COLUMNS)
             if not (part == "continuum" and c == "g")}
        d["edges"] = np.append(d["e_lo_kev"], d["e_hi_kev"][-1:])
        out[part] = d
    return out


class RayPath(dict):
    """The path of one ray: arrays under PATH_COLUMNS (also as attributes)
    and what the ray reports: outcome (a word of OUTCOMES), hit_r, hit_phi,
    redshift, steps."""

    def __getattr__(self, k):
        try:
            return self[k]
        except KeyError:
            raise AttributeError(k) from None


def trace(scene, pixel, width, height, frame=0, frames=1, **config):
    """The path of the ray of pixel (i, j) = (column from the left, row from
    the top) of the width x height image of `scene`, from the image's own
    trace loop (the same as curray --trace i,j). Arguments as for render.

    Returns a RayPath: param (affine parameter under rk4, Mino time under
    mino), t, r, theta, phi (BL; phi continuous), x, y, z (Cartesian), and
    ut, ur, utheta, uphi (dx^mu/dlambda of the backward tangent), one entry a
    point from the observer to the end; lengths in units of M.
    """
    try:
        i, j = pixel
    except (TypeError, ValueError):
        raise ValueError("pixel: expected (i, j), got %r" % (pixel,)) from None
    for v in (i, j):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
            raise ValueError("pixel: expected integers (i, j), got %r" % (pixel,))
        _in_c_range("pixel", v)
    args = _common(scene, width, height, frame, frames, config)
    raw, n, outcome, hit_r, hit_phi, redshift, steps = _curray._trace(i=int(i), j=int(j), **args)
    a = np.frombuffer(raw, dtype="<f8").reshape(n, len(PATH_COLUMNS))
    p = RayPath((c, a[:, k].copy()) for k, c in enumerate(PATH_COLUMNS))
    p.update(outcome=outcome, hit_r=hit_r, hit_phi=hit_phi, redshift=redshift, steps=steps)
    return p


#: columns of a worldline (see orbit), in the order of curray orbit's CSV
#: (whose u^t, u^r, u^theta, u^phi are ut, ur, utheta, uphi here)
ORBIT_COLUMNS = ("tau", "t", "r", "theta", "phi", "x", "y", "z", "ut", "ur", "utheta", "uphi")
_ENDS = {0: "span", 1: "horizon", 2: "escaped"}


def _orbit_args(spec, what):
    return _file_args(spec, what, "(orbit dict)", "an orbit file")


class Worldline(dict):
    """The arrays of a worldline by column name, also as attributes."""

    def __getattr__(self, k):
        try:
            return self[k]
        except KeyError:
            raise AttributeError(k) from None


def orbit(spec):
    """The worldline of a massive or charged particle, the rows of
    `curray orbit -s FILE` (docs/scenes.md, orbit files): spec is the path
    of an orbit file or a dict of its keys ({"metric": {...}, "particle":
    {...}}).

    Returns a Worldline: tau (proper time), t, r, theta, phi (BL; phi
    continuous), x, y, z (Cartesian) and ut, ur, utheta, uphi (the
    4-velocity), one entry a row, equal to the CSV's values; and E, L, K (the
    constants), ended ("span": followed for the whole proper time, "horizon",
    "escaped"), steps. Bad input raises ValueError with the command line's
    message.
    """
    raw, n, E, L, K, ended, steps = _curray._orbit(*_orbit_args(spec, "orbit"))
    a = np.frombuffer(raw, dtype="=f8").reshape(n, len(ORBIT_COLUMNS))
    w = Worldline((c, a[:, k].copy()) for k, c in enumerate(ORBIT_COLUMNS))
    w.update(E=E, L=L, K=K, ended=_ENDS.get(ended, str(ended)), steps=steps)
    return w


#: columns of an image of the lensed picture (see orbit_picture), those of
#: curray orbit -t c's orbit_image.csv
ORBIT_IMAGE_COLUMNS = ("tau", "t", "order", "i", "j", "t_obs", "visible", "row")
_ORBIT_MAX_SIDE = _C["orbit_max_side"]


class OrbitPicture(Worldline):
    """The lensed picture of an orbit (see orbit_picture), keys also attributes."""


def orbit_picture(spec, width=320, height=240):
    """The lensed picture of an orbit, what `curray orbit -s FILE -t c -x
    width -y height` writes (docs/scenes.md, "The lensed picture"): spec is
    an orbit file with a view section (a path, or a dict of its keys; a
    relative view.scene is taken from the orbit file's folder, or for a
    dict from the working directory).

    Returns an OrbitPicture (a dict whose keys are also attributes):
    rgb (height x width x 3 uint8, row 0 at the top: orbit.png's pixels) and
    the columns of orbit_image.csv, one entry an image: tau, t (the point of
    the worldline, units of M), order (int), i, j (pixel, the centre of
    pixel (I, J) at (I, J)), t_obs (when its light arrives), visible and row
    (bool); and points (the worldline points drawn), lost (points without
    an image, over the orders), solves (Newton solutions tried). The same C
    code as the command line's makes it. Bad input raises ValueError with
    the command line's message.
    """
    args = _orbit_args(spec, "orbit_picture")
    for what, v in (("width", width), ("height", height)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
            raise ValueError("%s: expected an integer, got %r" % (what, v))
        if not 1 <= v <= _ORBIT_MAX_SIDE:
            raise ValueError("%s: expected a size from 1 to %d pixels, got %d"
                             % (what, _ORBIT_MAX_SIDE, v))
    rgb, raw, n, points, lost, solves = _curray._orbit_picture(*args, int(width), int(height))
    a = np.frombuffer(raw, dtype="=f8").reshape(n, len(ORBIT_IMAGE_COLUMNS))
    p = OrbitPicture(rgb=np.frombuffer(rgb, dtype="u1").reshape(int(height), int(width), 3).copy())
    for k, c in enumerate(ORBIT_IMAGE_COLUMNS):
        col = a[:, k].copy()
        if c == "order":
            col = col.astype(np.int16)
        elif c in ("visible", "row"):
            col = col != 0
        p[c] = col
    p.update(points=points, lost=lost, solves=solves)
    return p
