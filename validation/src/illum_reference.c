/* illum_reference.c -- the exact illuminance of a rotationally symmetric case (val_ring_map): a
 * glass ball over a floor lit along its axis. A ray in a meridional plane at parameter t (its
 * distance b from the axis for a parallel light, its angle theta from the axis for a point
 * light) is traced exactly in two dimensions (Snell's law at the ball's entry and exit) to where
 * it lands on the floor, at signed radius rho(t). Between neighbouring t the light fills an
 * annulus of the floor whose radii are the two landings, and carries the flux of the ring of
 * source parameters (pi (b2^2 - b1^2) I, or 2 pi (cos th1 - cos th2) I). Spreading each ring's
 * flux evenly over its annulus and summing gives every cell's average to the resolution of the
 * rings: with 10^5 .. 10^6 of them, far below the maps' errors. Area of a disk within a cell in
 * closed form. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "validation/illum_bench.h"

/* Area of {0 <= s <= x, 0 <= t <= y, s^2 + t^2 <= r^2} for x, y >= 0. */
static double quad_area(double x, double y, double r) {
  if (x <= 0 || y <= 0 || r <= 0)
    return 0.0;
  if (x * x + y * y <= r * r)
    return x * y;
  double xs = fmin(x, r), ss = y < r ? sqrt(r * r - y * y) : 0.0; /* t = y for s <= ss */
  double a = fmin(ss, xs);
#define G(s) (0.5 * ((s)*sqrt(fmax(r * r - (s) * (s), 0.0)) + r * r * asin(fmin((s) / r, 1.0))))
  return y * a + G(xs) - G(a);
#undef G
}

/* Signed corner function: the area of the disk within [0, x] x [0, y], signed by quadrant. */
static double corner(double x, double y, double r) {
  double s = (x < 0) != (y < 0) ? -1.0 : 1.0;
  return s * quad_area(fabs(x), fabs(y), r);
}

/* Area of the disk of radius r within [x0, x1] x [y0, y1]. */
static double disk_rect(double x0, double x1, double y0, double y1, double r) {
  return corner(x1, y1, r) - corner(x0, y1, r) - corner(x1, y0, r) + corner(x0, y0, r);
}

/* 2-D refraction of unit d at unit normal nn (facing against d), n1 -> n2; 0 on TIR. */
static int refract2(double d[2], const double nn[2], double n1, double n2) {
  double ci = -(d[0] * nn[0] + d[1] * nn[1]), eta = n1 / n2, k = 1 - eta * eta * (1 - ci * ci);
  if (k < 0)
    return 0;
  double c = eta * ci - sqrt(k);
  d[0] = eta * d[0] + c * nn[0];
  d[1] = eta * d[1] + c * nn[1];
  double l = hypot(d[0], d[1]);
  d[0] /= l;
  d[1] /= l;
  return 1;
}

/* Where the ray from o along d (y up, the ball at (0, h)) lands on the floor y = 0: 1 with *rho,
 * 0 when it leaves upwards or sideways. From inside the ball (a source there) it leaves first. */
static int land(double o[2], double d[2], double r, double n, double h, double *rho) {
  double c[2] = {0.0, h}, oc[2] = {o[0] - c[0], o[1] - c[1]};
  double bq = oc[0] * d[0] + oc[1] * d[1], cq = oc[0] * oc[0] + oc[1] * oc[1] - r * r;
  double disc = bq * bq - cq;
  if (cq < 0) { /* inside: to the exit, t = -bq + sqrt(disc) */
    double t = -bq + sqrt(disc);
    double p[2] = {o[0] + t * d[0], o[1] + t * d[1]};
    double nx[2] = {-(p[0] - c[0]) / r, -(p[1] - c[1]) / r}; /* facing the ray, inside */
    if (!refract2(d, nx, n, 1.0))
      return 0;
    o[0] = p[0];
    o[1] = p[1];
  } else if (disc > 0 && -bq - sqrt(disc) > 0) { /* enters the ball */
    double t = -bq - sqrt(disc);
    double p[2] = {o[0] + t * d[0], o[1] + t * d[1]};
    double nn[2] = {(p[0] - c[0]) / r, (p[1] - c[1]) / r};
    if (!refract2(d, nn, 1.0, n))
      return 0;
    /* the chord to the exit: t = -2 (p - c) . d */
    double t2 = -2.0 * ((p[0] - c[0]) * d[0] + (p[1] - c[1]) * d[1]);
    p[0] += t2 * d[0];
    p[1] += t2 * d[1];
    double nx[2] = {-(p[0] - c[0]) / r, -(p[1] - c[1]) / r}; /* facing the ray, inside */
    if (!refract2(d, nx, n, 1.0))
      return 0;
    o[0] = p[0];
    o[1] = p[1];
  }
  if (!(d[1] < 0))
    return 0;
  *rho = o[0] - o[1] / d[1] * d[0];
  return 1;
}

void val_ring_map(double r, double n, double h, double source_height, long rays, lt_map_t *m,
                  unsigned char *smooth) {
  int parallel = source_height <= 0;
  size_t cells = (size_t)m->width * (size_t)m->height;
  double *flux = calloc(cells, sizeof *flux);
  double du = (m->u1 - m->u0) / m->width, dv = (m->v1 - m->v0) / m->height;
  double rmax = 0.0; /* the map's farthest corner from the axis */
  for (int k = 0; k < 4; k++)
    rmax = fmax(rmax, hypot(k & 1 ? m->u1 : m->u0, k & 2 ? m->v1 : m->v0));
  /* the radial profile: flux per annulus of NB bins up to rmax */
  enum { NB = 8192 };
  double *bin = calloc(NB, sizeof *bin);
  /* parameters: b in [0, rmax] (beyond, rays land beyond the map); theta up to the direction
   * that reaches rmax directly or just grazes the ball, whichever is larger */
  double tmax = parallel ? rmax
                : fabs(source_height - h) < r
                    ? M_PI /* inside the ball: every direction */
                    : fmax(atan(rmax / source_height), asin(fmin(1.0, r / (source_height - h))));
  double prev_rho = 0.0, prev_t = 0.0;
  int prev_ok = 0;
  for (long k = 0; k <= rays && flux && bin; k++) {
    double t = tmax * (double)k / (double)rays, rho = 0.0;
    double o[2], d[2];
    if (parallel) {
      o[0] = t;
      o[1] = h + 2 * r + 1;
      d[0] = 0;
      d[1] = -1;
    } else {
      o[0] = 0;
      o[1] = source_height;
      d[0] = sin(t);
      d[1] = -cos(t);
    }
    int ok = land(o, d, r, n, h, &rho);
    if (ok && prev_ok && k > 0) {
      double phi = parallel ? M_PI * (t * t - prev_t * prev_t) : 2 * M_PI * (cos(prev_t) - cos(t));
      double ra = fmin(fabs(rho), fabs(prev_rho)), rb = fmax(fabs(rho), fabs(prev_rho));
      if ((rho < 0) != (prev_rho < 0))
        ra = 0.0;
      double ring = M_PI * (rb * rb - ra * ra);
      if (ring > 0 && ra < rmax) {
        /* cells that meet the annulus: per row, those between the hole and the outer circle */
        int j0 = (int)fmax(0, floor((-rb - m->v0) / dv));
        int j1 = (int)fmin(m->height - 1, floor((rb - m->v0) / dv));
        for (int j = j0; j <= j1; j++) {
          double y0 = m->v0 + j * dv, y1 = y0 + dv;
          double ynear = fmax(0, fmax(y0, -y1)), yfar = fmax(fabs(y0), fabs(y1));
          if (ynear >= rb)
            continue;
          double xout = sqrt(rb * rb - ynear * ynear), xin = sqrt(fmax(ra * ra - yfar * yfar, 0));
          /* cells with x in [-xout, -xin] or [xin, xout], each once */
          int a0 = (int)floor((-xout - m->u0) / du), a1 = (int)floor((-xin - m->u0) / du);
          int c0 = (int)floor((xin - m->u0) / du), c1 = (int)floor((xout - m->u0) / du);
          if (c0 <= a1)
            c0 = a1 + 1;
          for (int sp = 0; sp < 2; sp++)
            for (int i = (int)fmax(0, sp ? c0 : a0); i <= (sp ? c1 : a1) && i < m->width; i++) {
              double x0 = m->u0 + i * du, x1 = x0 + du;
              double a = disk_rect(x0, x1, y0, y1, rb) - disk_rect(x0, x1, y0, y1, ra);
              flux[(size_t)j * m->width + i] += phi * a / ring;
            }
        }
        /* the radial profile */
        int b0 = (int)(ra / rmax * NB), b1 = (int)fmin(NB - 1, rb / rmax * NB);
        for (int b = b0; b <= b1 && b < NB; b++) {
          double lo = fmax(ra, b * rmax / NB), hi = fmin(rb, (b + 1) * rmax / NB);
          if (hi > lo)
            bin[b] += phi * M_PI * (hi * hi - lo * lo) / ring;
        }
      }
    }
    prev_ok = ok;
    prev_rho = rho;
    prev_t = t;
  }
  for (size_t k = 0; k < cells; k++) {
    double e = flux ? flux[k] / (du * dv) : NAN;
    m->e[3 * k] = m->e[3 * k + 1] = m->e[3 * k + 2] = e;
  }
  if (smooth) {
    for (int j = 0; j < m->height; j++)
      for (int i = 0; i < m->width; i++) {
        double x0 = m->u0 + i * du, x1 = x0 + du, y0 = m->v0 + j * dv, y1 = y0 + dv;
        double rn = hypot(fmax(0, fmax(x0, -x1)), fmax(0, fmax(y0, -y1)));
        double rf = hypot(fmax(fabs(x0), fabs(x1)), fmax(fabs(y0), fabs(y1)));
        int b0 = (int)(rn / rmax * NB), b1 = (int)fmin(NB - 1, rf / rmax * NB);
        double lo = INFINITY, hi = 0.0;
        for (int b = b0; b <= b1 && bin; b++) {
          double a = M_PI * (pow((b + 1) * rmax / NB, 2) - pow(b * rmax / NB, 2));
          double e = bin[b] / a;
          lo = fmin(lo, e);
          hi = fmax(hi, e);
        }
        smooth[(size_t)j * m->width + i] = lo > 0 && hi <= 1.1 * lo;
      }
  }
  free(flux);
  free(bin);
}
