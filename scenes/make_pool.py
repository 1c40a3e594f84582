#!/usr/bin/python3
"""Writes pool.json: the 1989 paper's Fig. 8 set-up (Shinya, Saito, Takahashi, Graphics
Interface 1989), a swimming pool under a parallel light, its water surface a periodic height
field made by Fourier synthesis, and caustics on the pool floor. The paper does not give the
waves; ours are h(x, z) = 1 + sum a_k cos(2 pi (m x + n z) / L + phi_k) over x, z in [-2, 2]
(period L = 4), for the integer wave vectors k = (m, n) with 2 <= |k| <= 6 in the half plane
n > 0 or (n = 0, m > 0), amplitudes a_k = A |k|^-2 (a power spectrum falling as |k|^-4),
phases uniform in [0, 2 pi) from random.Random(1989), and A chosen so that the RMS slope
|grad h| over the mesh vertices (gradient taken analytically) is 0.3. The water is one closed
polyhedron: a 96 x 96 grid of quads, each split into two triangles with the diagonal
alternating in a checker pattern, four vertical side walls (one planar polygon each) and a
bottom at y = -0.25. The floor is eight 0.5-wide strips at y = 0, inside the water, alternately
white tile and blue lane, and an opaque square ring of walls just outside the water lets light in
through the surface only. Flat triangles refract a parallel light into uniform beams, so the
caustic network on the floor shows the facets' seams where neighbouring beams part or overlap;
their share of the floor does not shrink with the facets, only their width. Run with Debian's
/usr/bin/python3."""
import json, math, random

L, LEVEL, BOTTOM, N, KMIN, KMAX, SLOPE = 4.0, 1.0, -0.25, 96, 2, 6, 0.3
WALL_IN, WALL_OUT, WALL_LO, WALL_HI = 2.0005, 2.3, -0.3, 1.3

rng = random.Random(1989)
waves = []  # (m, n, |k|^-2, phase)
for n in range(0, KMAX + 1):
    for m in range(-KMAX, KMAX + 1):
        k = math.hypot(m, n)
        if KMIN <= k <= KMAX and (n > 0 or m > 0):
            waves.append((m, n, k ** -2, rng.uniform(0, 2 * math.pi)))

def grid(i):
    return -L / 2 + L * i / N

def field(x, z):
    """Height and gradient of the unscaled sum (A = 1), about the mean level."""
    h = gx = gz = 0.0
    for m, n, a, phi in waves:
        w = 2 * math.pi / L
        t = w * (m * x + n * z) + phi
        h += a * math.cos(t)
        gx -= a * w * m * math.sin(t)
        gz -= a * w * n * math.sin(t)
    return h, gx, gz

samples = [[field(grid(i), grid(j)) for j in range(N + 1)] for i in range(N + 1)]
rms1 = math.sqrt(sum(gx * gx + gz * gz for row in samples for _, gx, gz in row) / (N + 1) ** 2)
A = SLOPE / rms1

idx = lambda i, j: i * (N + 1) + j  # i along x, j along z
verts = [[round(grid(i), 12), round(LEVEL + A * samples[i][j][0], 12), round(grid(j), 12)]
         for i in range(N + 1) for j in range(N + 1)]
bot = {}
for i in (0, N):
    for j in (0, N):
        bot[i, j] = len(verts)
        verts.append([grid(i), BOTTOM, grid(j)])

faces = []  # all ordered outwards by the right-hand rule; the loader checks and orients anyway
for i in range(N):
    for j in range(N):
        v00, v10, v11, v01 = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
        if (i + j) % 2 == 0:
            faces += [[v00, v01, v11], [v00, v11, v10]]
        else:
            faces += [[v00, v01, v10], [v01, v11, v10]]
faces.append([idx(0, j) for j in range(N, -1, -1)] + [bot[0, 0], bot[0, N]])    # x = -2
faces.append([idx(N, j) for j in range(N + 1)] + [bot[N, N], bot[N, 0]])        # x = +2
faces.append([idx(i, 0) for i in range(N + 1)] + [bot[N, 0], bot[0, 0]])        # z = -2
faces.append([idx(i, N) for i in range(N, -1, -1)] + [bot[0, N], bot[N, N]])    # z = +2
faces.append([bot[0, 0], bot[N, 0], bot[N, N], bot[0, N]])                      # bottom

# The pool's walls: an opaque square ring just outside the water (a closed polyhedron of 16 quads,
# every face outwards), so that light enters the water through its surface only.
ring = []
for y in (WALL_LO, WALL_HI):
    for s in (WALL_OUT, WALL_IN):
        ring += [[-s, y, -s], [s, y, -s], [s, y, s], [-s, y, s]]
ob, ib, ot, it = (lambda k: k % 4), (lambda k: 4 + k % 4), (lambda k: 8 + k % 4), (lambda k: 12 + k % 4)
ring_faces = []
for k in range(4):
    ring_faces += [[it(k), it(k + 1), ot(k + 1), ot(k)],   # top, +y
                   [ob(k), ob(k + 1), ib(k + 1), ib(k)],   # bottom, -y
                   [ot(k), ot(k + 1), ob(k + 1), ob(k)],   # outer side, away from the pool
                   [ib(k), ib(k + 1), it(k + 1), it(k)]]   # inner side, towards the water

def strip(x0, x1, z0, z1):  # counter-clockwise seen from above: normal +y
    return [[x0, 0, z0], [x0, 0, z1], [x1, 0, z1], [x1, 0, z0]]

floor = [{"type": "polygon", "name": "floor %d" % s, "material": ("tile", "lane")[s % 2],
          "vertices": strip(-2 + 0.5 * s, -1.5 + 0.5 * s, -2, 2)} for s in range(8)]

scene = {
    "comment": "1989 paper Fig. 8: a swimming pool under a parallel light, caustics on the floor. "
               "Water surface: mean level 1 + sum of %d cosines over [-2, 2]^2 (period 4), wave vectors "
               "(m, n) with %d <= |k| <= %d in a half plane, amplitude A |k|^-2 (power spectrum |k|^-4), "
               "phases from random.Random(1989), A = %.6g for an RMS slope of %g over the vertices; "
               "mesh %d x %d quads split into triangles, closed by vertical walls and a bottom at y = -0.25. "
               "Floor: eight 0.5-wide strips at y = 0; opaque walls around the water. "
               "Generated by make_pool.py." % (len(waves), KMIN, KMAX, A, SLOPE, N, N),
    "camera": {"eye": [0, 5.5, -2.5], "look_at": [0, 0, 0], "fov": 40, "width": 256, "height": 256},
    "settings": {"ambient": 0.3, "background": [0.02, 0.03, 0.05], "max_depth": 4, "spp": 4,
                 "caustics": "auto"},
    "materials": {
        "water": {"ka": 0, "kd": 0, "ks": 0.8, "phong": 200, "kr": 0.02, "kt": 0.95, "ior": 1.33},
        "tile": {"color": [0.8, 0.88, 0.92], "ka": 0.1, "kd": 0.9},
        "lane": {"color": [0.15, 0.3, 0.65], "ka": 0.1, "kd": 0.9},
    },
    "lights": [{"type": "parallel", "direction": [0.25, -1, 0.15], "intensity": 1}],
    "objects": floor + [
        {"type": "polyhedron", "name": "water", "material": "water", "vertices": verts, "faces": faces},
        {"type": "polyhedron", "name": "walls", "material": "tile", "vertices": ring, "faces": ring_faces},
    ],
}

with open(__file__.replace("make_pool.py", "pool.json"), "w") as f:
    text = json.dumps(scene, indent=1)
    f.write(text + "\n")
