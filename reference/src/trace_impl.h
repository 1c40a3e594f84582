/* trace_impl.h -- the exact map psi -> psi' of an ex_system_t, written once for any real type.
 *
 * Included by trace_double.c and trace_quad.c with REAL, R_SQRT and FN(name) defined. The ray
 * vector is turned into a real ray (origin O + x1 x1^ + x2 x2^, unit direction with transverse
 * part xi), carried through every stage with the vector form of Snell's law and the mirror law,
 * and expressed in the output ray frame: the point where it crosses the plane through O'
 * normal to z', and the projection of its direction on x1', x2' (section 2.1, Fig. 1).
 */
typedef struct {
  REAL x, y, z;
} FN(v3);

static FN(v3) FN(lift)(px_vec3_t a) {
  return (FN(v3)){a.x, a.y, a.z};
}
static FN(v3) FN(add)(FN(v3) a, FN(v3) b) {
  return (FN(v3)){a.x + b.x, a.y + b.y, a.z + b.z};
}
static FN(v3) FN(sub)(FN(v3) a, FN(v3) b) {
  return (FN(v3)){a.x - b.x, a.y - b.y, a.z - b.z};
}
static FN(v3) FN(scale)(FN(v3) a, REAL s) {
  return (FN(v3)){a.x * s, a.y * s, a.z * s};
}
static REAL FN(dot)(FN(v3) a, FN(v3) b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

/* half gradient M p + b of a quadric */
static FN(v3) FN(half_grad)(const ex_quadric_t *q, FN(v3) p, int with_b) {
  const double *m = q->m;
  FN(v3)
  g = {m[0] * p.x + m[1] * p.y + m[2] * p.z, m[3] * p.x + m[4] * p.y + m[5] * p.z,
       m[6] * p.x + m[7] * p.y + m[8] * p.z};
  if (with_b) {
    g.x += q->b[0];
    g.y += q->b[1];
    g.z += q->b[2];
  }
  return g;
}

/* The root of F(o + t d) = 0 nearest to t_hint; 0 when there is none. */
static int FN(nearest_root)(const ex_quadric_t *q, FN(v3) o, FN(v3) d, REAL t_hint, REAL *t) {
  REAL a = FN(dot)(d, FN(half_grad)(q, d, 0));
  FN(v3) go = FN(half_grad)(q, o, 1);
  REAL bb = FN(dot)(d, go);
  REAL c = FN(dot)(o, go) + q->b[0] * o.x + q->b[1] * o.y + q->b[2] * o.z + q->c;
  REAL scale = (bb < 0 ? -bb : bb) + (a < 0 ? -a : a);
  if ((a < 0 ? -a : a) <= (REAL)1e-14 * scale) {
    if (bb == 0)
      return 0;
    *t = -c / (2 * bb);
    return 1;
  }
  REAL disc = bb * bb - a * c;
  if (disc < 0)
    return 0;
  REAL sq = R_SQRT(disc);
  REAL qq = -(bb + (bb < 0 ? -sq : sq));
  REAL t1 = qq / a, t2 = qq != 0 ? c / qq : t1;
  REAL d1 = t1 - t_hint, d2 = t2 - t_hint;
  *t = (d1 < 0 ? -d1 : d1) <= (d2 < 0 ? -d2 : d2) ? t1 : t2;
  return 1;
}

px_status_t FN(ex_map)(const ex_system_t *sys, const ex_axial_t *ax, const REAL psi[4],
                       REAL out[4]) {
  const px_frame_t *f = &sys->frame;
  REAL xi2 = psi[2] * psi[2] + psi[3] * psi[3];
  if (!(xi2 < 1))
    return PX_EINVAL;
  FN(v3)
  o = FN(add)(FN(lift)(sys->origin),
              FN(add)(FN(scale)(FN(lift)(f->x1), psi[0]), FN(scale)(FN(lift)(f->x2), psi[1])));
  FN(v3)
  d = FN(add)(FN(add)(FN(scale)(FN(lift)(f->x1), psi[2]), FN(scale)(FN(lift)(f->x2), psi[3])),
              FN(scale)(FN(lift)(f->z), R_SQRT(1 - xi2)));
  REAL n1 = sys->n0;
  for (size_t k = 0; k < ax->n; k++) {
    const ex_stage_t *st = &sys->stage[k];
    REAL t;
    if (!FN(nearest_root)(&st->surface, o, d, ax->t[k], &t))
      return PX_EMISS;
    o = FN(add)(o, FN(scale)(d, t));
    FN(v3) g = FN(half_grad)(&st->surface, o, 1);
    REAL gn = R_SQRT(FN(dot)(g, g));
    if (!(gn > 0))
      return PX_ESINGULAR;
    FN(v3) nrm = FN(scale)(g, 1 / gn);
    REAL ci = FN(dot)(nrm, d);
    if (ci < 0) {
      nrm = FN(scale)(nrm, -1);
      ci = -ci;
    }
    if (st->event == PX_EVENT_REFLECT) {
      d = FN(sub)(d, FN(scale)(nrm, 2 * ci));
    } else {
      REAL eta = n1 / st->n_after;
      REAL k2 = 1 - eta * eta * (1 - ci * ci);
      if (k2 < 0)
        return PX_ETIR;
      d = FN(add)(FN(scale)(d, eta), FN(scale)(nrm, R_SQRT(k2) - eta * ci));
      n1 = st->n_after;
    }
    d = FN(scale)(d, 1 / R_SQRT(FN(dot)(d, d)));
  }
  const px_frame_t *g = &ax->out_frame;
  REAL denom = FN(dot)(FN(lift)(g->z), d);
  if (!(denom > (REAL)PX_COS_MIN))
    return PX_EGRAZING;
  FN(v3) rel = FN(sub)(o, FN(lift)(ax->out_origin));
  REAL t = -FN(dot)(FN(lift)(g->z), rel) / denom;
  rel = FN(add)(rel, FN(scale)(d, t));
  out[0] = FN(dot)(FN(lift)(g->x1), rel);
  out[1] = FN(dot)(FN(lift)(g->x2), rel);
  out[2] = FN(dot)(FN(lift)(g->x1), d);
  out[3] = FN(dot)(FN(lift)(g->x2), d);
  return PX_OK;
}

/* Column j of the Jacobian: Richardson extrapolation (4 D(h/2) - D(h)) / 3 of central
 * differences D(h) = (F(h e_j) - F(-h e_j)) / 2h, error O(h^4). */
px_status_t FN(ex_jacobian)(const ex_system_t *sys, const ex_axial_t *ax, double length,
                            px_mat4_t *j) {
  px_mat4_t r;
  for (int col = 0; col < 4; col++) {
    REAL h = (REAL)JAC_STEP * (col < 2 ? (REAL)length : 1);
    REAL dh[2][4];
    for (int level = 0; level < 2; level++) {
      REAL step = level == 0 ? h : h / 2;
      REAL p[4] = {0, 0, 0, 0}, m[4] = {0, 0, 0, 0}, fp[4], fm[4];
      p[col] = step;
      m[col] = -step;
      px_status_t s = FN(ex_map)(sys, ax, p, fp);
      if (s == PX_OK)
        s = FN(ex_map)(sys, ax, m, fm);
      if (s != PX_OK)
        return s;
      for (int i = 0; i < 4; i++)
        dh[level][i] = (fp[i] - fm[i]) / (2 * step);
    }
    for (int i = 0; i < 4; i++)
      r.m[i][col] = (double)((4 * dh[1][i] - dh[0][i]) / 3);
  }
  if (!px_mat4_isfinite(r))
    return PX_ENONFINITE;
  *j = r;
  return PX_OK;
}

/* Where the ray psi crosses the receiver plane through O' with unit normal nrm (in output-frame
 * coordinates x1', x2', z'), as a point in those coordinates. */
static px_status_t FN(receiver_hit)(const ex_system_t *sys, const ex_axial_t *ax, const REAL psi[4],
                                    const REAL nrm[3], REAL hit[3]) {
  REAL o[4];
  px_status_t s = FN(ex_map)(sys, ax, psi, o);
  if (s != PX_OK)
    return s;
  REAL d[3] = {o[2], o[3], R_SQRT(1 - o[2] * o[2] - o[3] * o[3])};
  REAL dn = d[0] * nrm[0] + d[1] * nrm[1] + d[2] * nrm[2];
  if (!(dn > (REAL)PX_COS_MIN || dn < -(REAL)PX_COS_MIN))
    return PX_EGRAZING;
  REAL t = -(o[0] * nrm[0] + o[1] * nrm[1]) / dn;
  hit[0] = o[0] + t * d[0];
  hit[1] = o[1] + t * d[1];
  hit[2] = t * d[2];
  return PX_OK;
}

/* The area the pencil covers on the receiver per unit of the source's measure, |N . (h_1 x h_2)|,
 * h_j the Richardson-extrapolated central difference of the receiver hit along the source's
 * coordinate j (xi_j for a point source, x_j for a parallel one). */
px_status_t FN(ex_flux)(const ex_system_t *sys, const ex_axial_t *ax, px_vec3_t receiver_normal,
                        int parallel, double length, double *area) {
  const px_frame_t *g = &ax->out_frame;
  REAL nrm[3] = {(REAL)px_vec3_dot(receiver_normal, g->x1),
                 (REAL)px_vec3_dot(receiver_normal, g->x2),
                 (REAL)px_vec3_dot(receiver_normal, g->z)};
  REAL nn = R_SQRT(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
  if (!(nn > 0))
    return PX_EINVAL;
  for (int i = 0; i < 3; i++)
    nrm[i] /= nn;
  REAL h[2][3];
  for (int k = 0; k < 2; k++) {
    int col = parallel ? k : 2 + k;
    REAL step0 = (REAL)JAC_STEP * (parallel ? (REAL)length : 1), dh[2][3];
    for (int level = 0; level < 2; level++) {
      REAL step = level == 0 ? step0 : step0 / 2;
      REAL p[4] = {0, 0, 0, 0}, m[4] = {0, 0, 0, 0}, fp[3], fm[3];
      p[col] = step;
      m[col] = -step;
      px_status_t s = FN(receiver_hit)(sys, ax, p, nrm, fp);
      if (s == PX_OK)
        s = FN(receiver_hit)(sys, ax, m, nrm, fm);
      if (s != PX_OK)
        return s;
      for (int i = 0; i < 3; i++)
        dh[level][i] = (fp[i] - fm[i]) / (2 * step);
    }
    for (int i = 0; i < 3; i++)
      h[k][i] = (4 * dh[1][i] - dh[0][i]) / 3;
  }
  REAL cx = h[0][1] * h[1][2] - h[0][2] * h[1][1], cy = h[0][2] * h[1][0] - h[0][0] * h[1][2],
       cz = h[0][0] * h[1][1] - h[0][1] * h[1][0];
  REAL a = nrm[0] * cx + nrm[1] * cy + nrm[2] * cz;
  double r = (double)(a < 0 ? -a : a);
  if (!isfinite(r))
    return PX_ENONFINITE;
  *area = r;
  return PX_OK;
}
