/* bounds_truth.c -- the true worst-case errors that Eq. (4) and the A-1 coefficients claim to
 * bound (section 3.2): maxima over all directions of x0 and xi0 of the second-order term
 * Delta psi = 1/2 t(2)[psi, psi], and of the full error of the linear map from exact tracing.
 *
 * The maximisations are over one or two angles of smooth trigonometric functions: a grid
 * (7.5 degrees or finer) finds every local maximum's basin, and a shrinking local grid (1D:
 * golden section) refines the best few to ~1e-12 relative. */
#include <math.h>
#include <quadmath.h>

#include "validation/bounds.h"

double val_phi(int k) {
  return (double)k / (VAL_NPHI - 1) * M_PI / 2;
}

typedef struct {
  double h[4][4][4]; /* scaled tensor */
} scaled_t;

/* |1/2 h[part][psi, psi]| for part 0 (positions) or 1 (directions) */
static double quad_norm(const scaled_t *s, int part, const double psi[4]) {
  double v[2];
  for (int a = 0; a < 2; a++) {
    int i = 2 * part + a;
    double acc = 0.0;
    for (int j = 0; j < 4; j++) {
      if (psi[j] == 0.0)
        continue;
      double row = 0.0;
      for (int k = 0; k < 4; k++)
        row += s->h[i][j][k] * psi[k];
      acc += psi[j] * row;
    }
    v[a] = 0.5 * acc;
  }
  return hypot(v[0], v[1]);
}

typedef double (*fn1_t)(const void *ctx, double a);

/* max over a in [0, period) of f: grid of n points, golden section around the best three */
static double max1d(fn1_t f, const void *ctx, double period, int n, double *arg) {
  double best[3] = {-1, -1, -1}, at[3] = {0, 0, 0};
  double step = period / n;
  for (int i = 0; i < n; i++) {
    double a = i * step, v = f(ctx, a);
    for (int b = 0; b < 3; b++)
      if (v > best[b]) {
        for (int c = 2; c > b; c--) {
          best[c] = best[c - 1];
          at[c] = at[c - 1];
        }
        best[b] = v;
        at[b] = a;
        break;
      }
  }
  double m = best[0], am = at[0];
  const double g = 0.5 * (sqrt(5.0) - 1.0);
  for (int b = 0; b < 3; b++) {
    if (best[b] < 0)
      continue;
    double lo = at[b] - step, hi = at[b] + step;
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    double f1 = f(ctx, x1), f2 = f(ctx, x2);
    for (int it = 0; it < 80 && hi - lo > 1e-13; it++) {
      if (f1 > f2) {
        hi = x2;
        x2 = x1;
        f2 = f1;
        x1 = hi - g * (hi - lo);
        f1 = f(ctx, x1);
      } else {
        lo = x1;
        x1 = x2;
        f1 = f2;
        x2 = lo + g * (hi - lo);
        f2 = f(ctx, x2);
      }
    }
    double v = fmax(f1, f2);
    if (v > m) {
      m = v;
      am = f1 > f2 ? x1 : x2;
    }
  }
  if (arg)
    *arg = am;
  return m;
}

typedef struct {
  const scaled_t *s;
  int part;
  int which; /* 0: pure x, 1: pure xi, 2: bilinear */
} coef_ctx_t;

static double coef_fn(const void *p, double a) {
  const coef_ctx_t *c = p;
  if (c->which < 2) {
    double psi[4] = {0, 0, 0, 0};
    psi[2 * c->which] = cos(a);
    psi[2 * c->which + 1] = sin(a);
    return quad_norm(c->s, c->part, psi);
  }
  /* bilinear part sum_{j<2, k>=2} h[i][j][k] x_j xi_k: the spectral norm over xi for x(a) */
  double x[2] = {cos(a), sin(a)};
  px_mat2_t m;
  for (int r = 0; r < 2; r++)
    for (int k = 0; k < 2; k++)
      m.m[r][k] =
          c->s->h[2 * c->part + r][0][2 + k] * x[0] + c->s->h[2 * c->part + r][1][2 + k] * x[1];
  return px_mat2_norm2(m);
}

typedef struct {
  const scaled_t *s;
  int part;
  double x0, xi0;
} shape_ctx_t;

static double shape_fn(const shape_ctx_t *c, double a, double b) {
  double psi[4] = {c->x0 * cos(a), c->x0 * sin(a), c->xi0 * cos(b), c->xi0 * sin(b)};
  return quad_norm(c->s, c->part, psi);
}

/* max over (a, b) in [0, pi) x [0, 2 pi) (Delta(-psi) = Delta(psi)): grid, then a shrinking
 * 5 x 5 local grid from the best three cells */
static double max2d(const shape_ctx_t *c, double dir[2]) {
  enum { NA = 24, NB = 48 };
  double best[3] = {-1, -1, -1}, at[3][2] = {{0}};
  double sa = M_PI / NA, sb = 2 * M_PI / NB;
  for (int i = 0; i < NA; i++)
    for (int j = 0; j < NB; j++) {
      double v = shape_fn(c, i * sa, j * sb);
      for (int q = 0; q < 3; q++)
        if (v > best[q]) {
          for (int r = 2; r > q; r--) {
            best[r] = best[r - 1];
            at[r][0] = at[r - 1][0];
            at[r][1] = at[r - 1][1];
          }
          best[q] = v;
          at[q][0] = i * sa;
          at[q][1] = j * sb;
          break;
        }
    }
  double m = best[0];
  dir[0] = at[0][0];
  dir[1] = at[0][1];
  for (int q = 0; q < 3; q++) {
    double ca = at[q][0], cb = at[q][1], ha = sa, hb = sb, cv = best[q];
    for (int it = 0; it < 44; it++) {
      double na = ca, nb = cb;
      for (int i = -2; i <= 2; i++)
        for (int j = -2; j <= 2; j++) {
          double a = ca + 0.5 * i * ha, b = cb + 0.5 * j * hb, v = shape_fn(c, a, b);
          if (v > cv) {
            cv = v;
            na = a;
            nb = b;
          }
        }
      ca = na;
      cb = nb;
      ha *= 0.6;
      hb *= 0.6;
    }
    if (cv > m) {
      m = cv;
      dir[0] = ca;
      dir[1] = cb;
    }
  }
  return m;
}

void val_truth_from_tensor(double hess[4][4][4], double length, val_truth_t *t) {
  scaled_t s;
  double L = length, scale = 1.0;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      for (int k = 0; k < 4; k++) {
        double w = (i < 2 ? 1.0 / L : 1.0) * (j < 2 ? L : 1.0) * (k < 2 ? L : 1.0);
        s.h[i][j][k] = hess[i][j][k] * w;
        scale = fmax(scale, fabs(s.h[i][j][k]));
      }
  t->scale = scale;
  for (int part = 0; part < 2; part++) {
    coef_ctx_t c0 = {&s, part, 0}, c1 = {&s, part, 1}, c2 = {&s, part, 2};
    t->coef[3 * part + 0] = max1d(coef_fn, &c0, M_PI, 72, NULL);
    t->coef[3 * part + 1] = max1d(coef_fn, &c2, M_PI, 72, NULL);
    t->coef[3 * part + 2] = max1d(coef_fn, &c1, M_PI, 72, NULL);
  }
  for (int k = 0; k < VAL_NPHI; k++) {
    double ph = val_phi(k);
    for (int part = 0; part < 2; part++) {
      shape_ctx_t c = {&s, part, cos(ph), sin(ph)};
      double *dir = part ? t->dir_xi[k] : t->dir_x[k];
      (part ? t->exi : t->ex)[k] = max2d(&c, dir);
    }
  }
}

double val_ex_scaled(const px_pencil_t *k, double phi) {
  double c = cos(phi), s = sin(phi);
  return k->a * c * c + k->b * c * s + k->c * s * s;
}

double val_exi_scaled(const px_pencil_t *k, double phi) {
  double c = cos(phi), s = sin(phi);
  return k->d * c * c + k->e * c * s + k->f * s * s;
}

px_pencil_t val_scale_pencil(const px_pencil_t *k, double L) {
  return (px_pencil_t){k->a * L, k->b, k->c / L, k->d * L * L, k->e * L, k->f};
}

typedef struct {
  const ex_system_t *sys;
  const ex_axial_t *ax;
  px_mat4_t t;
  double length, xi0;
  px_status_t status;
  double f0[4]; /* image of the axial ray (~1e-17 L off O') */
} pin_ctx_t;

static double pin_fn(const void *p, double b) {
  pin_ctx_t *c = (pin_ctx_t *)p;
  double psi[4] = {0, 0, c->xi0 * cos(b), c->xi0 * sin(b)}, out[4];
  if (c->status != PX_OK)
    return 0.0;
  px_status_t st = ex_map(c->sys, c->ax, psi, out);
  if (st != PX_OK) {
    c->status = st;
    return 0.0;
  }
  double lin[2] = {c->t.m[0][2] * psi[2] + c->t.m[0][3] * psi[3],
                   c->t.m[1][2] * psi[2] + c->t.m[1][3] * psi[3]};
  return hypot(out[0] - c->f0[0] - lin[0], out[1] - c->f0[1] - lin[1]) / c->length;
}

px_status_t val_pinhole_error(const ex_system_t *sys, const ex_axial_t *ax, px_mat4_t t,
                              double length, double xi0, double *err) {
  pin_ctx_t c = {sys, ax, t, length, xi0, PX_OK, {0, 0, 0, 0}};
  const double zero4[4] = {0, 0, 0, 0};
  px_status_t st = ex_map(sys, ax, zero4, c.f0);
  if (st != PX_OK)
    return st;
  double e = max1d(pin_fn, &c, 2 * M_PI, 36, NULL);
  if (c.status != PX_OK)
    return c.status;
  *err = e;
  return PX_OK;
}

/* The exact map along the ray vector s * p in __float128. */
static px_status_t map_q_scaled(const ex_system_t *sys, const ex_axial_t *ax, const double p[4],
                                __float128 s, __float128 out[4]) {
  __float128 pq[4];
  for (int k = 0; k < 4; k++)
    pq[k] = s * (__float128)p[k];
  return ex_map_q(sys, ax, pq, out);
}

/* full error F(psi) - F(0) - J psi at amplitude eps, shape phi, directions (a, b), divided by
 * eps^2 (positions also by L). J psi = (F(h psi) - F(-h psi)) / 2h in __float128: a double
 * Jacobian would leave 1e-16 |T| eps of noise, comparable to a small eps^2 error; this leaves
 * h^2 eps^3 of the third-order term and ~1e-34 eps of rounding (h = 1e-6). F(0): the axial
 * ray, traced in double, lands ~1e-17 L off O', which is no error of the linear map. */
static px_status_t sampled_one(const ex_system_t *sys, const ex_axial_t *ax, const __float128 f0[4],
                               double length, double eps, double phi, int part, double a, double b,
                               double *err) {
  double p[4] = {eps * length * cos(phi) * cos(a), eps * length * cos(phi) * sin(a),
                 eps * sin(phi) * cos(b), eps * sin(phi) * sin(b)};
  __float128 out[4], fp[4], fm[4], h = 1e-6Q;
  px_status_t st = map_q_scaled(sys, ax, p, 1, out);
  if (st == PX_OK)
    st = map_q_scaled(sys, ax, p, h, fp);
  if (st == PX_OK)
    st = map_q_scaled(sys, ax, p, -h, fm);
  if (st != PX_OK)
    return st;
  double e[2];
  for (int r = 0; r < 2; r++) {
    int row = 2 * part + r;
    e[r] = (double)(out[row] - f0[row] - (fp[row] - fm[row]) / (2 * h));
  }
  *err = hypot(e[0], e[1]) / (part == 0 ? length : 1.0) / (eps * eps);
  return PX_OK;
}

px_status_t val_sampled_error(const ex_system_t *sys, const ex_axial_t *ax, double length,
                              double eps, double phi, int part, const double dir[2], double *err,
                              double *eps_used) {
  __float128 f0[4];
  const double zero4[4] = {0, 0, 0, 0};
  px_status_t st = map_q_scaled(sys, ax, zero4, 1, f0);
  if (st != PX_OK)
    return st;
  /* In the second-order regime e(eps) / eps^2 does not depend on eps: where it changes by more
   * than 1e-3 between eps and eps/2 the third-order terms still matter, and eps is lowered
   * tenfold (to 1e-12 at most: quad rounding is then ~1e-22 of the sample). */
  for (int tries = 0;; tries++) {
    double v1, v2;
    if ((st = sampled_one(sys, ax, f0, length, eps, phi, part, dir[0], dir[1], &v1)) != PX_OK ||
        (st = sampled_one(sys, ax, f0, length, eps / 2, phi, part, dir[0], dir[1], &v2)) != PX_OK)
      return st;
    if (fabs(v1 - v2) <= 1e-3 * v2 || tries == 5)
      break;
    eps /= 10;
  }
  double best = 0.0;
  const double d1 = M_PI / 180.0;
  static const int nb[5][2] = {{0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  for (int q = 0; q < 5; q++) {
    double v;
    st = sampled_one(sys, ax, f0, length, eps, phi, part, dir[0] + nb[q][0] * d1,
                     dir[1] + nb[q][1] * d1, &v);
    if (st != PX_OK)
      return st;
    best = fmax(best, v);
  }
  *err = best;
  if (eps_used)
    *eps_used = eps;
  return PX_OK;
}
