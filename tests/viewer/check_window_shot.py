"""The viewer's panel does not hide the scene.

    check_window_shot.py WINDOW.png SCREENSHOT.png

WINDOW.png is `candela view --window-shot` (the whole window, panel included), SCREENSHOT.png is
`--screenshot` of the same frame (the rendered scene only). The panel is docked to the right, so
the window must be exactly as tall as the scene and wider, its left part must equal the
screenshot pixel for pixel (nothing drawn over the scene), and its right part must hold the panel
(not empty, not the scene). Decodes PNG with the standard library only (zlib), so the test needs
no imaging package; 8-bit RGB/RGBA, non-interlaced, as Candela writes them.
"""
import struct
import sys
import zlib


def read_png(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise SystemExit(f"{path}: not a PNG")
    pos, idat, header = 8, [], None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in (2, 6) or interlace:
        raise SystemExit(f"{path}: only 8-bit RGB/RGBA non-interlaced PNG is handled (depth {depth}, colour type {colour})")
    bpp = 3 if colour == 2 else 4
    raw = zlib.decompress(b"".join(idat))
    stride = width * bpp
    rows, previous = [], bytearray(stride)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        # PNG filters (PNG spec, section 9): 0 none, 1 sub, 2 up, 3 average, 4 Paeth.
        if kind == 1:
            for i in range(bpp, stride):
                line[i] = (line[i] + line[i - bpp]) & 255
        elif kind == 2:
            for i in range(stride):
                line[i] = (line[i] + previous[i]) & 255
        elif kind == 3:
            for i in range(stride):
                left = line[i - bpp] if i >= bpp else 0
                line[i] = (line[i] + ((left + previous[i]) >> 1)) & 255
        elif kind == 4:
            for i in range(stride):
                a = line[i - bpp] if i >= bpp else 0
                b = previous[i]
                c = previous[i - bpp] if i >= bpp else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        elif kind != 0:
            raise SystemExit(f"{path}: bad filter type {kind} in row {y}")
        rows.append(line)
        previous = line
    # RGB only, one bytes object per row.
    rgb = []
    for line in rows:
        if bpp == 3:
            rgb.append(bytes(line))
        else:
            out = bytearray(width * 3)
            out[0::3], out[1::3], out[2::3] = line[0::4], line[1::4], line[2::4]
            rgb.append(bytes(out))
    return width, height, rgb


def main():
    window_path, shot_path = sys.argv[1], sys.argv[2]
    ww, wh, window = read_png(window_path)
    sw, sh, shot = read_png(shot_path)
    print(f"window shot {ww}x{wh}, screenshot {sw}x{sh}")
    failures = []
    if wh != sh:
        failures.append(f"the window is {wh} pixels tall, the scene {sh}: --size must be the scene's size")
    if ww <= sw:
        failures.append(f"the window ({ww} wide) has no room beside the scene ({sw} wide) for the panel")
    if failures:
        raise SystemExit("FAIL: " + "; ".join(failures))
    differing = 0
    first = None
    for y in range(sh):
        left, ref = window[y][:sw * 3], shot[y]
        if left != ref:
            for x in range(sw):
                if left[3 * x:3 * x + 3] != ref[3 * x:3 * x + 3]:
                    differing += 1
                    if first is None:
                        first = (x, y, tuple(left[3 * x:3 * x + 3]), tuple(ref[3 * x:3 * x + 3]))
    print(f"scene region: {differing} of {sw * sh} pixels differ from the screenshot" +
          (f" (first at {first[0]},{first[1]}: window {first[2]}, screenshot {first[3]})" if first else ""))
    # The screenshot itself must show something: a black or flat image would pass the equality.
    shot_colours = set()
    lum_sum = 0
    for row in shot:
        for x in range(0, len(row), 3):
            shot_colours.add(row[x:x + 3])
            lum_sum += row[x] + row[x + 1] + row[x + 2]
    mean = lum_sum / (3.0 * sw * sh)
    print(f"screenshot: {len(shot_colours)} distinct colours, mean value {mean:.1f}/255")
    panel_colours = set()
    for row in window:
        for x in range(sw * 3, ww * 3, 3):
            panel_colours.add(row[x:x + 3])
    print(f"panel region ({ww - sw}x{wh}): {len(panel_colours)} distinct colours")
    if differing:
        failures.append("the panel (or something else) is drawn over the scene region")
    if len(shot_colours) < 16 or mean < 5.0:
        failures.append("the screenshot is (nearly) flat or black")
    if len(panel_colours) < 8:
        failures.append("the panel region holds no panel (text and widgets give many colours)")
    if failures:
        raise SystemExit("FAIL: " + "; ".join(failures))
    print("ok: the panel is beside the scene, not over it")


if __name__ == "__main__":
    main()
