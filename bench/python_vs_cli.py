#!/usr/bin/env python3
"""curray.render against the command line on the same frame, side by side.

    <venv>/bin/python bench/python_vs_cli.py <curray binary> [runs] [width height] [scene]

Each run times, alternately, (a) the command line as a fresh process
(`curray -s scene -o tmp -x W -y H -t i -a true -q --threads 2 --backend cpu`:
load, render, write info.txt) and (b) `curray.render(scene, W, H, threads=2,
backend="cpu")` in this process (load, render, NumPy arrays of every CSV field). Prints the median
and smallest wall time of each, the ratio of the medians and the median of
the ratios of adjacent pairs (steadier on a loaded machine); the render itself is the same C code, so
the ratio shows the cost of the Python layer (argument conversion, the
pixel buffer, the arrays). The CPU time (user + sys of the child process,
of this process) is printed too: it is what the load of other work on the
machine inflates least.
"""
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import curray

bin_ = sys.argv[1]
runs = int(sys.argv[2]) if len(sys.argv) > 2 else 7
w, h = (int(sys.argv[3]), int(sys.argv[4])) if len(sys.argv) > 4 else (640, 480)
here = os.path.dirname(os.path.abspath(__file__))
scene = sys.argv[5] if len(sys.argv) > 5 else os.path.join(here, "..", "scenes", "demo.yml")

cli, py, cli_cpu, py_cpu = [], [], [], []


def cpu(who):
    r = resource.getrusage(who)
    return r.ru_utime + r.ru_stime


with tempfile.TemporaryDirectory() as tmp:
    cmd = [bin_, "-s", scene, "-o", tmp, "-x", str(w), "-y", str(h), "-t", "i", "-a", "true",
           "-q", "--threads", "2", "--backend", "cpu"]
    subprocess.run(cmd, check=True)  # warm-up (page cache)
    curray.render(scene, w, h, threads=2, backend="cpu")
    for _ in range(runs):
        t0, c0 = time.perf_counter(), cpu(resource.RUSAGE_CHILDREN)
        subprocess.run(cmd, check=True)
        cli.append(time.perf_counter() - t0)
        cli_cpu.append(cpu(resource.RUSAGE_CHILDREN) - c0)
        t0, c0 = time.perf_counter(), cpu(resource.RUSAGE_SELF)
        img = curray.render(scene, w, h, threads=2, backend="cpu")
        py.append(time.perf_counter() - t0)
        py_cpu.append(cpu(resource.RUSAGE_SELF) - c0)
mc, mp = statistics.median(cli), statistics.median(py)
print("scene %s, %dx%d, 2 threads, %d runs each, alternating" % (os.path.relpath(scene), w, h,
                                                                  runs))
print("command line (-t i), median %.3f s  [%s]" % (mc, " ".join("%.3f" % t for t in cli)))
print("curray.render,       median %.3f s  [%s]" % (mp, " ".join("%.3f" % t for t in py)))
print("smallest: command line %.3f s, curray.render %.3f s" % (min(cli), min(py)))
print("ratio curray.render / command line: medians %.3f, median of pairs %.3f"
      % (mp / mc, statistics.median(b / a for a, b in zip(cli, py))))
print("CPU time (user + sys, all threads; the load inflates it less): command line median "
      "%.3f s, curray.render median %.3f s, ratio %.3f"
      % (statistics.median(cli_cpu), statistics.median(py_cpu),
         statistics.median(py_cpu) / statistics.median(cli_cpu)))
print("mean steps a ray: %.1f" % img["steps"].mean())
