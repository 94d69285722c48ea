#!/usr/bin/env python3
"""bench/mino_report.py: the markdown report of bench/mino.sh.

Usage: mino_report.py RUNS_CSV CASES_CSV OUT_PREFIX
RUNS_CSV: case,part,kind,run,wall_s,user_s,sys_s,maxrss_kb,frame_s,steps,rays,load1_before
  kind: time (timed, -t i), csv (the -t id run for the classes), base (the
  same case at 1x1: start-up, scene and exit, for (b)).
CASES_CSV: case|part|label|scene|config|width|height|threads|runs|csv_timed
  (csv_timed 1: the csv run counts as a timed run; the rk4 cases).
OUT_PREFIX-compare-A-vs-B.txt: key=value lines of bench/compare_classes.py.
Medians throughout; ratios are of the medians. Standard library only.
"""
import csv
import os
import statistics
import sys

med = statistics.median


def main():
    runs_csv, cases_csv, prefix = sys.argv[1:4]
    rows = list(csv.DictReader(open(runs_csv)))
    cases = []
    with open(cases_csv) as f:
        head = f.readline().strip().split("|")
        for line in f:
            cases.append(dict(zip(head, line.rstrip("\n").split("|"))))
    byname = {c["case"]: c for c in cases}

    def samples(name, kind):
        return [r for r in rows if r["case"] == name and r["kind"] == kind]

    def timed(name):
        t = samples(name, "time")
        if byname[name].get("csv_timed") == "1":
            t = samples(name, "csv") + t
        return t

    def stat(name, kind=None):
        rs = samples(name, kind) if kind else timed(name)
        if not rs:
            return None
        cpu = [float(r["user_s"]) + float(r["sys_s"]) for r in rs]
        return {
            "n": len(rs),
            "wall": med([float(r["wall_s"]) for r in rs]),
            "wall_min": min(float(r["wall_s"]) for r in rs),
            "wall_max": max(float(r["wall_s"]) for r in rs),
            "frame": med([float(r["frame_s"]) for r in rs]),
            "cpu": med(cpu),
            "steps": int(rs[0]["steps"]),
            "rays": int(rs[0]["rays"]),
            "steps_same": len(set(r["steps"] for r in rs)) == 1,
            "load": med([float(r["load1_before"]) for r in rs]),
        }

    def compare(a, b):
        p = "%s-compare-%s-vs-%s.txt" % (prefix, a, b)
        if not os.path.exists(p):
            return None
        d = {}
        for line in open(p):
            if "=" in line and not line.startswith("|"):
                k, _, v = line.strip().partition("=")
                d[k] = v
        return d

    def cmp_cell(a, b):
        d = compare(a, b)
        if d is None:
            return "n/a"
        n, dis, edge = int(d["pixels"]), int(d["disagree"]), int(d["disagree_on_edges"])
        if dis == 0:
            return "0"
        return "%d (%.3f %%; %d on edges)" % (dis, 100.0 * dis / n, edge)

    parts = [c["part"] for c in cases]

    if "a" in parts:
        m, k = stat("a-mino"), stat("a-rk4")
        c = byname["a-mino"]
        print("### (a) `make demo`'s scene (scenes/demo.yml), %sx%s, %s threads" % (c["width"], c["height"], c["threads"]))
        print()
        print("| integrator | runs | wall time, median [min-max] (s) | frame time (info.txt) (s) | CPU time user+sys (s) | steps/ray | CPU-ns/step | load |")
        print("|---|---|---|---|---|---|---|---|")
        for name, s in (("a-mino", m), ("a-rk4", k)):
            print("| %s | %d | %.3f [%.3f-%.3f] | %.3f | %.3f | %.1f | %.0f | %.2f |" % (
                byname[name]["label"], s["n"], s["wall"], s["wall_min"], s["wall_max"], s["frame"], s["cpu"],
                s["steps"] / s["rays"], 1e9 * s["cpu"] / s["steps"], s["load"]))
        print()
        print("Speed-up rk4 / mino: **%.1fx** in wall time (process), %.1fx in frame time, %.1fx in CPU time "
              "(the target: >= 50x in wall time). Pixels classed differently, mino vs rk4: %s." % (
                  k["wall"] / m["wall"], k["frame"] / m["frame"], k["cpu"] / m["cpu"], cmp_cell("a-mino", "a-rk4")))
        print()

    if "b" in parts:
        names = [c["case"] for c in cases if c["part"] == "b"]
        c0 = byname[names[0]]
        print("### (b) a = 0.9, 85 deg, static observer at r = 100, disc 6-15, %sx%s, 1 thread" % (c0["width"], c0["height"]))
        print()
        print("| integrator | runs | CPU per ray (us) | steps/ray (max) | CPU-ns/step | frame CPU, whole process (s) | 1x1 run CPU (s) | classed differently from rk4 | from rk4 c = 1/128 |")
        print("|---|---|---|---|---|---|---|---|---|")
        for name in names:
            s, b = stat(name), stat(name, "base")
            net = s["cpu"] - (b["cpu"] if b else 0.0)
            mx = [r for r in rows if r["case"] == name and r["kind"] != "base"]
            print("| %s | %d | **%.2f** | %.1f | %.0f | %.4f | %.4f | %s | %s |" % (
                byname[name]["label"], s["n"], 1e6 * net / s["rays"], s["steps"] / s["rays"],
                1e9 * net / s["steps"], s["cpu"], b["cpu"] if b else float("nan"),
                "-" if name == "b-rk4" else ("(reference)" if name == "b-ref" else cmp_cell(name, "b-rk4")),
                "(reference)" if name == "b-ref" else cmp_cell(name, "b-ref")))
        print()
        print("CPU per ray = (median CPU time of the frame - median CPU time of the same run at 1x1) / rays; "
              "CPU-ns/step likewise per step. The rk4 runs include their class run (-t id); the reference ran once.")
        print()

    if "c" in parts:
        s30, s6, si = stat("c-r30"), stat("c-r1e6"), stat("c-inf")
        c = byname["c-r30"]
        print("### (c) distance: the same +-20 M plane from r = 30, r = 1e6 and r = inf; mino; %sx%s, %s threads" % (
            c["width"], c["height"], c["threads"]))
        print()
        print("| observer | runs | wall time, median [min-max] (s) | CPU time (s) | steps/ray | CPU time / r = 30 | wall time / r = 30 |")
        print("|---|---|---|---|---|---|---|")
        for name, s in (("c-r30", s30), ("c-r1e6", s6), ("c-inf", si)):
            print("| %s | %d | %.3f [%.3f-%.3f] | %.3f | %.1f | **%.2f** | %.2f |" % (
                byname[name]["label"], s["n"], s["wall"], s["wall_min"], s["wall_max"], s["cpu"],
                s["steps"] / s["rays"], s["cpu"] / s30["cpu"], s["wall"] / s30["wall"]))
        print()
        print("Target: r = 1e6 costs at most 1.5x r = 30. Classes, r = 1e6 vs r = inf: %s." % cmp_cell("c-r1e6", "c-inf"))
        print()

    print("Timed runs write info.txt only; wall time = the whole process (time.perf_counter around it), "
          "CPU time = user+sys of the process (wait4), frame time = info.txt's. Runs: %s; comparisons: %s-compare-*.txt." % (
              runs_csv, prefix))
    for name in sorted(set(r["case"] for r in rows)):
        s = stat(name)
        if s and not s["steps_same"]:
            print("Note: %s took different step counts in different runs." % name)


if __name__ == "__main__":
    main()
