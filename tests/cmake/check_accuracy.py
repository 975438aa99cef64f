#!/usr/bin/python3
"""Checks `candela bench accuracy --quick` output (results.csv): a row for every effect, finite
errors and times, error never rising with more samples beyond the reference's noise (SSAO, RSM,
the ray tracer's own convergence), and Pareto flags that agree with the numbers."""
import csv
import math
import re
import sys

rows = list(csv.DictReader(open(sys.argv[1])))
problems = []
effects = {r["effect"] for r in rows}
for e in ["shadows", "shadows_colour", "area_lights", "ssao", "rsm", "gi", "transparency", "reflections", "dof", "aa", "motion_blur", "forward_deferred", "ray_tracer", "ray_tracer_depth"]:
    if e not in effects:
        problems.append(f"no rows for {e}")

def f(r, k):
    return float(r[k]) if r[k] != "" else math.nan

for r in rows:
    if not (f(r, "ms") > 0 and math.isfinite(f(r, "ms"))):
        problems.append(f"{r['effect']} {r['variant']}: time {r['ms']!r} is not a positive number")
    if r["effect"] != "forward_deferred":
        for k in ("rmse", "relmse", "max", "pct_over", "ref_noise"):
            if not math.isfinite(f(r, k)) or f(r, k) < 0:
                problems.append(f"{r['effect']} {r['variant']}: {k} {r[k]!r} is not a finite non-negative number")

def monotone(effect, key):
    groups = {}
    for r in rows:
        if r["effect"] != effect:
            continue
        n, rest = key(r["variant"])
        groups.setdefault(rest, []).append((n, f(r, "rmse"), f(r, "ref_noise"), r["variant"]))
    checked = 0
    for rest, g in groups.items():
        g.sort()
        for (n0, e0, noise, v0), (n1, e1, _, v1) in zip(g, g[1:]):
            checked += 1
            if e1 > e0 + noise + 1e-9:
                problems.append(f"{effect}: '{v1}' has error {e1:.5g} > '{v0}' {e0:.5g} + noise {noise:.3g}")
    if checked == 0:
        problems.append(f"{effect}: no pair of rows differing only in sample count")

def samples_key(v):
    m = re.match(r"(\d+) (samples|spp)(.*)", v)
    return int(m.group(1)), m.group(3)

def aa_key(v):
    m = re.match(r"(forward|deferred) (\d+) samples?(.*)", v)
    return (int(m.group(2)), m.group(1) + m.group(3).replace(" (aa off)", "")) if m else (0, v)

monotone("ssao", samples_key)
# Anti-aliasing: the edge error falls with the sample count on each path.
monotone("aa", aa_key)
monotone("rsm", samples_key)
monotone("ray_tracer", samples_key)

# Indirect light in a closed room: the probes (every bounce) beat one-bounce RSM, which
# beats no indirect light; one bounce of the probes is worse than all of them.
gi = {r["variant"]: f(r, "rmse") for r in rows if r["effect"] == "gi"}
order = ["probes 8 rays 64", "rsm one bounce", "no indirect"]
if all(v in gi for v in order):
    for a, b in zip(order, order[1:]):
        if not gi[a] < gi[b]:
            problems.append(f"gi: '{a}' has error {gi[a]:.5g}, not below '{b}' {gi[b]:.5g}")
    if "probes 8 rays 64 bounces 1" in gi and not gi["probes 8 rays 64"] < gi["probes 8 rays 64 bounces 1"]:
        problems.append("gi: every bounce is not better than one bounce")
else:
    problems.append(f"gi: missing variants (have {sorted(gi)})")

# Depth of field: the shipped gather is closer to the traced thin lens than the pinhole image.
dof = {r["variant"]: f(r, "rmse") for r in rows if r["effect"] == "dof"}
if "32 samples" in dof and "pinhole (no DOF)" in dof:
    if not dof["32 samples"] < dof["pinhole (no DOF)"]:
        problems.append(f"dof: '32 samples' has error {dof['32 samples']:.5g}, not below the pinhole's {dof['pinhole (no DOF)']:.5g}")
else:
    problems.append(f"dof: missing variants (have {sorted(dof)})")

# Motion blur: the shipped reconstruction is closer to the tracer's exact motion blur
# than the sharp frame at the shutter's centre.
mb = {r["variant"]: f(r, "rmse") for r in rows if r["effect"] == "motion_blur"}
if "15 samples" in mb and "no motion blur" in mb:
    if not mb["15 samples"] < mb["no motion blur"]:
        problems.append(f"motion_blur: '15 samples' has error {mb['15 samples']:.5g}, not below the sharp frame's {mb['no motion blur']:.5g}")
else:
    problems.append(f"motion_blur: missing variants (have {sorted(mb)})")

# The depth cap: the same paths up to the cap, so the error is the truncation alone. It falls as the
# cap rises, and the default (no cap) is the reference itself.
depth_rows = sorted(((int(re.match(r"max depth (\d+)", r["variant"]).group(1)), f(r, "rmse"), r["variant"])
                     for r in rows if r["effect"] == "ray_tracer_depth" and r["variant"].startswith("max depth")))
for (d0, e0, v0), (d1, e1, v1) in zip(depth_rows, depth_rows[1:]):
    if not e1 < e0:
        problems.append(f"ray_tracer_depth: '{v1}' has error {e1:.5g}, not below '{v0}' {e0:.5g}")
if depth_rows and not depth_rows[0][1] > 0:
    problems.append(f"ray_tracer_depth: '{depth_rows[0][2]}' has no error: the cap does not truncate")
for r in rows:
    if r["effect"] == "ray_tracer_depth" and r["variant"].startswith("no cap") and f(r, "rmse") != 0:
        problems.append(f"ray_tracer_depth: the default differs from itself (rmse {r['rmse']})")

for e in effects - {"forward_deferred"}:
    part = [r for r in rows if r["effect"] == e and r["scene"] == r["scene"]]
    for scene in {r["scene"] for r in part}:
        p = [r for r in part if r["scene"] == scene]
        for r in p:
            dominated = any(f(o, "ms") <= f(r, "ms") and f(o, "rmse") <= f(r, "rmse") and
                            (f(o, "ms") < f(r, "ms") or f(o, "rmse") < f(r, "rmse")) for o in p if o is not r)
            # A row tied with another at the CSV's printed precision (same image, times equal to
            # the printed digits: "sorted" and "sorted by triangle" can render alike) was decided
            # by the unprinted digits: the file cannot say which way, so it is not checked.
            tied = any(f(o, "ms") == f(r, "ms") and f(o, "rmse") == f(r, "rmse") for o in p if o is not r)
            # Likewise a row whose only dominator has the same printed time (a row with a lower
            # error and a time equal to the printed digits may be the slower one).
            strictly = any(f(o, "ms") < f(r, "ms") and f(o, "rmse") <= f(r, "rmse") for o in p if o is not r)
            tied = tied or (dominated and not strictly and
                            not any(f(o, "ms") <= f(r, "ms") and f(o, "rmse") < f(r, "rmse") and f(o, "ms") != f(r, "ms")
                                    for o in p if o is not r))
            if (r["pareto"] == "1") == dominated and not tied:
                problems.append(f"{e} {r['variant']}: pareto flag {r['pareto']} but dominated={dominated}")

print(f"{len(rows)} rows, {len(effects)} effects checked")
for p in problems:
    print("FAIL:", p)
sys.exit(1 if problems else 0)
