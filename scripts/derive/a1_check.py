#!/usr/bin/python3
# a1_check.py -- derivation aid: compares the sympy series of a1_series.py with the closed-form
# second-order term that libparaxial/src/bounds.c (px_element_second_order) implements, at random
# angles, curvature matrices, cubic terms and ray vectors. Prints the largest difference.
# Usage: /usr/bin/python3 a1_check.py refr|refl   (after a1_series.py with the same argument)
import math, pickle, random, sys
import numpy as np
import sympy as sp

refl = sys.argv[1] == 'refl'
res = pickle.load(open('a1_series_%s_2.pkl' % sys.argv[1], 'rb'))
X1, X2, k1, k2 = sp.symbols('X1 X2 k1 k2', real=True)
S, C, eta, Cp = sp.symbols('S C eta Cp', real=True)
q11, q12, q22 = sp.symbols('q11 q12 q22', real=True)
cs = sp.symbols('c111 c112 c122 c222', real=True)


def closed_form(th, et, Q, Ct, x, xi):
    s, c = math.sin(th), math.cos(th)
    if refl:
        et, sp_, cp = 1.0, s, -c
    else:
        sp_ = et * s
        cp = math.sqrt(1 - sp_ ** 2)
    h = cp - et * c
    Th, Thp = np.diag([c, 1.]), np.diag([cp, 1.])
    Ti, Tpi = np.linalg.inv(Th), np.linalg.inv(Thp)
    u = Ti @ x
    w = 0.5 * u @ Q @ u
    g = Q @ u
    xl = -h * Tpi @ Q @ u + et * Tpi @ Th @ xi
    dx = ((s * cp - c * sp_) / c) * w * np.array([1, 0]) + u[0] * (s * Thp @ Ti @ xi - sp_ * xl)
    u2 = Ti @ (s * (w * np.array([1, 0]) + u[0] * xi))
    cub = 0.5 * np.array([sum(Ct[i][j][k] * u[i] * u[j] for i in range(2) for j in range(2))
                          for k in range(2)])
    g2 = Q @ u2 + cub
    dc1 = -s * (g[0] + xi[0])
    om = 1 - et ** 2
    d1 = (-(h / cp) * g2[0] - 0.5 * et * s * om * (xi @ xi) / cp + 0.5 * h * h * sp_ * (g @ g) / cp
          - et * h * s * (g[0] + xi[0]) * g[0] - (et * h * sp_ / cp) * (c * xi[0] * g[0] + xi[1] * g[1])
          - 0.5 * sp_ * et ** 2 * om * dc1 ** 2 / cp ** 3)
    d2 = -h * g2[1] - (et * h * s / cp) * (g[0] + xi[0]) * g[1]
    return np.array([dx[0], dx[1], d1, d2])


random.seed(1)
worst = 0.0
for trial in range(20):
    th = random.uniform(0, 1.3)
    et = random.choice([0.66, 1.5, 0.75, 1.2])
    if et * math.sin(th) >= 0.99:
        th = 0.3
    q = [random.uniform(-1, 1) for _ in range(3)]
    c = [random.uniform(-1, 1) for _ in range(4)]
    x = np.array([random.uniform(-1, 1) for _ in range(2)])
    xi = np.array([random.uniform(-1, 1) for _ in range(2)])
    Q = np.array([[q[0], q[1]], [q[1], q[2]]])
    Ct = np.zeros((2, 2, 2))
    for i in range(2):
        for j in range(2):
            for k in range(2):
                Ct[i][j][k] = c[i + j + k]
    sub = {S: math.sin(th), C: math.cos(th), eta: et, q11: q[0], q12: q[1], q22: q[2],
           X1: x[0], X2: x[1], k1: xi[0], k2: xi[1]}
    if not refl:
        sub[Cp] = math.sqrt(1 - (et * math.sin(th)) ** 2)
    sub.update({cs[i]: c[i] for i in range(4)})
    ref = np.array([float(res[(i, 2)].subs(sub)) for i in range(4)])
    worst = max(worst, float(np.max(np.abs(closed_form(th, et, Q, Ct, x, xi) - ref))))
print('largest |closed form - series| over 20 random cases: %.3g' % worst)
sys.exit(0 if worst < 1e-12 else 1)
