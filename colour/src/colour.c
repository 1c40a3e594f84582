/* colour.c -- the colour science of colour.h. */
#include "colour/colour.h"

#include <math.h>

#include "cmf_table.h"

static double step(void) {
  return (cs__cmf_end - cs__cmf_start) / (cs__cmf_bands - 1);
}

void cs_cmf_range(double *lo_nm, double *hi_nm) {
  *lo_nm = cs__cmf_start;
  *hi_nm = cs__cmf_end;
}

static void row(int k, double xyz[3]) {
  xyz[0] = cs__cmf_x[k];
  xyz[1] = cs__cmf_y[k];
  xyz[2] = cs__cmf_z[k];
}

void cs_cmf(double lambda_nm, double xyz[3]) {
  xyz[0] = xyz[1] = xyz[2] = 0.0;
  double u = (lambda_nm - cs__cmf_start) / step();
  if (!(u >= 0.0 && u <= cs__cmf_bands - 1))
    return;
  int k = (int)u;
  if (k >= cs__cmf_bands - 1)
    k = cs__cmf_bands - 2;
  double f = u - k, a[3], b[3];
  row(k, a);
  row(k + 1, b);
  for (int c = 0; c < 3; c++)
    xyz[c] = (1.0 - f) * a[c] + f * b[c];
}

void cs_cmf_integral(double a_nm, double b_nm, double xyz[3]) {
  xyz[0] = xyz[1] = xyz[2] = 0.0;
  double h = step();
  double a = fmax(a_nm, cs__cmf_start), b = fmin(b_nm, cs__cmf_end);
  if (!(b > a))
    return;
  /* the trapezoid rule between a, the table's rows inside (a, b), and b: exact for a function
   * linear between rows */
  double x0 = a, f0[3];
  cs_cmf(x0, f0);
  int k = (int)floor((a - cs__cmf_start) / h) + 1;
  for (;; k++) {
    double x1 = k < cs__cmf_bands ? cs__cmf_start + k * h : b, f1[3];
    if (x1 > b)
      x1 = b;
    cs_cmf(x1, f1);
    for (int c = 0; c < 3; c++)
      xyz[c] += 0.5 * (x1 - x0) * (f0[c] + f1[c]);
    if (x1 >= b)
      break;
    x0 = x1;
    for (int c = 0; c < 3; c++)
      f0[c] = f1[c];
  }
}

/* XYZ of chromaticity (x, y) at Y = 1. */
static void xyz_of(double x, double y, double out[3]) {
  out[0] = x / y;
  out[1] = 1.0;
  out[2] = (1.0 - x - y) / y;
}

void cs_white_d65(double xyz[3]) {
  xyz_of(0.3127, 0.3290, xyz);
}

static double det3(double m[3][3]) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

static void inverse3(double m[3][3], double out[3][3]) {
  double d = det3(m);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
      out[i][j] = (m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1]) / d;
    }
}

void cs_xyz_from_srgb(double m[3][3]) {
  /* the columns are the primaries' XYZ, scaled so that (1, 1, 1) is the white */
  const double prim[3][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}};
  double p[3][3], pi[3][3], w[3], s[3];
  for (int j = 0; j < 3; j++) {
    double c[3];
    xyz_of(prim[j][0], prim[j][1], c);
    for (int i = 0; i < 3; i++)
      p[i][j] = c[i];
  }
  cs_white_d65(w);
  inverse3(p, pi);
  for (int j = 0; j < 3; j++)
    s[j] = pi[j][0] * w[0] + pi[j][1] * w[1] + pi[j][2] * w[2];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      m[i][j] = p[i][j] * s[j];
}

void cs_srgb_from_xyz(double m[3][3]) {
  double t[3][3];
  cs_xyz_from_srgb(t);
  inverse3(t, m);
}

static double lab_f(double t) {
  const double d = 6.0 / 29.0;
  return t > d * d * d ? cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
}

void cs_lab_from_xyz(const double xyz[3], const double white[3], double lab[3]) {
  double fx = lab_f(xyz[0] / white[0]), fy = lab_f(xyz[1] / white[1]),
         fz = lab_f(xyz[2] / white[2]);
  lab[0] = 116.0 * fy - 16.0;
  lab[1] = 500.0 * (fx - fy);
  lab[2] = 200.0 * (fy - fz);
}

void cs_lab_from_srgb(const double rgb[3], double lab[3]) {
  double m[3][3], xyz[3], w[3];
  cs_xyz_from_srgb(m);
  for (int i = 0; i < 3; i++)
    xyz[i] = m[i][0] * rgb[0] + m[i][1] * rgb[1] + m[i][2] * rgb[2];
  cs_white_d65(w);
  cs_lab_from_xyz(xyz, w, lab);
}

static double deg(double r) {
  return r * (180.0 / M_PI);
}

static double rad(double d) {
  return d * (M_PI / 180.0);
}

/* h' in degrees, [0, 360); 0 for the achromatic a' = b = 0 (Sharma et al., Eq. 4) */
static double hue(double a, double b) {
  if (a == 0.0 && b == 0.0)
    return 0.0;
  double h = deg(atan2(b, a));
  return h < 0.0 ? h + 360.0 : h;
}

double cs_delta_e2000(const double lab1[3], const double lab2[3]) {
  const double p25 = 6103515625.0; /* 25^7 */
  double L1 = lab1[0], a1 = lab1[1], b1 = lab1[2], L2 = lab2[0], a2 = lab2[1], b2 = lab2[2];
  double cbar = 0.5 * (hypot(a1, b1) + hypot(a2, b2)), c7 = pow(cbar, 7.0);
  double g = 0.5 * (1.0 - sqrt(c7 / (c7 + p25)));
  double ap1 = (1.0 + g) * a1, ap2 = (1.0 + g) * a2;
  double cp1 = hypot(ap1, b1), cp2 = hypot(ap2, b2);
  double hp1 = hue(ap1, b1), hp2 = hue(ap2, b2);
  double dL = L2 - L1, dC = cp2 - cp1, dh = 0.0;
  if (cp1 * cp2 != 0.0) {
    dh = hp2 - hp1;
    if (dh > 180.0)
      dh -= 360.0;
    else if (dh < -180.0)
      dh += 360.0;
  }
  double dH = 2.0 * sqrt(cp1 * cp2) * sin(rad(0.5 * dh));
  double Lb = 0.5 * (L1 + L2), Cb = 0.5 * (cp1 + cp2), hb = hp1 + hp2;
  if (cp1 * cp2 != 0.0) {
    if (fabs(hp1 - hp2) <= 180.0)
      hb *= 0.5;
    else
      hb = hb < 360.0 ? 0.5 * (hb + 360.0) : 0.5 * (hb - 360.0);
  }
  double T = 1.0 - 0.17 * cos(rad(hb - 30.0)) + 0.24 * cos(rad(2.0 * hb)) +
             0.32 * cos(rad(3.0 * hb + 6.0)) - 0.20 * cos(rad(4.0 * hb - 63.0));
  double dtheta = 30.0 * exp(-((hb - 275.0) / 25.0) * ((hb - 275.0) / 25.0));
  double cb7 = pow(Cb, 7.0), Rc = 2.0 * sqrt(cb7 / (cb7 + p25));
  double l50 = (Lb - 50.0) * (Lb - 50.0);
  double Sl = 1.0 + 0.015 * l50 / sqrt(20.0 + l50), Sc = 1.0 + 0.045 * Cb,
         Sh = 1.0 + 0.015 * Cb * T;
  double Rt = -sin(rad(2.0 * dtheta)) * Rc;
  double tl = dL / Sl, tc = dC / Sc, th = dH / Sh;
  return sqrt(tl * tl + tc * tc + th * th + Rt * tc * th);
}

int cs_bins(int n, double lo_nm, double hi_nm, double *centre, double (*w)[3]) {
  if (n < 1 || !(lo_nm < hi_nm) || !(lo_nm >= cs__cmf_start) || !(hi_nm <= cs__cmf_end))
    return -1;
  double m[3][3], total[3] = {0, 0, 0}, h = (hi_nm - lo_nm) / n;
  cs_srgb_from_xyz(m);
  for (int i = 0; i < n; i++) {
    double a = lo_nm + i * h, b = i == n - 1 ? hi_nm : lo_nm + (i + 1) * h, xyz[3];
    centre[i] = 0.5 * (a + b);
    cs_cmf_integral(a, b, xyz);
    for (int c = 0; c < 3; c++) {
      w[i][c] = m[c][0] * xyz[0] + m[c][1] * xyz[1] + m[c][2] * xyz[2];
      total[c] += w[i][c];
    }
  }
  for (int i = 0; i < n; i++)
    for (int c = 0; c < 3; c++)
      w[i][c] /= total[c];
  return 0;
}
