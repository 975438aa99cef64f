"""Screenshots of the viewer playing Fox (tests/viewer/viewer_animation.cmake).

    check_animation.py DIR

DIR holds the screenshots of tests/viewer/animation.script plus anim_cli.png (`view --animation
Walk --time 0.5`, which viewer_animation.cmake compares with `candela render` itself). Checks:
- each shows the fox: not black, not flat (the fox's region is found as the pixels that differ
  from the background, estimated from the image border);
- the walk at 0.25 s and at 0.5 s differ meaningfully inside the fox's region (many pixels, by a
  visible amount), and very little outside it;
- scrubbing back to 0.25 s gives the 0.25 s image again (to within 1/255 on 99.9 % of pixels);
- playing moved the fox; paused, two frames 6 apart are identical.
Standard library only (the PNG reader of check_window_shot.py).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_window_shot import read_png  # noqa: E402


def load(directory, name):
    w, h, rows = read_png(os.path.join(directory, name))
    return w, h, [list(r) for r in rows]


def pixel(rows, x, y):
    r = rows[y]
    return r[3 * x], r[3 * x + 1], r[3 * x + 2]


def background(w, h, rows):
    """The border's median colour (the fox is framed in the middle)."""
    border = [pixel(rows, x, y) for x in range(w) for y in (0, h - 1)] + [pixel(rows, x, y) for y in range(h) for x in (0, w - 1)]
    return tuple(sorted(c[i] for c in border)[len(border) // 2] for i in range(3))


def foreground(w, h, rows, bg, threshold=24):
    return {(x, y) for y in range(h) for x in range(w)
            if max(abs(a - b) for a, b in zip(pixel(rows, x, y), bg)) > threshold}


def diff_stats(w, h, a, b, region=None, threshold=16):
    """(pixels compared, pixels differing by more than threshold/255 in a channel, mean abs diff)."""
    coords = region if region is not None else [(x, y) for y in range(h) for x in range(w)]
    n = big = 0
    total = 0
    for x, y in coords:
        d = max(abs(p - q) for p, q in zip(pixel(a, x, y), pixel(b, x, y)))
        n += 1
        total += d
        big += d > threshold
    return n, big, (total / n if n else 0.0)


def near_equal(w, h, a, b):
    _, over1, _ = diff_stats(w, h, a, b, threshold=1)
    return over1, over1 <= 0.001 * w * h


def main():
    directory = sys.argv[1]
    names = ["anim_a.png", "anim_b.png", "anim_a2.png", "anim_played.png", "anim_paused1.png", "anim_paused2.png", "anim_cli.png"]
    images = {}
    failures = []
    for n in names:
        w, h, rows = load(directory, n)
        images[n] = rows
        bg = background(w, h, rows)
        fg = foreground(w, h, rows, bg)
        mean = sum(sum(r) for r in rows) / (3.0 * w * h)
        fg_mean = sum(sum(pixel(rows, x, y)) for x, y in fg) / (3.0 * max(len(fg), 1))
        print(f"{n}: {w}x{h}, background {bg}, fox {len(fg)} pixels ({100.0 * len(fg) / (w * h):.1f} %), "
              f"mean value {mean:.1f}/255, fox mean {fg_mean:.1f}/255")
        if mean < 5.0 or fg_mean < 10.0:
            failures.append(f"{n} is (nearly) black")
        if len(fg) < 0.01 * w * h:
            failures.append(f"{n}: no fox found (fewer than 1 % of pixels differ from the background)")
    a, b = images["anim_a.png"], images["anim_b.png"]
    # The fox's region: where either pose differs from its background, grown by 2 pixels (its
    # silhouette moves between the poses).
    fg = foreground(w, h, a, background(w, h, a)) | foreground(w, h, b, background(w, h, b))
    region = {(x + dx, y + dy) for x, y in fg for dx in range(-2, 3) for dy in range(-2, 3)
              if 0 <= x + dx < w and 0 <= y + dy < h}
    outside = [(x, y) for y in range(h) for x in range(w) if (x, y) not in region]
    n_in, big_in, mean_in = diff_stats(w, h, a, b, region)
    n_out, big_out, mean_out = diff_stats(w, h, a, b, outside)
    print(f"walk 0.25 s vs 0.5 s: inside the fox's region {big_in}/{n_in} pixels differ by > 16/255 "
          f"({100.0 * big_in / max(n_in, 1):.1f} %, mean |diff| {mean_in:.1f}); outside {big_out}/{n_out} ({mean_out:.2f})")
    if big_in < 0.05 * n_in or mean_in < 4.0:
        failures.append("the walk at 0.25 s and 0.5 s do not differ meaningfully in the fox's region")
    if big_out > 0.02 * max(n_out, 1):
        failures.append("the two poses differ outside the fox's region (more than 2 % of those pixels)")
    for x_name, y_name, what in [("anim_a.png", "anim_a2.png", "scrubbing back to 0.25 s")]:
        over, ok = near_equal(w, h, images[x_name], images[y_name])
        print(f"{what}: {over} pixels differ by more than 1/255")
        if not ok:
            failures.append(f"{what} does not give the same image ({x_name} vs {y_name})")
    _, moved, mean_moved = diff_stats(w, h, images["anim_a2.png"], images["anim_played.png"], region)
    print(f"played at 4x: {moved} pixels of the fox's region moved by > 16/255 (mean |diff| {mean_moved:.1f})")
    if moved < 0.01 * len(region):
        failures.append("playing did not move the fox")
    if images["anim_paused1.png"] != images["anim_paused2.png"]:
        _, n_diff, _ = diff_stats(w, h, images["anim_paused1.png"], images["anim_paused2.png"], threshold=0)
        failures.append(f"paused, two frames differ ({n_diff} pixels)")
    else:
        print("paused: frames 16 and 22 are identical")
    if failures:
        raise SystemExit("FAIL: " + "; ".join(failures))
    print("ok: the viewer plays, scrubs and pauses Fox's walk")


if __name__ == "__main__":
    main()
