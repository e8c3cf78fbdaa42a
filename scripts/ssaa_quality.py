#!/usr/bin/env python3
"""The `ssaa` quality table of docs/performance.md (issue 13, session 11).

For each scene: one sample a pixel, `ssaa` and `ssaa_exact` at WxH, and the truth: the frame at
2Wx2H averaged 2x2. Prints PSNR and the share of pixels with a channel past 8/255 for each pair.
Pure Python (no imaging library on these machines): slow at large sizes.
Usage: scripts/ssaa_quality.py [--size 640x360] [--effects pbr,reflections=1] [scene ...]
"""
import argparse, math, os, struct, subprocess, sys, tempfile, zlib

def read_png(path):
    data = open(path, 'rb').read()
    pos, idat = 8, b''
    while pos < len(data):
        n, = struct.unpack('>I', data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b'IHDR': w, h, depth, colour = struct.unpack('>IIBB', body[:10])
        elif kind == b'IDAT': idat += body
    raw, bpp = zlib.decompress(idat), {2: 3, 6: 4}[colour]
    stride, rows, prev, p = w * bpp, [], bytearray(w * bpp), 0
    for _ in range(h):
        f, line = raw[p], bytearray(raw[p + 1:p + 1 + stride])
        p += 1 + stride
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b, c = prev[x], (prev[x - bpp] if x >= bpp else 0)
            if f == 1: line[x] = (line[x] + a) & 255
            elif f == 2: line[x] = (line[x] + b) & 255
            elif f == 3: line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else (b if pb <= pc else c))) & 255
        rows.append([line[i] for x in range(w) for i in range(x * bpp, x * bpp + 3)])
        prev = line
    return w, h, rows

def down2(img):
    w, h, rows = img
    out = []
    for y in range(h // 2):
        a, b = rows[2 * y], rows[2 * y + 1]
        out.append([(a[6 * x + c] + a[6 * x + 3 + c] + b[6 * x + c] + b[6 * x + 3 + c]) / 4
                    for x in range(w // 2) for c in range(3)])
    return w // 2, h // 2, out

def diff(a, b):
    w, h, ra = a
    se = over = 0
    for y in range(h):
        ya, yb = ra[y], b[2][y]
        for x in range(w):
            d = [abs(ya[3 * x + c] - yb[3 * x + c]) for c in range(3)]
            se += sum(v * v for v in d)
            over += max(d) > 8
    mse = se / (w * h * 3)
    psnr = 10 * math.log10(255 ** 2 / mse) if mse > 0 else float('inf')
    return f"{psnr:.1f} dB, {100 * over / (w * h):.2f} %"

def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('--size', default='640x360')
    ap.add_argument('--effects', default='pbr,reflections=1')
    ap.add_argument('--sdfvj', default=os.path.join(os.path.dirname(__file__), '..', 'build', 'src', 'app', 'sdfvj'))
    ap.add_argument('scenes', nargs='*', default=['midi', 'primitives', 'character', 'mandelbulb', 'field50', 'field150'])
    o = ap.parse_args()
    w, h = (int(v) for v in o.size.split('x'))
    print("| scene | one sample vs truth | `ssaa_exact` vs truth | `ssaa` vs truth | `ssaa` vs `ssaa_exact` | one sample vs `ssaa_exact` |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for scene in o.scenes:
            def render(extra, size):
                out = os.path.join(tmp, f"{scene}-{extra}-{size}")
                subprocess.run([o.sdfvj, 'render', '--scene', scene, '--path', 'compute', '--quiet', '--effects',
                                o.effects + (',' + extra if extra else ''), '--size', size, '--out', out],
                               check=True, stdout=subprocess.DEVNULL)
                return read_png(os.path.join(out, 'frame_00000.png'))
            one, shared, exact = render('', o.size), render('ssaa', o.size), render('ssaa_exact', o.size)
            truth = down2(render('', f"{2 * w}x{2 * h}"))
            print(f"| {scene} | {diff(one, truth)} | {diff(exact, truth)} | {diff(shared, truth)} | "
                  f"{diff(shared, exact)} | {diff(one, exact)} |", flush=True)

if __name__ == '__main__':
    sys.exit(main())
