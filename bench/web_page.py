#!/usr/bin/env python3
"""The browser explorer's speed in headless Chromium (bench/web.sh has the
per-ray cost in Node), side by side with the native build:

  per-ray   one wasm instance on the page's main thread tracing every pixel
            of the demo scene (320x180) in one call, against bench/web_bench.c
            built natively (NATIVE_BENCH, one thread), run alternately;
  preview   from a control change (the spin, 0 <-> 0.01) to the end of each
            progressive pass of a 320x180 view with the page's workers
            (navigator.hardwareConcurrency: 2 here): pass 1 (step 16) is the
            first full preview, every later pass a sharper one;
  1280x720  the same change, to the last pass (every pixel traced);
  look      a camera turn with looking around on at 1280x720: the view
            reprojected from the traced 1024x512 sky, per frame.

Wall times (performance.now), medians over the repeats; the machine's load
is printed, since other work shares it.

Usage: bench/web_page.py WEB_DIR NATIVE_BENCH [repeats]
(run with the system Python, which has Debian's python3-selenium)
"""
import os
import shutil
import statistics
import subprocess
import sys
import time

from selenium import webdriver
from selenium.webdriver.chrome.options import Options
from selenium.webdriver.chrome.service import Service


def load():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def main():
    web_dir, native = sys.argv[1], sys.argv[2]
    reps = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    o = Options()
    for a in ["--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1400,1000",
              "--disable-dev-shm-usage"]:
        o.add_argument(a)
    o.binary_location = shutil.which("chromium")
    d = webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=o)
    d.set_script_timeout(600)
    print("machine: %d cores, load %s; %s" % (os.cpu_count(), load(),
                                              d.capabilities.get("browserVersion", "")))
    try:
        d.get("file://" + os.path.abspath(os.path.join(web_dir, "index.html")))
        while not d.execute_script("return !!(window.crApp && window.crApp.started)"):
            time.sleep(0.1)
        d.execute_async_script("arguments[arguments.length - 1](); ")
        workers = d.execute_script("return window.crApp.nWorkers")

        # per-ray: wasm on the main thread vs native, alternately
        wasm, nat = [], []
        for r in range(reps):
            ns = d.execute_script(
                "const app = window.crApp, s = app.core.scene();"
                "crSceneApply(s, crDefaultScene(), null);"
                "if (s.frame(320, 180)) return -1;"
                "const pix = Int32Array.from({length: 320 * 180}, (_, k) => k);"
                "const t0 = performance.now(); s.trace(pix); const t1 = performance.now();"
                "return 1e6 * (t1 - t0) / pix.length;")
            wasm.append(ns)
            out = subprocess.run([native, "demo", "320", "180", "1"], capture_output=True,
                                 text=True, check=True).stdout
            nat.append(float([l for l in out.split("\n") if l.startswith("run")][0].split()[3]))
        print("per-ray, demo 320x180, 1 thread (wall ns a ray, median of %d): wasm in Chromium "
              "%.0f, native %.0f, ratio %.2f" % (reps, statistics.median(wasm),
                                                 statistics.median(nat),
                                                 statistics.median(wasm) / statistics.median(nat)))

        def change_and_wait(size):
            return d.execute_async_script(
                "const done = arguments[arguments.length - 1], app = window.crApp;"
                "const sz = document.getElementById('size');"
                "if (sz.value !== arguments[0]) { sz.value = arguments[0];"
                "  sz.dispatchEvent(new Event('change')); }"
                "app.whenDone().then(() => {"
                "  const a = document.querySelector('[data-key=\"metric.a\"]');"
                "  a.value = app.scene.metric.a === 0 ? '0.01' : '0';"
                "  a.dispatchEvent(new Event('input'));"
                "  app.whenDone().then((m) => { const r = app.renderer;"
                "    done([m, r.t0 - app.changeT0].concat(r.passTimes)); }); });", size)

        for size in ("320x180", "1280x720"):
            n = reps if size == "320x180" else max(2, reps // 2)
            rows = []
            for r in range(n):
                res = change_and_wait(size)
                if res[0]:
                    raise SystemExit("render failed: %r" % res[0])
                rows.append([res[1] + t for t in res[2:]])
            med = [statistics.median(c) for c in zip(*rows)]
            print("%s, %d workers, control change -> end of pass (steps 16, 8, 4, 2, 1), ms, "
                  "median of %d: %s" % (size, workers, n, ", ".join("%.0f" % m for m in med)))

        # looking around at 1280x720
        d.execute_async_script(
            "const done = arguments[arguments.length - 1], app = window.crApp;"
            "document.getElementById('look').checked = true; app.changed();"
            "app.skyDone.then(done);")
        sky_ms = d.execute_script("return window.crApp.skyRenderer.passTimes.slice(-1)[0]")
        ms = d.execute_script(
            "const app = window.crApp, out = [];"
            "for (let k = 0; k < 40; k++) { app.scene.observer.yaw = k; out.push(app.look()); }"
            "return out;")
        ms = [m for m in ms if m is not None and m >= 0]
        print("looking around, 1280x720 view from the 1024x512 sky (traced in %.0f ms): "
              "%d frames, median %.1f ms, max %.1f ms a frame" % (sky_ms, len(ms),
                                                                statistics.median(ms), max(ms)))
    finally:
        d.quit()
    print("load after: %s" % load())


if __name__ == "__main__":
    main()
