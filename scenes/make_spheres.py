#!/usr/bin/python3
"""Writes spheres-N.json for N = 1, 10, 100 and 1000: N glass and mirror spheres over the Fig. 8
board, the scenes of issue 26's complexity curve (where the exact renderer's search grows with N
and the pencil renderer's cost per sample should not). Board, light, sky, camera, depth and the
glass are Fig. 8's (README.md); spheres-1.json is Fig. 8 itself. For N > 1 the spheres sit on a
k x k grid (k = ceil(sqrt(N)), filled row by row) over the square x, z in [-2.5, 2.5] x [-1.5, 3.5]
of the board, each jittered within its cell by a fixed generator so that the files are the same
at every run: radius 0.35 of the cell, floating half a radius above the board as Fig. 8's ball
does; glass and mirror alternate. Run with Debian's /usr/bin/python3 in scenes/."""
import json, math, os, sys

here = os.path.dirname(os.path.abspath(__file__))

MATERIALS = {
    "white": {"color": [0.9, 0.9, 0.9], "ka": 0.2, "kd": 0.8},
    "red": {"color": [0.85, 0.12, 0.1], "ka": 0.2, "kd": 0.8},
    "glass": {"ka": 0, "kd": 0, "ks": 0.6, "phong": 80, "kr": 0.15, "kt": 0.75, "ior": 1.5},
    "mirror": {"color": [0.8, 0.8, 0.85], "ka": 0, "kd": 0.1, "ks": 0.6, "phong": 80, "kr": 0.8},
}


def jitter(state):
    """The next number in [0, 1) of a 64-bit linear congruential generator (Knuth's MMIX)."""
    state[0] = (state[0] * 6364136223846793005 + 1442695040888963407) % (1 << 64)
    return (state[0] >> 11) / float(1 << 53)


def spheres(n):
    if n == 1:
        return [{"type": "sphere", "name": "glass ball", "center": [0, 1.5, 0], "radius": 1,
                 "material": "glass"}]
    k = math.ceil(math.sqrt(n))
    cell = 5.0 / k
    r = 0.35 * cell
    slack = 0.5 * cell - r  # how far a centre may move in its cell without touching the next
    state = [n]
    out = []
    for i in range(n):
        row, col = divmod(i, k)
        x = -2.5 + (col + 0.5) * cell + slack * (2 * jitter(state) - 1)
        z = -1.5 + (row + 0.5) * cell + slack * (2 * jitter(state) - 1)
        out.append({"type": "sphere", "name": f"ball {i}",
                    "center": [round(x, 6), round(1.5 * r, 6), round(z, 6)],
                    "radius": round(r, 6), "material": "glass" if i % 2 == 0 else "mirror"})
    return out


def scene(n):
    return {
        "comment": f"{n} glass and mirror sphere(s) over the Fig. 8 board (issue 26's complexity "
                   "curve; written by make_spheres.py, see README.md).",
        "camera": {"eye": [0, 3, -6], "look_at": [0, 0.9, 0], "up": [0, 1, 0], "fov": 40,
                   "width": 256, "height": 256},
        "settings": {"ambient": 1, "background": [0.35, 0.55, 0.85], "max_depth": 6, "spp": 9,
                     "caustics": "off"},
        "materials": MATERIALS,
        "lights": [{"type": "point", "position": [-5, 6, -2.5], "intensity": 1}],
        "objects": [{"type": "plane", "name": "checkerboard", "point": [0, 0, 0],
                     "normal": [0, 1, 0], "material": "white",
                     "checker": {"size": 1, "material": "red", "u": [1, 0, 0]}}] + spheres(n),
    }


def main():
    counts = [int(a) for a in sys.argv[1:]] or [1, 10, 100, 1000]
    for n in counts:
        if n < 1:
            sys.exit(f"make_spheres.py: a count must be at least 1, got {n}")
        path = os.path.join(here, f"spheres-{n}.json")
        d = scene(n)
        objects = d.pop("objects")
        head = json.dumps(d, indent=1)[:-2]  # without the closing brace: the objects follow
        with open(path, "w") as f:  # one object a line, so that the files stay readable
            f.write(head + ',\n "objects": [\n  ')
            f.write(",\n  ".join(json.dumps(o) for o in objects))
            f.write("\n ]\n}\n")
        print(path)


if __name__ == "__main__":
    main()
