#!/usr/bin/env python3
"""The browser explorer (build/web) in headless Chromium, against the
command line.

1. The page loads from file:// with no console error and renders its demo
   scene (scenes/demo.yml's values).
2. For each scene below (the demo; a Kerr hole with a keplerian disc and the
   shipped sky.png; a moving observer's fisheye with sky_grid.png and a
   sphere; the observer at infinity; Kerr-Newman with an orbiting observer):
   the page imports it, renders it, and its pixels equal the command line's
   render of the YAML the page exports, at the same size: every pixel's
   outcome identical, every colour channel within 1 level (d_0.csv of
   curray -t d holds both), and the page's redshift and bolometric views
   equal to r_0.png and b_0.png within 1 level.
3. Every control changes the exported YAML as documented (CONTROLS), and a
   bad value (a spin without a horizon, an orbit that does not exist) shows
   the command line's own message for the exported file.
4. A screenshot of the page (README) into OUT_DIR/screenshot.png.

Usage: test_web_page.py CURRAY WEB_DIR SCENES_DIR OUT_DIR
Prints "SKIPPED: ..." (and exits 0) when Chromium, chromedriver or Selenium is
missing.
"""
import base64
import csv
import os
import shutil
import subprocess
import sys
import time
import zlib

try:
    from selenium import webdriver
    from selenium.webdriver.chrome.options import Options
    from selenium.webdriver.chrome.service import Service
except ImportError:
    print("SKIPPED: Python's selenium is missing (Debian: python3-selenium), for %s" % sys.executable)
    sys.exit(0)

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
DRIVER = shutil.which("chromedriver")

SCENES = {
    "demo": None,  # the page's own start-up scene
    "kerr-keplerian-sky": """
metric:
  m: 1
  a: 0.9
  q: 0
observer:
  r: 40
  theta: 80 deg
  phi: 0
  hfov: 40 deg
accretion:
  model: keplerian
  radius: [20]
  temperature: 8000
skymap:
  image: sky.png
""",
    "fisheye-infall-grid": """
metric:
  m: 1
  a: 0.5
  q: 0.3
observer:
  r: 12
  theta: 70
  phi: 30
  hfov: 200
  motion: infall
  projection: fisheye
  yaw: 20
accretion:
  color1: [255, 128, 0]
  resolution: [3, 16]
  radius: [4, 11]
skymap:
  image: sky_grid.png
  boundary: 50
sphere:
  color: [0, 0, 255]
  resolution: [4, 8]
  r: 9
  theta: 90
  phi: 60
  radius: 1.5
horizon_color: [40, 40, 40]
""",
    "infinity": """
metric:
  m: 1
  a: 0.99
  q: 0
observer:
  r: inf
  theta: 60 deg
  phi: 0
  hextent: 24
  roll: 10
accretion:
  color1: [0, 255, 0]
  resolution: [2, 12]
  radius: [3, 12]
sky_color: [20, 20, 60]
""",
    "kn-velocity-redshift-sky": """
metric:
  m: 1
  a: 0.6
  q: 0.5
observer:
  r: 15
  theta: 90
  phi: 0
  hfov: 80
  motion: [0.1, 0, 0.4]
accretion:
  model: keplerian
  radius: [3, 14]
  retrograde: true
skymap:
  image: sky.png
redshift_sky: true
""",
}

# the README's screenshot: a spinning hole's keplerian disc on the sky
SCREENSHOT = """
metric:
  m: 1
  a: 0.9
  q: 0
observer:
  r: 30
  theta: 84 deg
  phi: 0
  hfov: 45 deg
accretion:
  model: keplerian
  radius: [18]
  temperature: 9000
skymap:
  image: sky.png
horizon_color: [0, 0, 0]
"""

# looking around: the reprojected view's agreement with the traced one
LOOK_AGREE = 0.95

# cr_outcome's values, as d_<k>.csv names them
OUTCOMES = ["none", "horizon", "disc", "sphere", "sky", "error", "limit", "outside"]

# control (CSS selector), value, a line the exported YAML then holds
CONTROLS = [
    ('[data-key="metric.a"]', "0.7", "  a: 0.7"),
    ('[data-key="metric.q"]', "0.2", "  q: 0.2"),
    ("#obs-r", "25", "  r: 25"),
    ('[data-key="observer.theta"]', "60", "  theta: 60 deg"),
    ('[data-key="observer.phi"]', "15", "  phi: 15 deg"),
    ('[data-key="observer.hfov"]', "50", "  hfov: 50 deg"),
    ('[data-key="observer.roll"]', "5", "  roll: 5 deg"),
    ('[data-key="observer.pitch"]', "-3", "  pitch: -3 deg"),
    ('[data-key="observer.yaw"]', "4", "  yaw: 4 deg"),
    ('[data-key="observer.motion"]', "zamo", "  motion: zamo"),
    ('[data-key="observer.motion"]', "velocity", "  motion: [0, 0, 0]"),
    ('[data-key="observer.v.2"]', "0.3", "  motion: [0, 0, 0.3]"),
    ('[data-key="observer.motion"]', "static", None),
    ('[data-key="observer.projection"]', "fisheye", "  projection: fisheye"),
    ('[data-key="observer.projection"]', "rectilinear", None),
    ('[data-key="accretion.color1"]', "#ff8000", "  color1: [255, 128, 0]"),
    ('[data-key="accretion.resolution.0"]', "3", "  resolution: [3, 12]"),
    ('[data-key="accretion.resolution.1"]', "8", "  resolution: [3, 8]"),
    ("#disc-rin", "7", "  radius: [7, 15]"),
    ('[data-key="accretion.r_out"]', "18", "  radius: [7, 18]"),
    ('[data-key="accretion.model"]', "keplerian", "  model: keplerian"),
    ("#disc-rin-isco", True, "  radius: [18]"),
    ('[data-key="accretion.temperature"]', "6000", "  temperature: 6000"),
    ('[data-key="accretion.retrograde"]', True, "  retrograde: true"),
    ('[data-key="accretion.inside_isco"]', "plunging", "  inside_isco: plunging"),
    ('[data-key="accretion.enabled"]', False, None),
    ("#sky-image", "sky_grid.png", "  image: sky_grid.png"),
    ("#sky-b-inf", False, "  boundary: "),
    ("#sky-b", "80", "  boundary: 80"),
    ('[data-key="sky_color"]', "#102030", "sky_color: [16, 32, 48]"),
    ('[data-key="horizon_color"]', "#000000", "horizon_color: [0, 0, 0]"),
    ('[data-key="redshift_sky"]', True, "redshift_sky: true"),
    ("#obs-r-inf", True, "  r: inf"),
    ('[data-key="observer.hextent"]', "20", "  hextent: 20"),
]

# (control, value, scene key path) that the core refuses
BAD = [
    ('[data-key="metric.a"]', "1.2", "no event horizon"),
    ('[data-key="observer.motion"]', "orbit", "no timelike circular orbit"),
]


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def browser():
    o = Options()
    for a in ["--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1400,1000",
              "--disable-dev-shm-usage"]:
        o.add_argument(a)
    o.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    o.binary_location = CHROMIUM
    return webdriver.Chrome(service=Service(DRIVER), options=o)


def wait_done(d, what, timeout=120):
    msg = d.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "const t = setTimeout(() => done('TIMEOUT'), %d);"
        "window.crApp.whenDone().then((m) => { clearTimeout(t); done(m); });" % (timeout * 1000))
    if msg == "TIMEOUT":
        fail("%s: the page did not finish rendering in %d s" % (what, timeout))
    return msg


def console_errors(d):
    return [e for e in d.get_log("browser") if e.get("level") == "SEVERE"]


def page_pixels(d):
    r = d.execute_script(
        "const r = window.crApp.renderer;"
        "const bin = (a) => { let s = ''; for (let i = 0; i < a.length; i += 8192)"
        "  s += String.fromCharCode.apply(null, a.subarray(i, i + 8192)); return btoa(s); };"
        "return [r.width, r.height, bin(r.outcome), bin(r.rgb), bin(r.level)];")
    w, h = r[0], r[1]
    return w, h, base64.b64decode(r[2]), base64.b64decode(r[3]), base64.b64decode(r[4])


def read_png(path):
    """(width, height, rows of bytes RGB) of an 8-bit RGB or RGBA PNG, not
    interlaced (what curray writes)."""
    with open(path, "rb") as f:
        data = f.read()
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        n = int.from_bytes(data[pos:pos + 4], "big")
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h = int.from_bytes(body[0:4], "big"), int.from_bytes(body[4:8], "big")
            depth, ctype, interlace = body[8], body[9], body[12]
            if depth != 8 or ctype not in (2, 6) or interlace:
                fail("%s: unexpected PNG format" % path)
            bpp = 3 if ctype == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows, prev = [], bytearray(stride)
    for y in range(h):
        ft, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if ft == 1:
                line[i] = (line[i] + a) & 255
            elif ft == 2:
                line[i] = (line[i] + b) & 255
            elif ft == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif ft == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line[i] for i in range(stride) if i % bpp < 3))
        prev = line
    return w, h, rows


def cli_render(curray, yaml_text, work, scenes_dir, w, h, maps=False, own=None):
    os.makedirs(work, exist_ok=True)
    for t in ("sky.png", "sky_grid.png"):
        shutil.copyfile(os.path.join(scenes_dir, t), os.path.join(work, t))
    if own:  # the user's own sky image, next to the scene file
        shutil.copyfile(own, os.path.join(work, os.path.basename(own)))
    with open(os.path.join(work, "scene.yml"), "w") as f:
        f.write(yaml_text)
    out = os.path.join(work, "out")
    shutil.rmtree(out, ignore_errors=True)
    p = subprocess.run([curray, "-s", os.path.join(work, "scene.yml"), "-o", out, "-x", str(w),
                        "-y", str(h), "-t", "dcrb" if maps else "d", "-q", "true", "-a", "true", "--backend", "cpu"],
                       capture_output=True, text=True)
    return p, os.path.join(out, "d_0.csv")


def compare(name, d, curray, scenes_dir, out_dir, own=None):
    w, h, outcome, rgb, level = page_pixels(d)
    if any(v == 255 for v in level):
        fail("%s: the page's render is not complete (pixels not traced)" % name)
    yaml_text = d.execute_script("return window.crApp.yaml();")
    p, path = cli_render(curray, yaml_text, os.path.join(out_dir, name), scenes_dir, w, h, True, own)
    if p.returncode != 0:
        fail("%s: curray refused the exported YAML: %s\n%s" % (name, p.stderr, yaml_text))
    n_out = n_col = worst = 0
    first = []
    counts = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            x, y = int(row["x"]), int(row["y"])
            k = y * w + x
            oc = OUTCOMES.index(row["outcome"])
            counts[oc] = counts.get(oc, 0) + 1
            diff = max(abs(int(row[c]) - rgb[9 * k + i]) for i, c in enumerate("rgb"))
            worst = max(worst, diff)
            if oc != outcome[k]:
                n_out += 1
            if diff > 1:
                n_col += 1
            if (oc != outcome[k] or diff > 1) and len(first) < 5:
                first.append("(%d, %d): cli outcome %d rgb %s,%s,%s; page outcome %d rgb %d,%d,%d" % (
                    x, y, oc, row["r"], row["g"], row["b"], outcome[k], rgb[9 * k], rgb[9 * k + 1],
                    rgb[9 * k + 2]))
    # the redshift and bolometric views against r_0.png and b_0.png
    maps = []
    for view, letter in ((1, "r"), (2, "b")):
        png = os.path.join(os.path.dirname(path), "%s_0.png" % letter)
        if not os.path.exists(png):
            continue
        pw, ph, rows = read_png(png)
        off = sum(1 for y in range(ph) for x in range(pw)
                  if max(abs(rows[y][3 * x + c] - rgb[9 * (y * w + x) + 3 * view + c])
                         for c in range(3)) > 1)
        maps.append("%s_0.png: %d pixels off by more than 1" % (letter, off))
        if off:
            fail("%s: the page's %s view differs from %s_0.png in %d pixels" % (
                name, "redshift" if view == 1 else "bolometric", letter, off))
    print("%s: %dx%d, outcomes %s: %d outcomes differ, %d colours off by more than 1, worst "
          "channel difference %d; %s" % (name, w, h, counts, n_out, n_col, worst, ", ".join(maps)))
    if n_out or n_col:
        fail("%s: the page and the command line differ:\n  %s" % (name, "\n  ".join(first)))
    return p


def own_sky(d, curray, scenes_dir, out_dir):
    """The user's own sky image, chosen through the page's file input (a
    copy of sky_grid.png under another name, a new PNG to the page): the
    YAML names it, and the render equals the command line's with the image
    next to the scene file."""
    own = os.path.join(out_dir, "my_sky.png")
    shutil.copyfile(os.path.join(scenes_dir, "sky_grid.png"), own)
    d.execute_script("window.crApp.scene = crDefaultScene(); window.crApp.sky = null;"
                     "window.crApp.scene.metric.a = 0.8; window.crApp.show(); window.crApp.changed();")
    wait_done(d, "own sky: before")
    d.execute_script("window.crApp.renderDone = new Promise((res) => { window.crApp.resolveRender = res; });")
    d.find_element("id", "sky-file").send_keys(own)
    t0 = time.time()
    while "image: my_sky.png" not in d.execute_script("return window.crApp.yaml();"):
        if time.time() - t0 > 30:
            fail("own sky: the YAML never named my_sky.png")
        time.sleep(0.1)
    if wait_done(d, "own sky"):
        fail("own sky: the page says %r" % d.execute_script(
            "return document.getElementById('message').textContent"))
    compare("own-sky", d, curray, scenes_dir, out_dir, own)


def http_load(index_dir):
    """The page served by python3 -m http.server loads and renders with no
    console error."""
    import socket
    sock = socket.socket()
    sock.bind(("127.0.0.1", 0))
    port = sock.getsockname()[1]
    sock.close()
    srv = subprocess.Popen([sys.executable, "-m", "http.server", str(port), "--bind", "127.0.0.1"],
                           cwd=index_dir, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    d = browser()
    try:
        t0 = time.time()
        while True:
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError:
                if time.time() - t0 > 20:
                    fail("http.server did not start")
                time.sleep(0.2)
        d.set_script_timeout(120)
        d.get("http://127.0.0.1:%d/" % port)
        t0 = time.time()
        while not d.execute_script("return !!(window.crApp && window.crApp.started)"):
            if time.time() - t0 > 30:
                fail("over http: the page did not start: %s" % console_errors(d))
            time.sleep(0.1)
        msg = wait_done(d, "over http")
        errs = console_errors(d)
        if msg or errs:
            fail("over http: %r %s" % (msg, errs))
        print("over http (python3 -m http.server): loaded and rendered, no console error")
    finally:
        d.quit()
        srv.terminate()
        srv.wait()


def look_around(d):
    """Drag on the picture with looking around on: the view is reprojected
    from the equirectangular sky (no ray traced), then traced when the
    pointer is let go. The reprojected and the traced view of the same yaw
    agree but for the edges that nearest-pixel sampling of the 1024 x 512 sky
    moves: at least LOOK_AGREE of the pixels within 16 levels."""
    d.execute_script("window.crApp.scene = crDefaultScene(); window.crApp.sky = null;"
                     "window.crApp.show(); document.getElementById('look').checked = true;"
                     "window.crApp.changed();")
    wait_done(d, "look-around view")
    msg = d.execute_async_script("const done = arguments[arguments.length - 1];"
                                 "window.crApp.skyDone.then(done);")
    if msg:
        fail("looking around: the sky render says %r" % msg)
    r = d.execute_script(
        "const app = window.crApp, c = app.canvas, b = c.getBoundingClientRect();"
        "const ev = (t, x) => new PointerEvent(t, {clientX: b.left + x, clientY: b.top + 100,"
        "  pointerId: 1, bubbles: true});"
        "c.dispatchEvent(ev('pointerdown', 100));"
        "window.dispatchEvent(ev('pointermove', 100 + 20 * b.width / app.scene.observer.hfov));"
        "const img = app.lookImage.data.slice();"
        "const yaw = app.scene.observer.yaw, ms = app.lookMs;"
        "window.dispatchEvent(ev('pointerup', 0));"
        "let s = ''; for (let i = 0; i < img.length; i += 8192)"
        "  s += String.fromCharCode.apply(null, img.subarray(i, i + 8192));"
        "return [yaw, ms, btoa(s)];")
    yaw, ms, look = r[0], r[1], base64.b64decode(r[2])
    if abs(yaw - 20) > 0.5 or ms is None or ms < 0:
        fail("looking around: the drag gave yaw %r, reprojection %r ms" % (yaw, ms))
    if wait_done(d, "view after the drag"):
        fail("looking around: the view after the drag did not render")
    y = d.execute_script("return window.crApp.yaml();")
    if "  yaw: 20 deg" not in y.split("\n"):
        fail("looking around: the YAML has no yaw: 20 deg line:\n" + y)
    w, h, outcome, rgb, level = page_pixels(d)
    agree = sum(1 for k in range(w * h)
                if max(abs(look[4 * k + c] - rgb[9 * k + c]) for c in range(3)) <= 16)
    frac = agree / float(w * h)
    print("looking around: drag to yaw %.2f deg, reprojected in %.1f ms; %.4f of the pixels "
          "within 16 levels of the traced view" % (yaw, ms, frac))
    if frac < LOOK_AGREE:
        fail("looking around: only %.4f of the reprojected pixels match the traced view" % frac)
    d.execute_script("document.getElementById('look').checked = false;")


def set_control(d, sel, value):
    ok = d.execute_script(
        "const c = document.querySelector(arguments[0]); if (!c) return false;"
        "if (typeof arguments[1] === 'boolean') c.checked = arguments[1]; else c.value = arguments[1];"
        "const ev = (c.tagName === 'SELECT' || c.type === 'checkbox' || c.type === 'color') ? 'change' : 'input';"
        "c.dispatchEvent(new Event(ev)); return true;", sel, value)
    if not ok:
        fail("no control %s" % sel)


def main():
    curray, web_dir, scenes_dir, out_dir = sys.argv[1:5]
    if not CHROMIUM or not DRIVER:
        print("SKIPPED: Chromium or chromedriver not found (Debian: chromium chromium-driver)")
        return 0
    index = os.path.join(web_dir, "index.html")
    if not os.path.exists(index):
        fail("no page at %s (build the curray_wasm target)" % index)
    os.makedirs(out_dir, exist_ok=True)
    d = browser()
    try:
        d.set_script_timeout(300)
        d.get("file://" + os.path.abspath(index))
        t0 = time.time()
        started = "return !!(window.crApp && window.crApp.started)"
        while not d.execute_script(started) and time.time() - t0 < 30:
            time.sleep(0.1)
        if not d.execute_script(started):
            fail("the page did not start: %s" % console_errors(d))
        d.execute_script("document.getElementById('size').value = '320x240';"
                         "document.getElementById('size').dispatchEvent(new Event('change'));")
        msg = wait_done(d, "demo")
        if msg:
            fail("demo: the page says %r" % msg)
        errs = console_errors(d)
        if errs:
            fail("console errors on load: %s" % errs)
        for name, text in SCENES.items():
            if text is not None:
                ok = d.execute_script("return window.crApp.importYaml(arguments[0], 'scene.yml');", text)
                if not ok:
                    fail("%s: the page refused the scene: %s" % (
                        name, d.execute_script("return document.getElementById('message').textContent")))
                msg = wait_done(d, name)
                if msg:
                    fail("%s: the page says %r" % (name, msg))
            compare(name, d, curray, scenes_dir, out_dir)
        own_sky(d, curray, scenes_dir, out_dir)
        look_around(d)
        # controls, from the demo scene again
        d.execute_script("window.crApp.scene = crDefaultScene(); window.crApp.sky = null;"
                         "window.crApp.show(); window.crApp.changed();")
        for sel, value, line in CONTROLS:
            set_control(d, sel, value)
            y = d.execute_script("return window.crApp.yaml();")
            if line is not None and line not in y.split("\n") and not (
                    line.endswith(": ") and any(l.startswith(line) for l in y.split("\n"))):
                fail("control %s = %r: the YAML has no line %r:\n%s" % (sel, value, line, y))
        print("%d control changes: each gives its YAML line" % len(CONTROLS))
        # bad values: the command line's message
        for sel, value, words in BAD:
            d.execute_script("window.crApp.scene = crDefaultScene(); window.crApp.sky = null;"
                             "window.crApp.show(); window.crApp.changed();")
            if sel.endswith('motion"]'):
                set_control(d, '[data-key="observer.theta"]', "90")
                set_control(d, "#obs-r", "2.5")
            set_control(d, sel, value)
            shown = d.execute_script("return document.getElementById('message').textContent")
            y = d.execute_script("return window.crApp.yaml();")
            p, _ = cli_render(curray, y, os.path.join(out_dir, "bad"), scenes_dir, 32, 24)
            if p.returncode == 0:
                fail("%s = %s: the command line accepted the exported YAML" % (sel, value))
            if not shown or words not in shown:
                fail("%s = %s: the page shows %r, expected a message about %r" % (sel, value, shown, words))
            # the CLI names the path it was given; the page names scene.yml
            cli_msg = p.stderr.strip().replace(os.path.join(out_dir, "bad", ""), "")
            if shown not in cli_msg:
                fail("%s = %s: the page's message\n  %s\nis not the command line's\n  %s" % (
                    sel, value, shown, cli_msg))
            print("bad value %s = %s: the page shows the command line's message: %s" % (sel, value, shown))
        # the screenshot for the README: the keplerian disc on the sky
        d.execute_script("document.getElementById('size').value = '640x360';"
                         "document.getElementById('size').dispatchEvent(new Event('change'));")
        d.execute_script("return window.crApp.importYaml(arguments[0], 'scene.yml');", SCREENSHOT)
        wait_done(d, "screenshot")
        d.execute_script("document.getElementById('view').dispatchEvent(new MouseEvent('mousemove',"
                         "{clientX: document.getElementById('view').getBoundingClientRect().left + 250,"
                         " clientY: document.getElementById('view').getBoundingClientRect().top + 200}));")
        readout = d.execute_script("return document.getElementById('readout').textContent")
        if "disc" not in readout and "sky" not in readout and "horizon" not in readout:
            fail("cursor readout shows %r" % readout)
        print("cursor readout: " + readout)
        d.set_window_size(1280, 820)
        d.save_screenshot(os.path.join(out_dir, "screenshot.png"))
        errs = console_errors(d)
        if errs:
            fail("console errors: %s" % errs)
    finally:
        d.quit()
    http_load(web_dir)
    print("PASSED")
    return 0


if __name__ == "__main__":
    sys.exit(main())
