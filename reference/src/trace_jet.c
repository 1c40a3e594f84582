/* trace_jet.c -- the exact map psi -> psi' (trace_impl.h) once more, written for second-order
 * jets: truncated Taylor polynomials in the four components of psi (value, gradient, Hessian).
 * Forward-mode automatic differentiation gives the Jacobian and the second-order tensor t(2) of
 * section 3.2 to rounding error, without step sizes: an independent check of the __float128
 * second differences in trace_hessian.c. Each operation applies the chain rule
 *     f(a): v = f(a.v), g = f'(a.v) a.g, H = f'(a.v) a.H + f''(a.v) a.g a.g^t. */
#include <math.h>

#include "exact/trace.h"

typedef struct {
  double v;       /* value */
  double g[4];    /* gradient with respect to psi */
  double h[4][4]; /* Hessian, symmetric */
} jet_t;

static jet_t jconst(double c) {
  jet_t r = {0};
  r.v = c;
  return r;
}

static jet_t jvar(double v, int i) {
  jet_t r = jconst(v);
  r.g[i] = 1.0;
  return r;
}

static jet_t jadd(jet_t a, jet_t b) {
  jet_t r;
  r.v = a.v + b.v;
  for (int i = 0; i < 4; i++) {
    r.g[i] = a.g[i] + b.g[i];
    for (int j = 0; j < 4; j++)
      r.h[i][j] = a.h[i][j] + b.h[i][j];
  }
  return r;
}

static jet_t jscale(jet_t a, double s) {
  jet_t r;
  r.v = a.v * s;
  for (int i = 0; i < 4; i++) {
    r.g[i] = a.g[i] * s;
    for (int j = 0; j < 4; j++)
      r.h[i][j] = a.h[i][j] * s;
  }
  return r;
}

static jet_t jsub(jet_t a, jet_t b) {
  return jadd(a, jscale(b, -1.0));
}

static jet_t jmul(jet_t a, jet_t b) {
  jet_t r;
  r.v = a.v * b.v;
  for (int i = 0; i < 4; i++) {
    r.g[i] = a.v * b.g[i] + b.v * a.g[i];
    for (int j = 0; j < 4; j++)
      r.h[i][j] = a.v * b.h[i][j] + b.v * a.h[i][j] + a.g[i] * b.g[j] + a.g[j] * b.g[i];
  }
  return r;
}

/* f(a) for a scalar function with derivatives f1 = f'(a.v), f2 = f''(a.v) */
static jet_t jchain(jet_t a, double f0, double f1, double f2) {
  jet_t r;
  r.v = f0;
  for (int i = 0; i < 4; i++) {
    r.g[i] = f1 * a.g[i];
    for (int j = 0; j < 4; j++)
      r.h[i][j] = f1 * a.h[i][j] + f2 * a.g[i] * a.g[j];
  }
  return r;
}

static jet_t jinv(jet_t a) {
  double i = 1.0 / a.v;
  return jchain(a, i, -i * i, 2.0 * i * i * i);
}

static jet_t jdiv(jet_t a, jet_t b) {
  return jmul(a, jinv(b));
}

static jet_t jsqrt(jet_t a) {
  double s = sqrt(a.v);
  return jchain(a, s, 0.5 / s, -0.25 / (s * a.v));
}

typedef struct {
  jet_t x, y, z;
} jv3_t;

static jv3_t jv3_lift(px_vec3_t a) {
  return (jv3_t){jconst(a.x), jconst(a.y), jconst(a.z)};
}
static jv3_t jv3_add(jv3_t a, jv3_t b) {
  return (jv3_t){jadd(a.x, b.x), jadd(a.y, b.y), jadd(a.z, b.z)};
}
static jv3_t jv3_sub(jv3_t a, jv3_t b) {
  return (jv3_t){jsub(a.x, b.x), jsub(a.y, b.y), jsub(a.z, b.z)};
}
static jv3_t jv3_scale(jv3_t a, jet_t s) {
  return (jv3_t){jmul(a.x, s), jmul(a.y, s), jmul(a.z, s)};
}
static jv3_t jv3_scaled(px_vec3_t a, jet_t s) {
  return (jv3_t){jscale(s, a.x), jscale(s, a.y), jscale(s, a.z)};
}
static jet_t jv3_dot(jv3_t a, jv3_t b) {
  return jadd(jadd(jmul(a.x, b.x), jmul(a.y, b.y)), jmul(a.z, b.z));
}
static jet_t jv3_dotd(px_vec3_t a, jv3_t b) {
  return jadd(jadd(jscale(b.x, a.x), jscale(b.y, a.y)), jscale(b.z, a.z));
}

/* M p (+ b) of a quadric */
static jv3_t jhalf_grad(const ex_quadric_t *q, jv3_t p, int with_b) {
  const double *m = q->m;
  jv3_t g;
  g.x = jadd(jadd(jscale(p.x, m[0]), jscale(p.y, m[1])), jscale(p.z, m[2]));
  g.y = jadd(jadd(jscale(p.x, m[3]), jscale(p.y, m[4])), jscale(p.z, m[5]));
  g.z = jadd(jadd(jscale(p.x, m[6]), jscale(p.y, m[7])), jscale(p.z, m[8]));
  if (with_b) {
    g.x.v += q->b[0];
    g.y.v += q->b[1];
    g.z.v += q->b[2];
  }
  return g;
}

/* the root of F(o + t d) = 0 nearest to t_hint (same selection as trace_impl.h) */
static int jnearest_root(const ex_quadric_t *q, jv3_t o, jv3_t d, double t_hint, jet_t *t) {
  jet_t a = jv3_dot(d, jhalf_grad(q, d, 0));
  jv3_t go = jhalf_grad(q, o, 1);
  jet_t bb = jv3_dot(d, go);
  jet_t c = jadd(jv3_dot(o, go), jv3_dotd(px_vec3(q->b[0], q->b[1], q->b[2]), o));
  c.v += q->c;
  double scale = fabs(bb.v) + fabs(a.v);
  if (fabs(a.v) <= 1e-14 * scale) {
    if (bb.v == 0.0)
      return 0;
    *t = jdiv(jscale(c, -0.5), bb);
    return 1;
  }
  jet_t disc = jsub(jmul(bb, bb), jmul(a, c));
  if (disc.v < 0.0)
    return 0;
  jet_t sq = jsqrt(disc);
  jet_t qq = jscale(jadd(bb, bb.v < 0 ? jscale(sq, -1.0) : sq), -1.0);
  jet_t t1 = jdiv(qq, a), t2 = qq.v != 0.0 ? jdiv(c, qq) : t1;
  *t = fabs(t1.v - t_hint) <= fabs(t2.v - t_hint) ? t1 : t2;
  return 1;
}

px_status_t ex_map_jet(const ex_system_t *sys, const ex_axial_t *ax, const double psi0[4],
                       double out[4], double jac[4][4], double hess[4][4][4]) {
  jet_t p[4];
  for (int i = 0; i < 4; i++)
    p[i] = jvar(psi0[i], i);
  const px_frame_t *f = &sys->frame;
  jet_t xi2 = jadd(jmul(p[2], p[2]), jmul(p[3], p[3]));
  if (!(xi2.v < 1.0))
    return PX_EINVAL;
  jv3_t o =
      jv3_add(jv3_lift(sys->origin), jv3_add(jv3_scaled(f->x1, p[0]), jv3_scaled(f->x2, p[1])));
  jet_t zeta = jsqrt(jsub(jconst(1.0), xi2));
  jv3_t d =
      jv3_add(jv3_add(jv3_scaled(f->x1, p[2]), jv3_scaled(f->x2, p[3])), jv3_scaled(f->z, zeta));
  double n1 = sys->n0;
  for (size_t k = 0; k < ax->n; k++) {
    const ex_stage_t *st = &sys->stage[k];
    jet_t t;
    if (!jnearest_root(&st->surface, o, d, ax->t[k], &t))
      return PX_EMISS;
    o = jv3_add(o, jv3_scale(d, t));
    jv3_t g = jhalf_grad(&st->surface, o, 1);
    jet_t gn = jsqrt(jv3_dot(g, g));
    if (!(gn.v > 0.0))
      return PX_ESINGULAR;
    jv3_t nrm = jv3_scale(g, jinv(gn));
    jet_t ci = jv3_dot(nrm, d);
    if (ci.v < 0.0) {
      nrm = jv3_scale(nrm, jconst(-1.0));
      ci = jscale(ci, -1.0);
    }
    if (st->event == PX_EVENT_REFLECT) {
      d = jv3_sub(d, jv3_scale(nrm, jscale(ci, 2.0)));
    } else {
      double eta = n1 / st->n_after;
      jet_t k2 = jadd(jconst(1.0), jscale(jsub(jconst(1.0), jmul(ci, ci)), -eta * eta));
      if (k2.v < 0.0)
        return PX_ETIR;
      jet_t coef = jsub(jsqrt(k2), jscale(ci, eta));
      d = jv3_add(jv3_scale(d, jconst(eta)), jv3_scale(nrm, coef));
      n1 = st->n_after;
    }
    d = jv3_scale(d, jinv(jsqrt(jv3_dot(d, d))));
  }
  const px_frame_t *g = &ax->out_frame;
  jet_t denom = jv3_dotd(g->z, d);
  if (!(denom.v > PX_COS_MIN))
    return PX_EGRAZING;
  jv3_t rel = jv3_sub(o, jv3_lift(ax->out_origin));
  jet_t t = jscale(jdiv(jv3_dotd(g->z, rel), denom), -1.0);
  rel = jv3_add(rel, jv3_scale(d, t));
  jet_t r[4] = {jv3_dotd(g->x1, rel), jv3_dotd(g->x2, rel), jv3_dotd(g->x1, d), jv3_dotd(g->x2, d)};
  for (int i = 0; i < 4; i++) {
    if (!isfinite(r[i].v))
      return PX_ENONFINITE;
    if (out)
      out[i] = r[i].v;
    for (int j = 0; j < 4; j++) {
      if (jac)
        jac[i][j] = r[i].g[j];
      if (hess)
        for (int k = 0; k < 4; k++)
          hess[i][j][k] = r[i].h[j][k];
    }
  }
  return PX_OK;
}
