/* deposit.c -- flux into the map's cells: a photon into the cell it falls in; a pencil's triangle
 * spread evenly over its area, each cell taking the flux of the part of the triangle inside it
 * (the triangle clipped to the cell, Sutherland-Hodgman), so that the flux deposited is the
 * pencil's whatever the triangle's size against the cells. */
#include <math.h>

#include "internal.h"

static void add(lt_accum_t *A, int i, int j, rt_rgb_t phi) {
  double *c = A->flux + 3 * ((size_t)j * (size_t)A->m->width + (size_t)i);
  c[0] += phi.r;
  c[1] += phi.g;
  c[2] += phi.b;
}

static double mean(rt_rgb_t c) {
  return (c.r + c.g + c.b) / 3.0;
}

void lt__deposit_point(lt_accum_t *A, double u, double v, rt_rgb_t phi) {
  const lt_map_t *m = A->m;
  double fi = (u - m->u0) / (m->u1 - m->u0) * m->width,
         fj = (v - m->v0) / (m->v1 - m->v0) * m->height;
  if (!(fi >= 0 && fi < m->width && fj >= 0 && fj < m->height)) {
    A->st->flux_outside += mean(phi);
    return;
  }
  add(A, (int)fi, (int)fj, phi);
  A->st->flux_map += mean(phi);
}

/* Clip polygon p (n vertices) to the half-plane s * (x[axis] - c) <= 0; returns the count. */
static int clip(double p[][2], int n, int axis, double c, double s, double out[][2]) {
  int m = 0;
  for (int k = 0; k < n; k++) {
    const double *a = p[k], *b = p[(k + 1) % n];
    double da = s * (a[axis] - c), db = s * (b[axis] - c);
    if (da <= 0) {
      out[m][0] = a[0];
      out[m][1] = a[1];
      m++;
    }
    if ((da < 0 && db > 0) || (da > 0 && db < 0)) {
      double t = da / (da - db);
      out[m][0] = a[0] + t * (b[0] - a[0]);
      out[m][1] = a[1] + t * (b[1] - a[1]);
      m++;
    }
  }
  return m;
}

static double area(double p[][2], int n) {
  double a = 0.0;
  for (int k = 0; k < n; k++)
    a += p[k][0] * p[(k + 1) % n][1] - p[(k + 1) % n][0] * p[k][1];
  return 0.5 * fabs(a);
}

void lt__deposit_triangle(lt_accum_t *A, const double uv[3][2], rt_rgb_t phi) {
  const lt_map_t *m = A->m;
  /* in cell units */
  double sx = m->width / (m->u1 - m->u0), sy = m->height / (m->v1 - m->v0), t[3][2];
  for (int k = 0; k < 3; k++) {
    t[k][0] = (uv[k][0] - m->u0) * sx;
    t[k][1] = (uv[k][1] - m->v0) * sy;
  }
  double at = area(t, 3);
  if (!(at > 1e-300) || !isfinite(at)) {
    lt__deposit_point(A, (uv[0][0] + uv[1][0] + uv[2][0]) / 3, (uv[0][1] + uv[1][1] + uv[2][1]) / 3,
                      phi);
    return;
  }
  double x0 = fmin(t[0][0], fmin(t[1][0], t[2][0])), x1 = fmax(t[0][0], fmax(t[1][0], t[2][0]));
  double y0 = fmin(t[0][1], fmin(t[1][1], t[2][1])), y1 = fmax(t[0][1], fmax(t[1][1], t[2][1]));
  int i0 = (int)fmax(0.0, floor(x0)), i1 = (int)fmin(m->width - 1.0, floor(x1));
  int j0 = (int)fmax(0.0, floor(y0)), j1 = (int)fmin(m->height - 1.0, floor(y1));
  double inside = 0.0;
  for (int j = j0; j <= j1; j++) {
    double row[8][2], tmp[8][2];
    int n = clip(t, 3, 1, j, -1, tmp);  /* y >= j */
    n = clip(tmp, n, 1, j + 1, 1, row); /* y <= j + 1 */
    if (n < 3)
      continue;
    for (int i = i0; i <= i1; i++) {
      double cell[10][2], c2[10][2];
      int q = clip(row, n, 0, i, -1, c2);
      q = clip(c2, q, 0, i + 1, 1, cell);
      if (q < 3)
        continue;
      double f = area(cell, q) / at;
      inside += f;
      add(A, i, j, rt_rgb_scale(phi, f));
    }
  }
  A->st->flux_map += inside * mean(phi);
  A->st->flux_outside += (1 - inside) * mean(phi);
}

void lt__deposit_polygon(lt_accum_t *A, const double (*uv)[2], int n, rt_rgb_t phi) {
  double total = 0.0, part[64];
  if (n < 3 || n > 64) {
    double c[2] = {0, 0};
    for (int k = 0; k < n; k++) {
      c[0] += uv[k][0] / n;
      c[1] += uv[k][1] / n;
    }
    if (n > 0)
      lt__deposit_point(A, c[0], c[1], phi);
    return;
  }
  for (int k = 1; k + 1 < n; k++) {
    part[k] = fabs((uv[k][0] - uv[0][0]) * (uv[k + 1][1] - uv[0][1]) -
                   (uv[k + 1][0] - uv[0][0]) * (uv[k][1] - uv[0][1]));
    total += part[k];
  }
  for (int k = 1; k + 1 < n; k++) {
    double t[3][2] = {{uv[0][0], uv[0][1]}, {uv[k][0], uv[k][1]}, {uv[k + 1][0], uv[k + 1][1]}};
    double share = total > 0 ? part[k] / total : 1.0 / (n - 2);
    lt__deposit_triangle(A, (const double(*)[2])t, rt_rgb_scale(phi, share));
  }
}

void lt__settle(lt_accum_t *A, const lt_arrival_t *a, rt_rgb_t phi, int photon) {
  double m = mean(phi);
  if (a->kind == LT_END_ESCAPED) {
    A->st->flux_escaped += m;
  } else if (a->kind == LT_END_ABSORBED) {
    A->st->flux_absorbed += m;
  } else {
    lt__deposit_point(A, a->u, a->v, phi);
    A->st->photons += (uint64_t)photon;
  }
}

/* Area and centroid of polygon p (n vertices). */
static double area_centroid(double p[][2], int n, double c[2]) {
  double a = 0.0, cx = 0.0, cy = 0.0;
  for (int k = 1; k + 1 < n; k++) {
    double ax = p[k][0] - p[0][0], ay = p[k][1] - p[0][1];
    double bx = p[k + 1][0] - p[0][0], by = p[k + 1][1] - p[0][1];
    double t = ax * by - bx * ay;
    a += t;
    cx += t * (ax + bx);
    cy += t * (ay + by);
  }
  if (a == 0.0) {
    c[0] = p[0][0];
    c[1] = p[0][1];
    return 0.0;
  }
  c[0] = p[0][0] + cx / (3.0 * a);
  c[1] = p[0][1] + cy / (3.0 * a);
  return 0.5 * fabs(a);
}

/* Flux of the linear density e[k] at the vertices of triangle t (cell units, e per unit of the
 * map's area), k = 0..2, into the cells: each cell takes the integral over the part of the
 * triangle inside it, area times the density at the part's centroid. Returns the flux on the map
 * (mean of R, G, B of colour w times the integral). */
static double deposit_linear(lt_accum_t *A, double t[3][2], const double e[3], rt_rgb_t w,
                             double cell_area) {
  const lt_map_t *m = A->m;
  double det =
      (t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[2][0] - t[0][0]) * (t[1][1] - t[0][1]);
  if (!(fabs(det) > 1e-300) || !isfinite(det))
    return 0.0;
  double x0 = fmin(t[0][0], fmin(t[1][0], t[2][0])), x1 = fmax(t[0][0], fmax(t[1][0], t[2][0]));
  double y0 = fmin(t[0][1], fmin(t[1][1], t[2][1])), y1 = fmax(t[0][1], fmax(t[1][1], t[2][1]));
  int i0 = (int)fmax(0.0, floor(x0)), i1 = (int)fmin(m->width - 1.0, floor(x1));
  int j0 = (int)fmax(0.0, floor(y0)), j1 = (int)fmin(m->height - 1.0, floor(y1));
  double on = 0.0;
  for (int j = j0; j <= j1; j++) {
    double row[8][2], tmp[8][2];
    int n = clip(t, 3, 1, j, -1, tmp);
    n = clip(tmp, n, 1, j + 1, 1, row);
    if (n < 3)
      continue;
    for (int i = i0; i <= i1; i++) {
      double cl[10][2], c2[10][2], c[2];
      int q = clip(row, n, 0, i, -1, c2);
      q = clip(c2, q, 0, i + 1, 1, cl);
      if (q < 3)
        continue;
      double a = area_centroid(cl, q, c);
      /* barycentric coordinates of the part's centroid */
      double l1 =
                 ((c[0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[2][0] - t[0][0]) * (c[1] - t[0][1])) /
                 det,
             l2 =
                 ((t[1][0] - t[0][0]) * (c[1] - t[0][1]) - (c[0] - t[0][0]) * (t[1][1] - t[0][1])) /
                 det;
      double f = a * cell_area * ((1 - l1 - l2) * e[0] + l1 * e[1] + l2 * e[2]);
      add(A, i, j, rt_rgb_scale(w, f));
      on += f;
    }
  }
  return on * mean(w);
}

void lt__deposit_gouraud(lt_accum_t *A, const double (*uv)[2], const double *e, int n,
                         const double c[2], double ec, rt_rgb_t w) {
  const lt_map_t *m = A->m;
  double sx = m->width / (m->u1 - m->u0), sy = m->height / (m->v1 - m->v0);
  double cell_area = 1.0 / (sx * sy), total = 0.0, on = 0.0;
  for (int k = 0; k < n; k++) {
    int j = (k + 1) % n;
    double t[3][2] = {{(c[0] - m->u0) * sx, (c[1] - m->v0) * sy},
                      {(uv[k][0] - m->u0) * sx, (uv[k][1] - m->v0) * sy},
                      {(uv[j][0] - m->u0) * sx, (uv[j][1] - m->v0) * sy}};
    double ek[3] = {ec, e[k], e[j]};
    double at =
        0.5 * fabs((uv[k][0] - c[0]) * (uv[j][1] - c[1]) - (uv[j][0] - c[0]) * (uv[k][1] - c[1]));
    total += at * (ec + e[k] + e[j]) / 3.0;
    on += deposit_linear(A, t, ek, w, cell_area);
  }
  total *= mean(w);
  A->st->flux_map += on;
  A->st->flux_outside += total - on;
}
