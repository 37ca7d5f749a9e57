#!/usr/bin/python3
# The orbital-view figure of docs/sim-render.md ("Orbital view"): the visible and the
# thermal orbital image of one descent scenario and its first descent frame, side by side,
# each box-downscaled 2x and contrast-stretched (1st..99.5th percentile), with the descent
# frame's ground footprint (its edge pixels' true site points, through orbital.geo) drawn
# on the orbital panels. Also prints where the frame falls in the orbital image.
# Ground-side (Debian python3-numpy, python3-pil). Inputs: two `vtm-sim render` runs of
# the same scenario, one with `modality visible`, one with `modality thermal`:
#   tools/scripts/orbital_figure.py VISIBLE_DIR THERMAL_DIR OUT.png
import sys, numpy as np
from PIL import Image

def pfm(p):
    f = open(p, 'rb'); assert f.readline().strip() == b'Pf'
    w, h = map(int, f.readline().split()); s = float(f.readline())
    a = np.frombuffer(f.read(), dtype='<f4' if s < 0 else '>f4').reshape(h, w)
    return np.flipud(a).astype(np.float64)

def quat(w, x, y, z):
    return np.array([[1-2*(y*y+z*z), 2*(x*y-w*z), 2*(x*z+w*y)], [2*(x*y+w*z), 1-2*(x*x+z*z), 2*(y*z-w*x)],
                     [2*(x*z-w*y), 2*(y*z+w*x), 1-2*(x*x+y*y)]])

def geo(d):
    g = {}
    for l in open(d + '/orbital.geo'):
        t = l.split()
        if len(t) >= 2 and not l.startswith('#'):
            g[t[0]] = t[1:]
    return float(g['north0_m'][0]), float(g['east0_m'][0]), float(g['cell_m'][0])

def stretch(a):
    lo, hi = np.percentile(a, [1, 99.5])
    return np.clip((a - lo) / max(hi - lo, 1e-9) * 255.0, 0, 255)

def down2(a):
    h, w = a.shape[0] // 2 * 2, a.shape[1] // 2 * 2
    return a[:h, :w].reshape(h // 2, 2, w // 2, 2).mean(axis=(1, 3))

if len(sys.argv) != 4:
    sys.exit('usage: orbital_figure.py VISIBLE_DIR THERMAL_DIR OUT.png')
vis_dir, th_dir, out = sys.argv[1:]
vis = np.asarray(Image.open(vis_dir + '/orbital.png'), dtype=np.float64)
th = np.asarray(Image.open(th_dir + '/orbital.png'), dtype=np.float64)
cam = np.asarray(Image.open(th_dir + '/nadir_000.png'), dtype=np.float64)
n0, e0, cell = geo(th_dir)
# Frame 0's edge pixels through their true depth and pose to site points, then orbital pixels.
cm = dict(l.split()[:2] for l in open(th_dir + '/nadir.cmod') if len(l.split()) >= 2)
fx, fy, cx, cy = [float(cm[k]) for k in ('fx_px', 'fy_px', 'cx_px', 'cy_px')]
for l in open(th_dir + '/camera_poses.txt'):
    t = l.split()
    if l[0] in '#v' or int(t[0]) != 0:
        continue
    c, R = np.array(list(map(float, t[3:6]))), quat(*map(float, t[6:10]))
depth = pfm(th_dir + '/nadir_000_depth.pfm')
h, w = depth.shape
edge = [(u, 0) for u in range(w)] + [(w - 1, v) for v in range(h)] + [(u, h - 1) for u in range(w)] + [(0, v) for v in range(h)]
pts = []
for u, v in edge:
    d = depth[v, u]
    p = c + R @ (d * np.array([(u - cx) / fx, (v - cy) / fy, 1.0]))
    pts.append(((p[1] - e0) / cell, (n0 - p[0]) / cell))
pts = np.array(pts)
print('frame 0 footprint in orbital pixels: cols %.1f .. %.1f, rows %.1f .. %.1f of %d x %d' %
      (pts[:, 0].min(), pts[:, 0].max(), pts[:, 1].min(), pts[:, 1].max(), th.shape[1], th.shape[0]))
def ranks(x):
    r = np.empty(len(x)); r[np.argsort(x, kind='stable')] = np.arange(len(x)); return r
print('rank correlation thermal / visible over the orbital image: %.3f' %
      np.corrcoef(ranks(th.ravel()), ranks(vis.ravel()))[0, 1])
panels = []
for img, outline in ((vis, True), (th, True), (cam, False)):
    p = np.stack([stretch(down2(img))] * 3, axis=-1)
    if outline:
        for x, y in pts / 2.0:
            xi, yi = int(round(x)), int(round(y))
            if 0 <= yi < p.shape[0] and 0 <= xi < p.shape[1]:
                p[yi, xi] = (255, 200, 0)
    panels.append(p)
gap = np.full((panels[0].shape[0], 6, 3), 255.0)
Image.fromarray(np.concatenate([panels[0], gap, panels[1], gap, panels[2]], axis=1).astype(np.uint8)).save(out, optimize=True)
