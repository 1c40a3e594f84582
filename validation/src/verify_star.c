/* verify_star.c -- `pencil verify star` (validation/star.h): the cross-screen filter's
 * linearisation (1989 Eq. 16) against a plate simulated by exact refraction. */
#include "validation/star.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/json.h"
#include "io/output.h"

/* Refract unit d at a surface of unit normal nn facing it (d . nn < 0), from index n1 into n2:
 * 0 on total internal reflection. */
static int refract(const double d[3], const double nn[3], double n1, double n2, double out[3]) {
  double eta = n1 / n2, c = -(d[0] * nn[0] + d[1] * nn[1] + d[2] * nn[2]);
  double k = 1.0 - eta * eta * (1.0 - c * c);
  if (k < 0.0)
    return 0;
  double t = eta * c - sqrt(k);
  for (int i = 0; i < 3; i++)
    out[i] = eta * d[i] + t * nn[i];
  return 1;
}

int val_star_exact(double n, double s, double phi, double d, double x[2]) {
  double r = sqrt(1.0 + s * s);
  const double d0[3] = {0.0, 0.0, 1.0};
  const double front[3] = {s * cos(phi) / r, s * sin(phi) / r, -1.0 / r};
  const double back[3] = {0.0, 0.0, -1.0}; /* facing the ray inside the plate */
  double d1[3], d2[3];
  if (!refract(d0, front, 1.0, n, d1) || !refract(d1, back, n, 1.0, d2))
    return 0;
  x[0] = d * d2[0] / d2[2];
  x[1] = d * d2[1] / d2[2];
  return 1;
}

/* The linear landing point (n - 1) d (N_x, N_y) of the same normal. */
static void linear(double n, double s, double phi, double d, double x[2]) {
  double r = sqrt(1.0 + s * s);
  x[0] = (n - 1.0) * d * s * cos(phi) / r;
  x[1] = (n - 1.0) * d * s * sin(phi) / r;
}

/* The linearisation's relative error at slope s (sign: +1 or -1, the convention of N), INFINITY
 * past total internal reflection. */
static double rel_error(double n, double s, double phi, double d, double sign) {
  double xe[2], xl[2];
  linear(n, s, phi, d, xl);
  if (!val_star_exact(n, s, phi, d, xe))
    return INFINITY;
  return hypot(xe[0] - sign * xl[0], xe[1] - sign * xl[1]) / hypot(xl[0], xl[1]);
}

/* The slope in [lo, hi] where the relative error crosses t (it is below at lo, above at hi), by
 * bisection. */
static double crossing(double n, double phi, double d, double sign, double t, double lo,
                       double hi) {
  for (int k = 0; k < 60; k++) {
    double mid = 0.5 * (lo + hi);
    if (rel_error(n, mid, phi, d, sign) > t)
      hi = mid;
    else
      lo = mid;
  }
  return 0.5 * (lo + hi);
}

/* Mass of the slope profile (1 - w2) N(0, s1) + w2 N(0, s2) in [a, b]. */
static double profile_mass(double a, double b, double s1, double s2, double w2) {
  double m1 = 0.5 * (erf(b / (s1 * M_SQRT2)) - erf(a / (s1 * M_SQRT2)));
  double m2 = 0.5 * (erf(b / (s2 * M_SQRT2)) - erf(a / (s2 * M_SQRT2)));
  return (1.0 - w2) * m1 + w2 * m2;
}

typedef struct {
  double s1, s2, w2;
  double tv;        /* total variation distance between the two histograms */
  double rms_exact; /* RMS landing distance, exact (mm) */
  double rms_linear;
  double lost;  /* light lost to total internal reflection */
  double mass;  /* light the linear histogram holds (1 less the truncated tails) */
  double massx; /* ... the exact one, plus what TIR took */
} plate_t;

/* The star's profile along a ray: slopes on a fine grid, each slope's light at its exact and at
 * its linear landing point, histogrammed on the same bins. */
static int plate_profile(double n, double d, plate_t *p) {
  double smax = 6.0 * fmax(p->s1, p->s2), ds = fmin(p->s1, p->s2) / 200.0;
  double bw = (n - 1.0) * d * fmin(p->s1, p->s2) / 10.0;
  double range = 4.0 * (n - 1.0) * d * smax + 2.0 * d; /* exact points can land farther */
  int nb = 2 * (int)ceil(range / bw) + 1, half = nb / 2;
  double *he = calloc((size_t)nb, sizeof *he), *hl = calloc((size_t)nb, sizeof *hl);
  if (!he || !hl) {
    free(he);
    free(hl);
    return -1;
  }
  double se = 0.0, sl = 0.0, me = 0.0, ml = 0.0;
  p->lost = 0.0;
  long steps = (long)ceil(2.0 * smax / ds);
  for (long k = 0; k < steps; k++) {
    double a = -smax + k * ds, b = a + ds, s = 0.5 * (a + b);
    double m = profile_mass(a, b, p->s1, p->s2, p->w2), xe[2], xl[2];
    linear(n, s, 0.0, d, xl);
    int bl = half + (int)lrint(xl[0] / bw);
    if (bl >= 0 && bl < nb) {
      hl[bl] += m;
      ml += m;
      sl += m * xl[0] * xl[0];
    }
    if (!val_star_exact(n, s, 0.0, d, xe)) {
      p->lost += m;
      continue;
    }
    int be = half + (int)lrint(xe[0] / bw);
    if (be >= 0 && be < nb) {
      he[be] += m;
      me += m;
      se += m * xe[0] * xe[0];
    }
  }
  double tv = 0.0;
  for (int b = 0; b < nb; b++)
    tv += fabs(he[b] - hl[b]);
  p->tv = 0.5 * tv;
  p->rms_exact = me > 0 ? sqrt(se / me) : 0.0;
  p->rms_linear = ml > 0 ? sqrt(sl / ml) : 0.0;
  p->mass = ml;
  p->massx = me + p->lost;
  free(he);
  free(hl);
  return 0;
}

int val_verify_star(const val_star_opts_t *o) {
  const double d = 50.0; /* mm; the relative errors do not depend on it */
  const double indices[3] = {1.33, 1.5, 1.9}, phis[2] = {0.0, 30.0};
  int nslopes = o->quick ? 25 : 121;
  FILE *csv = NULL;
  char err[1024];
  io_atomic_t ac;
  if (o->csv) {
    if (io_csv_open(&ac, o->csv, err, sizeof err) != 0) {
      fprintf(stderr, "pencil verify star: %s\n", err);
      return -1;
    }
    csv = ac.f;
    fprintf(csv, "n,phi_deg,slope,exact_x,exact_y,linear_x,linear_y,relative_error,tir\n");
  }
  int fail = 0;
  json_t *rows = json_array();
  FILE *f = o->report;
  if (f)
    fprintf(f,
            "pencil verify star: the cross-screen filter's linearisation (1989 Eq. 16) against "
            "exact refraction through the plate\n\n%-5s %-5s %12s %7s %14s %14s %12s\n",
            "n", "phi", "err@1e-4", "sign", "slope at 1%", "slope at 10%", "TIR from");
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 2; j++) {
      double n = indices[i], phi = phis[j] * M_PI / 180.0;
      double first = NAN, sign = 0.0, at1 = NAN, at10 = NAN, tir = NAN;
      double prev = 0.0;
      for (int k = 0; k < nslopes; prev = 1e-4 * pow(2.0e4, (double)k / (nslopes - 1)), k++) {
        double s = 1e-4 * pow(2.0e4, (double)k / (nslopes - 1)); /* 1e-4 .. 2 */
        double xe[2], xl[2];
        linear(n, s, phi, d, xl);
        int ok = val_star_exact(n, s, phi, d, xe);
        double rel = NAN;
        if (ok) {
          double ll = hypot(xl[0], xl[1]);
          if (k == 0) /* the sign convention: along N or against it */
            sign = (xe[0] * xl[0] + xe[1] * xl[1]) > 0 ? 1.0 : -1.0;
          rel = hypot(xe[0] - sign * xl[0], xe[1] - sign * xl[1]) / ll;
          if (k == 0)
            first = rel;
          if (isnan(at1) && rel > 0.01)
            at1 = crossing(n, phi, d, sign, 0.01, prev, s);
          if (isnan(at10) && rel > 0.1)
            at10 = crossing(n, phi, d, sign, 0.1, prev, s);
        } else if (isnan(tir)) {
          tir = crossing(n, phi, d, sign, 1e300, prev, s); /* where the error turns infinite */
        }
        if (csv)
          fprintf(csv, "%.4g,%g,%.10g,%.10g,%.10g,%.10g,%.10g,%.6g,%d\n", n, phis[j], s,
                  ok ? xe[0] : NAN, ok ? xe[1] : NAN, sign * xl[0], sign * xl[1], rel, !ok);
      }
      int pass = first < 1e-6;
      fail |= !pass;
      if (f)
        fprintf(f, "%-5.3g %-5g %12.2e %7s %14.4g %14.4g %12.4g%s\n", n, phis[j], first,
                sign > 0 ? "+N" : "-N", at1, at10, tir, pass ? "" : "  FAIL");
      json_array_append_new(rows,
                            json_pack("{s:f, s:f, s:o, s:s, s:o, s:o, s:o, s:b}", "n", n, "phi_deg",
                                      phis[j], "relative_error_at_1e-4", io_json_number(first),
                                      "sign", sign > 0 ? "+N" : "-N", "slope_at_1pct",
                                      io_json_number(at1), "slope_at_10pct", io_json_number(at10),
                                      "tir_from_slope", io_json_number(tir), "pass", pass));
    }
  /* the star's profile for plates from fine to coarse scratches, n = 1.5 */
  const double plates[4][3] = {
      {0.005, 0.03, 0.5}, {0.02, 0.1, 0.5}, {0.05, 0.3, 0.5}, {0.1, 0.6, 0.5}};
  int nplates = o->quick ? 2 : 4;
  json_t *profiles = json_array();
  if (f)
    fprintf(f,
            "\nthe star's profile along a ray, n = 1.5 (exact landing against Eq. 16's, same "
            "bins)\n%-14s %10s %12s %12s %10s %12s\n",
            "sigma1,sigma2", "TV dist.", "RMS exact", "RMS Eq.16", "ratio", "lost to TIR");
  for (int q = 0; q < nplates; q++) {
    plate_t p = {plates[q][0], plates[q][1], plates[q][2], 0, 0, 0, 0, 0, 0};
    if (plate_profile(1.5, d, &p) != 0) {
      fprintf(stderr, "pencil verify star: out of memory\n");
      fail = 1;
      break;
    }
    /* both histograms hold the light of the same slopes */
    int pass = fabs(p.mass - p.massx) < 1e-6;
    fail |= !pass;
    if (f)
      fprintf(f, "%6g,%-7g %10.3e %12.5g %12.5g %10.5f %12.3e%s\n", p.s1, p.s2, p.tv, p.rms_exact,
              p.rms_linear, p.rms_exact / p.rms_linear, p.lost, pass ? "" : "  FAIL");
    json_array_append_new(profiles, json_pack("{s:f, s:f, s:f, s:f, s:f, s:f, s:f, s:f}", "sigma1",
                                              p.s1, "sigma2", p.s2, "weight2", p.w2, "tv_distance",
                                              p.tv, "rms_exact_mm", p.rms_exact, "rms_linear_mm",
                                              p.rms_linear, "rms_ratio", p.rms_exact / p.rms_linear,
                                              "lost_to_tir", p.lost));
  }
  int rc = fail ? 1 : 0;
  if (csv && io_atomic_commit(&ac, err, sizeof err) != 0) {
    fprintf(stderr, "pencil verify star: %s\n", err);
    rc = -1;
  }
  json_t *root = json_pack("{s:s, s:f, s:o, s:o, s:b}", "verification", "star", "focal_mm", d,
                           "slopes", rows, "profiles", profiles, "pass", !fail);
  if (o->json && io_json_write(o->json, root, err, sizeof err) != 0) {
    fprintf(stderr, "pencil verify star: %s\n", err);
    rc = -1;
  }
  json_decref(root);
  if (f)
    fprintf(f, "\n%s\n",
            fail ? "FAIL: the linearisation does not agree with exact refraction to first order"
                 : "the linearisation agrees with exact refraction to first order");
  return rc;
}
